#!/usr/bin/env bash
# Checks that scripts/setup.sh installs every Debian package the build used,
# so that README's first command works on a fresh Debian 12 machine even when
# this machine happens to have a package that setup.sh forgot.
#
# After a build in BUILD_DIR (Ninja, as setup.sh makes it), it collects every
# file the configure and build steps took from the system:
#   - the CMake files configure loaded (build.ninja's regeneration inputs),
#     and every file those under /usr reference (${_IMPORT_PREFIX} = /usr);
#   - the headers in the build's dependency records (ninja -t deps);
#   - the libraries on the link lines (absolute paths and -l names);
#   - the tools: compilers, archiver, linker, ninja and cmake;
# maps each to the Debian package that owns it (dpkg -S) and fails, naming
# the package and one file of it, when a package is neither in setup.sh's
# list nor installed through one of them (their Depends/Pre-Depends closure,
# followed through Provides) nor part of the base system (Priority: required
# and Essential packages, which every Debian installation has).
#
#   scripts/check_packages.sh [BUILD_DIR]           (default: build)
#   PACKAGES="a b c" scripts/check_packages.sh      check another package list
#
# Exit status: 0 all covered, 1 a package is missing, 2 cannot check (no
# build, no dpkg).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
start=$SECONDS

die() { echo "check_packages: $*" >&2; exit 2; }
command -v dpkg-query >/dev/null || die "dpkg-query not found (the check needs Debian's package database)"
[[ -f $build/build.ninja && -f $build/CMakeCache.txt ]] || die "$build/build.ninja not found: build first (scripts/setup.sh)"
ninja=$(sed -n 's/^CMAKE_MAKE_PROGRAM:[A-Z]*=//p' "$build/CMakeCache.txt")
[[ -x $ninja ]] || die "the build's make program '$ninja' is not executable"

listed=${PACKAGES:-$(scripts/setup.sh --list)}
[[ -n ${listed//[[:space:]]/} ]] || die "empty package list"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
files=$tmp/files

# 1. CMake files that configure loaded: the inputs of build.ninja's
# regeneration rule (everything CMake read while configuring).
cmake_inputs=$(awk '/^build build\.ninja/ {on = 1} on {print} on && !/\$$/ {exit}' "$build/build.ninja" |
  tr ' ' '\n' | grep '^/' | grep -v "^$PWD/" || true)
printf '%s\n' "$cmake_inputs" >>"$files"
# ... and every file that the ones under /usr name (imported targets'
# locations, include folders' files are covered by the headers below).
for f in $(grep '^/usr/' <<<"$cmake_inputs" | grep '\.cmake$'); do
  sed 's#${_IMPORT_PREFIX}#/usr#g; s#${PACKAGE_PREFIX_DIR}#/usr#g' "$f" |
    grep -oE '"/usr/[^"$;]*"' | tr -d '"' || true
done | sort -u | while read -r f; do if [[ -f $f ]]; then echo "$f"; fi; done >>"$files"

# 2. Headers from the compilers' dependency records.
"$ninja" -C "$build" -t deps | grep -E '^ +/' | sed 's/^ *//' | sort -u >>"$files"

# 3. Libraries on the link lines: absolute paths, and -lNAME resolved in the
# linker's default folders.
libs=$(grep -E '^ +LINK_LIBRARIES = ' "$build/build.ninja" | sed 's/^ *LINK_LIBRARIES = //' | tr ' ' '\n' | sort -u)
grep '^/' <<<"$libs" >>"$files" || true
for l in $(grep -oE '^-l[^ ]+' <<<"$libs" | cut -c3- | sort -u); do
  for d in /usr/lib/x86_64-linux-gnu /usr/lib /lib/x86_64-linux-gnu /lib; do
    if [[ -e $d/lib$l.so ]]; then echo "$d/lib$l.so"; break; fi
    if [[ -e $d/lib$l.a ]]; then echo "$d/lib$l.a"; break; fi
  done
done >>"$files"

# 4. Tools.
for key in CMAKE_CXX_COMPILER CMAKE_C_COMPILER CMAKE_AR CMAKE_RANLIB CMAKE_LINKER CMAKE_MAKE_PROGRAM CMAKE_COMMAND; do
  sed -n "s/^$key:[A-Z]*=//p" "$build/CMakeCache.txt"
done | grep '^/' >>"$files" || true

# Owners: dpkg -S on the path, and on its real path (symlinks made by
# update-alternatives or merged /usr are owned under the other name).
mapfile -t paths < <(sort -u "$files" | grep -E '^/(usr|lib|bin|sbin|etc|opt)/')
((${#paths[@]})) || die "no system file found in the build's records"
printf '%s\n' "${paths[@]}" >"$tmp/paths"
xargs -d '\n' realpath -m <"$tmp/paths" >"$tmp/real"
paste "$tmp/paths" "$tmp/paths" >"$tmp/asked"
paste "$tmp/real" "$tmp/paths" | awk -F '\t' '$1 != $2' >>"$tmp/asked"
# dpkg -S prints "pkg[:arch][, pkg...]: path" for every owned path given;
# feed it in batches and keep "path -> packages".
cut -f1 "$tmp/asked" | sort -u | xargs -d '\n' dpkg -S 2>/dev/null |
  grep -v '^diversion ' | sed -E 's/^(.*): (\/.*)$/\2\t\1/' >"$tmp/owned" || true

# Installed-package graph: name, Depends + Pre-Depends, Provides, base system.
dpkg-query -W -f='${db:Status-Abbrev}\t${Package}\t${Pre-Depends}, ${Depends}\t${Provides}\t${Priority}\t${Essential}\n' >"$tmp/graph"

report=$(
  awk -F '\t' -v listed="$listed" -v graph="$tmp/graph" -v owned="$tmp/owned" '
    function strip(s) { sub(/:[a-z0-9]+$/, "", s); sub(/ *\(.*$/, "", s); gsub(/^ +| +$/, "", s); return s }
    FILENAME == graph {  # the installed-package graph
      if ($1 !~ /^ii/) next
      pkg = $2; installed[pkg] = 1
      deps[pkg] = $3
      n = split($4, pr, ","); for (i = 1; i <= n; i++) { v = strip(pr[i]); if (v != "") provider[v] = provider[v] " " pkg }
      if ($5 == "required" || $6 == "yes") base[pkg] = 1
      next
    }
    FILENAME == owned { owners[$1] = owners[$1] "," $2; next }  # path -> "pkg, pkg"
    { asked[$1] = asked[$1] " " $2 }                            # queried path -> path the build used
    END {
      # Closure of the listed packages and of the base system.
      n = split(listed, l, /[ \t\n]+/)
      for (i = 1; i <= n; i++) if (l[i] != "") { want[l[i]] = 1; queue[++q] = l[i]; reached[l[i]] = 1 }
      for (p in base) if (!(p in reached)) { queue[++q] = p; reached[p] = 1 }
      for (h = 1; h <= q; h++) {
        m = split(deps[queue[h]], d, ",")
        for (i = 1; i <= m; i++) {
          k = split(d[i], alt, "|")
          for (j = 1; j <= k; j++) {
            a = strip(alt[j]); if (a == "") continue
            # A dependency is met by the package itself or by what provides it;
            # follow every installed candidate.
            cand = (a in installed ? a : "") " " provider[a]
            c = split(cand, cs, " ")
            for (x = 1; x <= c; x++) if (cs[x] != "" && !(cs[x] in reached)) { reached[cs[x]] = 1; queue[++q] = cs[x] }
          }
        }
      }
      for (p in want) if (!(p in installed)) print "unknown\t" p
      # Every used file must belong to a reached package.
      for (path in asked) {
        if (!(path in owners)) continue
        m = split(owners[path], o, ",")
        for (i = 1; i <= m; i++) {
          pk = strip(o[i]); if (pk == "") continue
          if (!(pk in reached) && !(pk in shown)) { shown[pk] = 1; split(asked[path], orig, " "); print "missing\t" pk "\t" orig[1] }
        }
      }
    }
  ' "$tmp/graph" "$tmp/owned" "$tmp/asked" | sort
)

checked=${#paths[@]}
if grep -q '^unknown' <<<"$report"; then
  grep '^unknown' <<<"$report" | while IFS=$'\t' read -r _ p; do
    echo "check_packages: setup.sh lists '$p', which is not installed here: run scripts/setup.sh first" >&2
  done
  exit 2
fi
if grep -q '^missing' <<<"$report"; then
  grep '^missing' <<<"$report" | while IFS=$'\t' read -r _ p f; do
    echo "check_packages: scripts/setup.sh does not install $p, which the build uses ($f)" >&2
  done
  exit 1
fi
echo "check_packages: the $checked system files the build used all come from packages scripts/setup.sh installs ($((SECONDS - start)) s)"
