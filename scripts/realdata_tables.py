#!/usr/bin/env python3
"""Table of scripts/realdata_compare.sh: one row per run in OUTDIR.

Warping ratio: per frame pair, eval's warp_advected / warp_fixed (the colour
change along the flow over the change in place: 0 moves with the liquid, 1
changes as much along the flow as in place); mean and 95th percentile over
the frame pairs. Flow error (pixels < 15 px): Farneback endpoint error over
the pixels whose projected motion is under 15 px per frame (eval's
flow_slow_ means; the flow is unreliable beyond), summed over the frame
pairs, over their projected speed summed (frames where the liquid barely
moves would make a per-frame ratio meaningless). Flow error (pairs < 15 px):
the same over every pixel of the frame pairs whose mean projected speed is
under 15 px (the measure before eval had the per-pixel limit). Synthesis s:
median seconds of the synthesis stage per frame (stats.jsonl).
"""
import json
import statistics
import sys
from pathlib import Path


def lines(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def pct(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))] if values else float("nan")


def main(out):
    print("| run | frames | births / live | active share (f > 24) | warping ratio mean | p95 | flow error (pixels < 15 px) | "
          "flow error (pairs < 15 px) | uncovered area max | ghosting mean | p95 | σ ratio G | spectrum | D_T p95 | synthesis s | s / frame |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for run in sorted(p for p in Path(out).iterdir() if (p / "eval" / "metrics.jsonl").exists()):
        m = lines(run / "eval" / "metrics.jsonl")
        stats = lines(run / "stats.jsonl")
        ratio = [r["warp_advected"] / r["warp_fixed"] for r in m if r.get("warp_fixed")]
        slow = [r for r in m if r.get("flow_speed_px") and r["flow_speed_px"] < 15 and r.get("flow_endpoint_px") is not None]
        flow = sum(r["flow_endpoint_px"] for r in slow) / sum(r["flow_speed_px"] for r in slow) if slow else float("nan")
        px = [r for r in m if r.get("flow_slow_speed_px") is not None and r.get("flow_slow_endpoint_px") is not None]
        px_speed = sum(r["flow_slow_speed_px"] for r in px)
        flow_px = sum(r["flow_slow_endpoint_px"] for r in px) / px_speed if px_speed > 0 else float("nan")
        live = [sum(s["patches"].values()) for s in stats]
        births = [s.get("patches_created", 0) / (s["frame"] - q["frame"]) / n  # per frame (a stepped run: 1-72x2)
                  for q, s, n in zip(stats, stats[1:], live[1:]) if n]
        late = [s["patches"]["active"] / n for s, n in zip(stats, live) if n and s["frame"] - stats[0]["frame"] >= 24]
        def mean(key):
            v = [r[key] for r in m if r.get(key) is not None]
            return statistics.mean(v) if v else float("nan")
        unc = [r["uncovered_area"] for r in m if r.get("uncovered_area") is not None]
        synth = [s["seconds"]["synthesis"] for s in stats if "synthesis" in s.get("seconds", {})]
        t = (run.parent / (run.name + ".time"))
        secs = float(t.read_text().split()[-1]) / len(stats) if t.exists() else float("nan")
        f = lambda x: f"{x:.3f}" if x == x else "—"
        print(f"| {run.name} | {len(stats)} | {f(statistics.mean(births)) if births else '—'} | "
              f"{f(statistics.mean(late)) if late else '—'} | {f(statistics.mean(ratio))} | {f(pct(ratio, 0.95))} | "
              f"{f(flow_px)} | {f(flow)} | {f'{max(unc):.1e}' if unc else '—'} | {f(mean('ghosting_mean'))} | "
              f"{f(mean('ghosting_p95'))} | {f(mean('contrast_g'))} | {f(mean('spectrum_distance'))} | "
              f"{f(mean('distortion_p95'))} | {f(statistics.median(synth)) if synth else '—'} | {secs:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/realdata")
