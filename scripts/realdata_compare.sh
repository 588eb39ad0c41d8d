#!/usr/bin/env bash
# Patches (defaults), the defaults without plastic relaxation (elastic), the
# paper's per-vertex rules, the flow-map baseline and pure advection (one uv
# set carried by the solver's velocities from the first frame, never reset:
# the flow map with a period far beyond any cache) on
# the real Mantaflow caches in ../shared/realdata (when present) and on
# generated scenes named in SCENES (`fluidtex gen`, GEN_FRAMES frames, 72),
# each run evaluated with `fluidtex eval`; prints the Markdown table of
# docs/results.md ("Real simulation caches").
#   scripts/realdata_compare.sh [OUTDIR]
#   ATLAS=2048 (atlas size)  SCENES="slosh drop obstacle river pour"  FRAMES_slosh=1-48 ...
#   VARIANTS="patches flowmap" (default: all five)
#   RUN_OPTIONS="--skipped-frames ignore" (added to every run)
#   BEFORE=PATH (another build's fluidtex: its defaults as the rows *-before)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/paper_rules.sh
out=${1:-out/realdata}
data=${REALDATA:-../shared/realdata}
atlas=${ATLAS:-2048}
bin=${FLUIDTEX:-build/fluidtex}
exemplar=data/gravel.png
mkdir -p "$out"
gen_frames=${GEN_FRAMES:-72}

variants=" ${VARIANTS:-patches elastic paper flowmap advect} before "
read -r -a run_options <<<"${RUN_OPTIONS:-}"
run() {  # name scene [run options...]
  local name=$1 scene=$2 bin=$bin
  shift 2
  [[ $name == *-before ]] && bin=$BEFORE
  [[ $variants == *" ${name#"$scene"-} "* ]] || return 0
  local pattern="$data/blender-$scene/$scene.####.ply"
  [[ -d "$data/blender-$scene" ]] || pattern="$out/scenes/$scene/$scene.####.ply"
  local frames_var="FRAMES_$scene" frames=()
  [[ -n ${!frames_var:-} ]] && frames=(--frames "${!frames_var}")
  if [[ ! -f "$out/$name/eval/summary.json" ]]; then
    /usr/bin/time -f "%e" -o "$out/$name.time" "$bin" run -q -i "$pattern" -e "$exemplar" -o "$out/$name" \
      --atlas-size "$atlas" "${frames[@]}" "$@" "${run_options[@]}"
    "$bin" eval -q -i "$pattern" "${frames[@]}" -o "$out/$name"
  fi
}

for scene in ${SCENES:-slosh drop obstacle river}; do
  if [[ ! -d "$data/blender-$scene" ]]; then
    "$bin" gen --help | grep -Eq "Scene: (.*, )?$scene(,|$)" || {
      echo "skipping $scene: neither $data/blender-$scene nor a generated scene" >&2
      continue
    }
    [[ -f "$out/scenes/$scene/$scene.0001.ply" ]] || "$bin" gen "$scene" --frames "$gen_frames" -o "$out/scenes/$scene" >/dev/null
  fi
  run "$scene-patches" "$scene"
  [[ -n ${BEFORE:-} ]] && run "$scene-before" "$scene"
  run "$scene-elastic" "$scene" --relax-frames 0
  run "$scene-paper" "$scene" "${PAPER_RULES[@]}"
  run "$scene-flowmap" "$scene" --method flowmap
  run "$scene-advect" "$scene" --method flowmap --flowmap-period 100000
done
python3 scripts/realdata_tables.py "$out"
