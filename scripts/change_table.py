#!/usr/bin/env python3
"""Where patches are, by where the surface is made and destroyed, from runs'
stats.jsonl (run or --track-only; the change_* counters).

Usage: change_table.py RUN_DIR [RUN_DIR ...]
Per run and class of surface change (sink_fast < -5 %/frame, sink, kept,
source, source_fast > +5 %/frame): the patches per area there over the
first frame's patches per area (median and max over the second half of
the run), the share of the surface there (mean), and the births and
removals there (totals).
"""
import statistics
import sys
from pathlib import Path

from summarize_stats import load  # stats.jsonl of a run, one dict per frame

CLASSES = ["sink_fast", "sink", "kept", "source", "source_fast"]


def main(runs):
    print("| run | class | surface share | patches per area vs frame 1 (median / max, second half) | births | removals |")
    print("|---|---|---|---|---|---|")
    for run in runs:
        rows = load(run)
        first = sum(rows[0]["patches"].values()) / rows[0]["surface_area"]
        measured = [r for r in rows if "change_area_kept" in r]
        late = measured[len(measured) // 2:]
        for c in CLASSES:
            dens = [r["change_patches_" + c] / r["change_area_" + c] / first for r in late if r["change_area_" + c] > 0]
            share = statistics.mean(r["change_area_" + c] / r["surface_area"] for r in measured)
            births = sum(r["change_births_" + c] for r in measured)
            removals = sum(r["change_removals_" + c] for r in measured)
            d = f"{statistics.median(dens):.2f} / {max(dens):.2f}" if dens else "—"
            print(f"| {Path(run).name} | {c} | {share:.2f} | {d} | {births} | {removals} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
