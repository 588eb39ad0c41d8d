#!/usr/bin/env bash
# How much the texture looks like its exemplar: frame 1 of the generated
# rotation disk (`fluidtex gen rotation`), textured with each exemplar by the
# flow map (the exemplar tiled, the reference) and by patch variants, each
# run measured with `fluidtex eval`; prints the Markdown table of
# docs/look.md and writes a gallery (exemplar, flow map, each variant) per
# exemplar to OUTDIR/gallery/.
#   scripts/look_compare.sh OUTDIR EXEMPLAR...
#   ATLAS=1024 (atlas size)  FRAMES=1 (frames of the disk textured; the last is measured)
#   VARIANTS="paper contrast histogram histogram-s3 defaults" (see options_of)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/look_compare.sh OUTDIR EXEMPLAR...}
shift
atlas=${ATLAS:-1024}
frames=${FRAMES:-1}
bin=${FLUIDTEX:-build/fluidtex}
mkdir -p "$out/gallery"
[[ -f "$out/scene/rotation.0001.ply" ]] || "$bin" gen rotation --frames "$frames" -o "$out/scene" >/dev/null

# A variant's options over the defaults: flowmap; paper (random orientation,
# Eq. 7); BLEND[-sP] (oriented patches, --blend BLEND, --blend-sharpness P,
# 1 without -s); defaults.
options_of() {
  case $1 in
    flowmap) echo "--method flowmap" ;;
    paper) echo "--orientation random --blend contrast --blend-sharpness 1" ;;
    defaults) echo "" ;;
    *-s*) echo "--orientation field --blend ${1%-s*} --blend-sharpness ${1##*-s}" ;;
    *) echo "--orientation field --blend $1 --blend-sharpness 1" ;;
  esac
}
variants=(flowmap ${VARIANTS:-paper contrast histogram histogram-s3 defaults})

for exemplar in "$@"; do
  name=$(basename "${exemplar%.*}")
  views=()
  for v in "${variants[@]}"; do
    run="$out/$name-$v"
    if [[ ! -f "$run/eval/summary.json" ]]; then
      # shellcheck disable=SC2086
      "$bin" run -q -i "$out/scene/rotation.####.ply" -e "$exemplar" -o "$run" --frames "1-$frames" \
        --atlas-size "$atlas" --force $(options_of "$v")
      "$bin" eval -q -o "$run" --frames "$frames" --flow-width 0 --images 0
    fi
    "$bin" preview "$run" --frames "$frames" --width 512 >/dev/null
    views+=("$run/preview/frame.$(printf %04d "$frames").png")
  done
  oiiotool "${views[@]}" --mosaic "${#views[@]}x1" -o "$out/gallery/$name.png"
done
python3 scripts/look_tables.py "$out" "${variants[@]}"
