#!/usr/bin/env python3
"""Summarise fluidtex stats.jsonl files: patch counts, coverage, churn, time.

Usage: summarize_stats.py RUN_DIR [RUN_DIR ...]   (each holds stats.jsonl)
Prints a Markdown table, one row per run, and the patch-count curve sampled
every 20 frames.
"""
import json
import statistics
import sys
from pathlib import Path


def load(run):
    with open(Path(run) / "stats.jsonl") as f:
        return [json.loads(line) for line in f if line.strip()]


def main(runs):
    print("| run | frames | faces (mean) | patches mean / max / last | fading in / active / out (mean) | "
          "created per frame | uncovered mean / max | s per frame |")
    print("|---|---|---|---|---|---|---|---|")
    curves = {}
    for run in runs:
        rows = load(run)
        total = [sum(r["patches"].values()) for r in rows]
        fin = statistics.mean(r["patches"]["fading_in"] for r in rows)
        act = statistics.mean(r["patches"]["active"] for r in rows)
        out = statistics.mean(r["patches"]["fading_out_distorted"] + r["patches"]["fading_out_close"] for r in rows)
        created = statistics.mean(r.get("patches_created", 0) for r in rows[1:]) if len(rows) > 1 else 0
        unc = [r["uncovered_fraction"] for r in rows]
        secs = statistics.mean(sum(r["seconds"].values()) for r in rows)
        faces = statistics.mean(r["faces"] for r in rows)
        name = Path(run).name
        curves[name] = total
        print(f"| {name} | {len(rows)} | {faces:.0f} | {statistics.mean(total):.0f} / {max(total)} / {total[-1]} | "
              f"{fin:.0f} / {act:.0f} / {out:.0f} | {created:.1f} | {statistics.mean(unc):.2e} / {max(unc):.2e} | "
              f"{secs:.3f} |")
    print()
    step = 20
    n = max(len(c) for c in curves.values())
    print("| run | " + " | ".join(f"f{k + 1}" for k in range(0, n, step)) + " |")
    print("|---|" + "---|" * len(range(0, n, step)))
    for name, c in curves.items():
        print(f"| {name} | " + " | ".join(str(c[k]) if k < len(c) else "" for k in range(0, n, step)) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
