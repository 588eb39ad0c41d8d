#!/usr/bin/env bash
# Static checks of the library and the CLI: clang-tidy with .clang-tidy's
# checks over every source file (and the headers they include), among them
# readability-function-size: no function over 60 lines.
#
# Usage: scripts/check_tidy.sh [BUILD_DIR]   (default: build; configured with
# CMake, which writes BUILD_DIR/compile_commands.json)
#
# Prints each warning once and exits 1 when there is any. The functions in
# LONG_FUNCTIONS below are still over 60 lines; each is reported as long
# until it is split, and the list may only shrink: a function that is no
# longer over the limit must leave it (exit 1 otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
LONG_FUNCTIONS=(
)
if [[ ! -f "$build/compile_commands.json" ]]; then
  echo "check_tidy: $build/compile_commands.json missing: configure the build with CMake first" >&2
  exit 2
fi
mapfile -t sources < <(git ls-files 'src/*.cpp' 'apps/*.cpp')
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
run-clang-tidy -p "$build" -quiet -j "$(nproc)" "${sources[@]/#/$PWD/}" >"$log" 2>&1 || status=$?
# Warnings and errors, once each (a header's are reported by every file
# that includes it), without colours and with paths from the repository root.
mapfile -t found < <(sed 's/\x1b\[[0-9;]*m//g' "$log" | grep -E '^/[^ ]+:[0-9]+:[0-9]+: (warning|error): ' |
  sed "s|^$PWD/||" | sort -u)
bad=0
long_seen=()
for line in "${found[@]}"; do
  if [[ $line =~ function\ \'([^\']+)\'\ exceeds ]]; then
    name="${line%%:*}:${BASH_REMATCH[1]}"
    if printf '%s\n' "${LONG_FUNCTIONS[@]}" | grep -qxF "$name"; then
      long_seen+=("$name")
      continue
    fi
  fi
  echo "$line"
  bad=1
done
for name in "${LONG_FUNCTIONS[@]}"; do
  if ! printf '%s\n' "${long_seen[@]}" | grep -qxF "$name"; then
    echo "check_tidy: $name is no longer over 60 lines: remove it from LONG_FUNCTIONS in $0"
    bad=1
  fi
done
if [[ $status -ne 0 && $bad -eq 0 ]]; then
  echo "check_tidy: run-clang-tidy failed (exit $status):" >&2
  tail -20 "$log" >&2
  exit 1
fi
echo "check_tidy: ${#sources[@]} files checked, ${#long_seen[@]} functions still over 60 lines (LONG_FUNCTIONS)"
exit $bad
