# The paper's rules (Gagnon et al. 2019) as `fluidtex run` options, for the
# comparison scripts: source this file and pass "${PAPER_RULES[@]}".
# shellcheck disable=SC2034
PAPER_RULES=(--patch-motion vertex --distortion-test vertex --fading density --weight-cutoff 0 --relax-frames 0
  --kill-frames 0 --birth-margin 0 --birth-gap centres --projection-slack 0 --distorted fade --gap-fill seed
  --sink keep)
