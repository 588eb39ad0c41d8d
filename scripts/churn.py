#!/usr/bin/env python3
"""Patch churn of fluidtex runs, from their stats.jsonl (run or --track-only).

Usage: churn.py RUN_DIR [RUN_DIR ...]
Per run: births per frame over live patches (mean over frames 2..; a line of a
stepped run (1-72x2) covers the frames since the previous one), the share
of active patches after frame 24, the patch count per unit surface area
relative to the first frame (max), uncovered surface (max), seconds per
frame, and the patches retired by rule (totals) and by age.
"""
import statistics
import sys
from pathlib import Path

from summarize_stats import load  # stats.jsonl of a run, one dict per frame

CAUSES = ["centre_lost", "emptied", "vertices_lost", "split", "flipped", "quality", "too_close", "sunk", "outflow"]
AGES = ["0_1", "2_3", "4_7", "8_15", "16_31", "32_up"]


def main(runs):
    print("| run | frames | births / live | active share (f > 24) | patches first / mean / last | "
          "density vs first (max) | uncovered max | s / frame | retired by rule | retired by age |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for run in runs:
        rows = load(run)
        live = [sum(r["patches"].values()) for r in rows]
        births = [r.get("patches_created", 0) / (r["frame"] - q["frame"]) / max(1, n)
                  for q, r, n in zip(rows, rows[1:], live[1:])]
        late = [r["patches"]["active"] / max(1, n) for r, n in zip(rows, live) if r["frame"] > 24]
        dens = [n / r["surface_area"] for r, n in zip(rows, live) if r.get("surface_area")]
        ratio = max(d / dens[0] for d in dens) if dens else float("nan")
        secs = statistics.mean(sum(r["seconds"].values()) for r in rows)
        causes = {c: sum(r.get("retired_" + c, 0) for r in rows) for c in CAUSES}
        ages = [sum(r.get("retired_age_" + a, 0) for r in rows) for a in AGES]
        unc = max(r["uncovered_fraction"] for r in rows)
        cause_text = ", ".join(f"{c} {n}" for c, n in causes.items() if n)
        print(f"| {Path(run).name} | {len(rows)} | {statistics.mean(births) if births else 0:.3f} | "
              f"{statistics.mean(late) if late else float('nan'):.2f} | {live[0]} / {statistics.mean(live):.0f} / {live[-1]} | "
              f"{ratio:.2f} | {unc:.2e} | {secs:.2f} | {cause_text} | {' / '.join(map(str, ages))} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
