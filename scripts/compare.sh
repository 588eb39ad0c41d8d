#!/usr/bin/env bash
# The paper's comparisons, reproduced with fluidtex itself (docs/results.md):
#   - density-based vs linear fading (Fig. 7): patch count, ghosting;
#   - ellipsoid+plane vs sphere criterion where two surfaces come close
#     (Figs. 3, 5): coverage (with and without the coverage-aware Poisson test);
#   - contrast-preserving vs linear blending: contrast, spectrum;
#   - texture-flow agreement on rotation and split (Figs. 8, 9, 15);
#   - the patch method vs two-phase advected UVs (`--method flowmap`) and vs
#     the paper's per-vertex rules, on every scene;
# and evaluates the default run of every generated scene.
# Every run is evaluated with `fluidtex eval`; the tables are printed as
# Markdown. Usage: scripts/compare.sh [OUTDIR]   (FRAMES=40 by default;
# FLUIDTEX=PATH runs another build than build/fluidtex)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/paper_rules.sh
out=${1:-out/compare}
frames=${FRAMES:-40}
bin=${FLUIDTEX:-build/fluidtex}  # FLUIDTEX=PATH: another build
mkdir -p "$out"

gen() {  # scene resolution
  [[ -f "$out/$1/$1.0001.ply" ]] || "$bin" gen "$1" -o "$out/$1" --frames "$frames" --resolution "$2" \
    --exemplar gravel --exemplar-pixels 256 >/dev/null
}
run() {  # name scene [run options...]
  local name=$1 scene=$2
  shift 2
  if [[ ! -f "$out/$name/eval/summary.json" ]]; then
    /usr/bin/time -f "%e" -o "$out/$name.time" "$bin" run -q -i "$out/$scene/$scene.####.ply" \
      -e "$out/$scene/gravel.png" -o "$out/$name" --atlas-size 1024 "$@"
    "$bin" eval -q -i "$out/$scene/$scene.####.ply" -o "$out/$name"
  fi
}

gen rotation 48
gen split 64
gen drop 48
gen merge 64

run rotation-patches rotation
run split-patches split
run drop-patches drop
run merge-patches merge
run split-linear-fading split --fading linear
run drop-linear-fading drop --fading linear
run drop-sphere drop --criterion sphere
run drop-plain drop --no-coverage-check
run drop-sphere-plain drop --criterion sphere --no-coverage-check
run split-linear-blend split --blend linear
run rotation-flowmap rotation --method flowmap
run split-flowmap split --method flowmap
run drop-flowmap drop --method flowmap
run merge-flowmap merge --method flowmap
for scene in rotation split drop merge; do
  run "$scene-paper" "$scene" "${PAPER_RULES[@]}"
done

python3 scripts/compare_tables.py "$out"
# Patches (defaults), the paper's rules and the flow map side by side.
python3 scripts/realdata_tables.py "$out"
