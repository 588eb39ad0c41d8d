#!/usr/bin/env python3
"""Longest free and member function definitions of the library and CLI.

Usage: scripts/function_lengths.py [N]   (from the repository root; N rows, default 12)

A definition starts at a line in column 0 that opens a function ("...) {", or a
signature continued over several lines) and ends at the next line that is just
"}" (the house format, .clang-format, puts it there). Lambdas are counted with
the function they live in. Prints "lines  file  signature" and a summary line.
"""
import glob
import re
import statistics
import sys


def definitions(path):
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        starts = re.match(r"^[A-Za-z].*\)\s*(const)?\s*(noexcept)?\s*\{\s*$", line) or re.match(
            r"^[A-Za-z][^;]*\($|^[A-Za-z][^;]*,$", line)
        if starts and not re.match(r"^(namespace|struct|class|enum|union)", line):
            j = i
            while j < len(lines) and not lines[j].rstrip().endswith("{"):
                if lines[j].rstrip().endswith(";"):
                    break
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{"):
                k = j + 1
                while k < len(lines) and lines[k] != "}":
                    k += 1
                yield k - i + 1, line.strip()[:80]
                i = k
        i += 1


def main():
    rows = []
    for path in sorted(glob.glob("src/**/*.cpp", recursive=True) + glob.glob("apps/**/*.cpp", recursive=True)):
        rows += [(n, path, sig) for n, sig in definitions(path)]
    rows.sort(key=lambda r: (-r[0], r[1]))
    for n, path, sig in rows[: int(sys.argv[1]) if len(sys.argv) > 1 else 12]:
        print(f"{n:4d}  {path}  {sig}")
    lengths = [r[0] for r in rows]
    print(f"functions {len(rows)}, median {statistics.median(lengths)} lines, over 80 lines: "
          f"{sum(1 for n in lengths if n > 80)}")


if __name__ == "__main__":
    main()
