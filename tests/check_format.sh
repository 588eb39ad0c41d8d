#!/usr/bin/env bash
# CTest Style.ClangFormat: every C++ source and header of the project is
# formatted as .clang-format says (clang-format 14, Debian 12's, which
# scripts/setup.sh installs). Names the files that are not, and the
# command that formats them. Exit 77 (skipped) where clang-format is missing.
#   tests/check_format.sh SOURCE_DIR
set -euo pipefail
cd "${1:?usage: $0 SOURCE_DIR}"
command -v clang-format >/dev/null || { echo "SKIPPED: clang-format not found"; exit 77; }
mapfile -t files < <(find apps bench include src tests -name '*.cpp' -o -name '*.h' | sort)
((${#files[@]} > 100)) || { echo "FAIL: only ${#files[@]} sources found"; exit 1; }
if ! out=$(clang-format --dry-run --Werror "${files[@]}" 2>&1); then
  mapfile -t bad < <(grep -oE '^[^:]+\.(cpp|h):[0-9]+:[0-9]+: (error|warning)' <<<"$out" | cut -d: -f1 | sort -u)
  ((${#bad[@]})) || { echo "FAIL: clang-format: $out" | head -5; exit 1; }
  echo "FAIL: ${#bad[@]} files are not clang-formatted: ${bad[*]}"
  echo "format them with: clang-format -i ${bad[*]}"
  exit 1
fi
echo "${#files[@]} files clang-formatted"
