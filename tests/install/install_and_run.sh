#!/usr/bin/env bash
# CTest Install.PrefixRunsTheExample: `cmake --install BUILD --prefix TMP`
# installs the executable, fluidtex(1), the scripts, the example and the
# docs; the installed executable runs the installed example; the manual page
# names every option of every subcommand that --help lists (it is written
# from the same tables), and man renders it without a warning.
#   tests/install/install_and_run.sh BUILD_DIR
set -euo pipefail
build=$(realpath "${1:?usage: $0 BUILD_DIR}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
fail() { echo "FAIL: $*" >&2; exit 1; }
for f in bin/fluidtex share/man/man1/fluidtex.1 share/doc/fluidtex/README.md share/doc/fluidtex/LICENSE \
  share/doc/fluidtex/docs/farm.md share/fluidtex/scripts/slurm/submit.sh share/fluidtex/scripts/slurm/synth.sbatch \
  share/fluidtex/scripts/blender/load_fluidtex.py share/fluidtex/examples/gravel.png \
  share/fluidtex/examples/split/split.0001.ply; do
  [[ -f $prefix/$f ]] || fail "$f was not installed"
done
[[ -x $prefix/share/fluidtex/scripts/slurm/submit.sh ]] || fail "submit.sh lost its execute bit"

exe=$prefix/bin/fluidtex
example=$prefix/share/fluidtex/examples
"$exe" run -q -i "$example/split/split.####.ply" -e "$example/gravel.png" -o "$tmp/out" --frames 1-2 --atlas-size 256
for f in atlas.0001.exr atlas.0002.exr mesh.0002.obj state/patches.0002.bin job.toml; do
  [[ -f $tmp/out/$f ]] || fail "the installed fluidtex wrote no $f"
done

page=$prefix/share/man/man1/fluidtex.1
for sub in run synth eval compare preview info gen; do
  grep -qF ".SS \"fluidtex $sub\"" "$page" || fail "fluidtex.1 has no section for $sub"
  options=$("$exe" "$sub" --help | grep -oE '^ +(-[a-zA-Z], )?--[a-z0-9-]+' | grep -oE -- '--[a-z0-9-]+')
  [[ -n $options ]] || fail "fluidtex $sub --help lists no options"
  for option in $options; do
    grep -qF "\\fB${option//-/\\-}\\fR" "$page" || fail "fluidtex.1 does not name $sub's $option"
  done
done
if command -v man >/dev/null; then
  warnings=$(MANWIDTH=80 man --warnings -l "$page" 2>&1 >/dev/null || true)
  [[ -z $warnings ]] || fail "man warns about fluidtex.1: $warnings"
fi
echo "installed into a prefix: the example runs, fluidtex(1) names every option"
