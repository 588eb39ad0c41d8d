#!/usr/bin/env bash
# Installs Blender 3.4 (Debian 12's package) for the Blender round trip
# (tests/dcc/blender_roundtrip.sh): not a build dependency of fluidtex
# (scripts/setup.sh leaves it out); CI runs this before the tests.
set -euo pipefail
dpkg-query -W -f='${Status}' blender 2>/dev/null | grep -q "install ok installed" && exit 0
SUDO=""
[[ $(id -u) -ne 0 ]] && SUDO="sudo"
echo "blender/install: installing blender"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends blender
