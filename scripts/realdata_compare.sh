#!/usr/bin/env bash
# Patches (defaults), the defaults without plastic relaxation (elastic), the
# paper's per-vertex rules, the flow-map baseline and pure advection (one uv
# set carried by the solver's velocities from the first frame, never reset:
# the flow map with a period far beyond any cache) on
# the real Mantaflow caches in ../shared/realdata (when present), each run
# evaluated with `fluidtex eval`; prints the Markdown table of
# docs/results.md ("Real simulation caches").
#   scripts/realdata_compare.sh [OUTDIR]
#   ATLAS=2048 (atlas size)  SCENES="slosh drop obstacle"  FRAMES_slosh=1-48 ...
#   VARIANTS="patches flowmap" (default: all five)
#   RUN_OPTIONS="--skipped-frames ignore" (added to every run)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/realdata}
data=${REALDATA:-../shared/realdata}
atlas=${ATLAS:-2048}
bin=${FLUIDTEX:-build/fluidtex}
exemplar=data/gravel.png
mkdir -p "$out"
[[ -d $data ]] || { echo "no real data at $data" >&2; exit 2; }

variants=" ${VARIANTS:-patches elastic paper flowmap advect} "
read -r -a run_options <<<"${RUN_OPTIONS:-}"
run() {  # name scene [run options...]
  local name=$1 scene=$2
  shift 2
  [[ $variants == *" ${name#"$scene"-} "* ]] || return 0
  local pattern="$data/blender-$scene/$scene.####.ply"
  local frames_var="FRAMES_$scene" frames=()
  [[ -n ${!frames_var:-} ]] && frames=(--frames "${!frames_var}")
  if [[ ! -f "$out/$name/eval/summary.json" ]]; then
    /usr/bin/time -f "%e" -o "$out/$name.time" "$bin" run -q -i "$pattern" -e "$exemplar" -o "$out/$name" \
      --atlas-size "$atlas" "${frames[@]}" "$@" "${run_options[@]}"
    "$bin" eval -q -i "$pattern" "${frames[@]}" -o "$out/$name"
  fi
}

for scene in ${SCENES:-slosh drop obstacle}; do
  [[ -d "$data/blender-$scene" ]] || continue
  run "$scene-patches" "$scene"
  run "$scene-elastic" "$scene" --relax-frames 0
  run "$scene-paper" "$scene" --patch-motion vertex --distortion-test vertex --fading density --weight-cutoff 0 \
    --relax-frames 0 --kill-frames 0 --birth-margin 0 --birth-gap centres --projection-slack 0 --distorted fade
  run "$scene-flowmap" "$scene" --method flowmap
  run "$scene-advect" "$scene" --method flowmap --flowmap-period 100000
done
python3 scripts/realdata_tables.py "$out"
