#!/usr/bin/env bash
# Installs fluidtex's build dependencies (Debian 12 packages only) and builds
# it in Release into ./build. Safe to run again: apt skips what is installed
# and the build is incremental.
#   scripts/setup.sh            install + build
#   SKIP_APT=1 scripts/setup.sh build only
#   scripts/setup.sh --list     print the package list (one per line) and stop
set -euo pipefail
cd "$(dirname "$0")/.."

# The GDAL and Xerces-C runtime libraries (second to last line) come with
# libopencv-dev's dependencies (OpenCV's image codecs link GDAL, GDAL links
# Xerces-C); they are listed so that the list names every library the
# build's link closure reaches. clang-format is the tests' (Style.ClangFormat),
# clang-tidy CI's (scripts/check_tidy.sh).
# perl-base (Essential) and libegl-mesa0 (libegl1's dependency) come with
# the others; they are named because the build's CMake packages reference
# their files.
PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopenmesh-dev libcgal-dev libeigen3-dev libnanoflann-dev libtbb-dev libcli11-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libopencv-dev libopencv-video-dev
  libopenvdb-dev libboost-iostreams-dev libblosc-dev
  libgdal32 libxerces-c3.2
  libgtest-dev libgmock-dev
  clang-format clang-tidy
  perl-base libegl-mesa0
)

if [[ "${1:-}" == --list ]]; then
  printf '%s\n' "${PACKAGES[@]}"
  exit 0
fi

if [[ "${SKIP_APT:-0}" != 1 ]]; then
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    SUDO=""
    [[ $(id -u) -ne 0 ]] && SUDO="sudo"
    echo "setup: installing ${missing[*]}"
    $SUDO apt-get update -qq
    # The whole list, so that apt holds every package named (perl-base and
    # libegl-mesa0 included) as the build's; installed ones are left as they are.
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${PACKAGES[@]}"
  fi
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build --parallel "$(nproc)"
