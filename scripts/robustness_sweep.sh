#!/usr/bin/env bash
# Robustness sweep: every shared real cache (../shared/realdata, when present)
# and every generated scene, × seeds × disk radius (a factor of the default,
# 0.05 × the first frame's bounding-box diagonal) × rules (the defaults and the
# paper's, scripts/paper_rules.sh), tracking only. Prints the churn table
# (scripts/churn.py): births per live patch, active share, patches per area
# against the first frame, uncovered area. A constant that holds at one scale
# or seed only shows as a row out of line with its neighbours.
#   scripts/robustness_sweep.sh [OUTDIR]
#   SEEDS="1 2 3 4"  RADII="0.7 1 1.5"  RULES="default paper"
#   SCENES="drop slosh obstacle river rotation split merge gen-drop pour stream stream-rock"
#   FRAMES=N (generated scenes' length, 120)  FLUIDTEX=PATH (another build)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/paper_rules.sh
out=${1:-out/sweep}
bin=${FLUIDTEX:-build/fluidtex}
data=${REALDATA:-../shared/realdata}
frames=${FRAMES:-120}
mkdir -p "$out"

# Bounding-box diagonal of a PLY's vertices (ASCII or binary little-endian,
# x y z the first three float properties).
diagonal() {
  python3 - "$1" <<'PY'
import struct, sys
with open(sys.argv[1], "rb") as f:
    header, count, props = [], 0, 0
    while (line := f.readline().decode().strip()) != "end_header":
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count, in_vertex = int(words[2]), True
        elif words[0] == "element":
            in_vertex = False
        elif words[0] == "property" and in_vertex:
            props += 1
        header.append(words)
    binary = ["format", "binary_little_endian", "1.0"] in header
    if binary:
        data = f.read(4 * props * count)
        points = [v[:3] for v in struct.iter_unpack(f"<{props}f", data)]
    else:
        points = [tuple(map(float, f.readline().split()[:3])) for _ in range(count)]
lo = [min(p[k] for p in points) for k in range(3)]
hi = [max(p[k] for p in points) for k in range(3)]
print(sum((h - l) ** 2 for l, h in zip(lo, hi)) ** 0.5)
PY
}

runs=()
for scene in ${SCENES:-drop slosh obstacle river rotation split merge gen-drop pour stream stream-rock}; do
  if [[ -d "$data/blender-$scene" ]]; then
    pattern="$data/blender-$scene/$scene.####.ply"
    first="$data/blender-$scene/$scene.0001.ply"
  else
    name=${scene#gen-}
    case $name in rotation|split|merge|drop|pour|stream|stream-rock) ;; *) continue ;; esac
    [[ -f "$out/scenes/$scene/$name.0001.ply" ]] ||
      "$bin" gen "$name" -o "$out/scenes/$scene" --frames "$frames" >/dev/null
    pattern="$out/scenes/$scene/$name.####.ply"
    first="$out/scenes/$scene/$name.0001.ply"
  fi
  diag=$(diagonal "$first")
  for rules in ${RULES:-default paper}; do
    rule_options=()
    [[ $rules == paper ]] && rule_options=("${PAPER_RULES[@]}")
    for factor in ${RADII:-0.7 1 1.5}; do
      radius=$(python3 -c "print(f'{0.05 * $factor * $diag:.6g}')")
      for seed in ${SEEDS:-1 2 3 4}; do
        run="$out/$scene-$rules-r$factor-s$seed"
        [[ -f "$run/stats.jsonl" ]] ||
          "$bin" run -q --track-only --force -i "$pattern" -o "$run" --seed "$seed" --radius "$radius" \
            "${rule_options[@]}"
        runs+=("$run")
      done
    done
  done
done
python3 scripts/churn.py "${runs[@]}"
