#!/usr/bin/env bash
# Static checks of the library and the CLI: clang-tidy with .clang-tidy's
# checks over every source file (and the headers they include), among them
# readability-function-size: no function over 60 lines.
#
# Usage: scripts/check_tidy.sh [BUILD_DIR]   (default: build; configured with
# CMake, which writes BUILD_DIR/compile_commands.json)
#
# Prints each warning once and exits 1 when there is any (about 7 minutes
# on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
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
if ((${#found[@]})); then
  printf '%s\n' "${found[@]}"
  echo "check_tidy: ${#found[@]} findings in ${#sources[@]} files" >&2
  exit 1
fi
if [[ $status -ne 0 ]]; then
  echo "check_tidy: run-clang-tidy failed (exit $status):" >&2
  tail -20 "$log" >&2
  exit 1
fi
echo "check_tidy: ${#sources[@]} files clean"
