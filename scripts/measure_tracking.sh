#!/usr/bin/env bash
# Tracking measurements for docs/tracking.md: every generated scene at the
# paper's sizes (Table 2), 200 frames, density-based (Eq. 6) vs linear (Eq. 5)
# fading. Tracking only (no atlas); coverage is the share of surface area with
# no patch of positive weight. Usage: scripts/measure_tracking.sh [OUTDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/measure-tracking}
frames=${FRAMES:-200}
bin=build/fluidtex
mkdir -p "$out"
# scene:resolution — about 6k polygons for the 2D scenes, ~50k for the drop.
for spec in rotation:64 split:90 merge:120 drop:100; do
  scene=${spec%%:*}; res=${spec##*:}
  [[ -f "$out/$scene/$scene.0001.ply" ]] || "$bin" gen "$scene" -o "$out/$scene" --frames "$frames" --resolution "$res" >/dev/null
  for fading in density linear; do
    "$bin" run -q --track-only -i "$out/$scene/$scene.####.ply" -o "$out/$scene-$fading" --fading "$fading"
  done
done
python3 scripts/summarize_stats.py "$out"/*-density "$out"/*-linear
