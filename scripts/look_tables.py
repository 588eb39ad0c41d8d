#!/usr/bin/env python3
"""Table of scripts/look_compare.sh: per exemplar and variant, eval's
appearance figures of the measured frame, the flow map's beside them.

coherence: orientation coherence over the flow map's (1 = as directional
as the exemplar tiled); energy: nearest-window energy ratio over the flow
map's (1 = as close to exemplar windows as the exemplar tiled); histogram:
colour histogram distance (exemplar σ) minus the flow map's; spectrum:
eval's spectrum distance; one patch: share of texels one patch carries 90 %
of (stats.jsonl's dominant_fraction).
"""
import json
import sys
from pathlib import Path


def last(path):
    with open(path) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    return rows[-1]


def main(out, variants):
    out = Path(out)
    names = sorted({p.name[: -len("-flowmap")] for p in out.iterdir() if p.name.endswith("-flowmap")})
    print("| exemplar | variant | coherence / flow map | energy / flow map | histogram − flow map | spectrum | one patch |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        ref = out / f"{name}-flowmap"
        if not (ref / "eval" / "metrics.jsonl").exists():
            continue
        r = last(ref / "eval" / "metrics.jsonl")
        for v in variants:
            run = out / f"{name}-{v}"
            if not (run / "eval" / "metrics.jsonl").exists():
                continue
            m = last(run / "eval" / "metrics.jsonl")
            s = last(run / "stats.jsonl")
            coherence = m["orientation_coherence"] / r["orientation_coherence"]
            energy = m["window_energy_ratio"] / r["window_energy_ratio"]
            histogram = m["histogram_distance"] - r["histogram_distance"]
            one = s.get("dominant_fraction", float("nan"))
            print(f"| {name} | {v} | {coherence:.2f} | {energy:.2f} | {histogram:+.3f} | "
                  f"{m['spectrum_distance']:.2f} | {one:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
