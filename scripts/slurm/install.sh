#!/usr/bin/env bash
# Installs what the Slurm recipe and its end-to-end test need on Debian 12:
# Slurm's controller, node daemon and client tools, and munge. Not build
# dependencies of fluidtex (scripts/setup.sh leaves them out); CI runs this
# before the tests.
set -euo pipefail
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0
SUDO=""
[[ $(id -u) -ne 0 ]] && SUDO="sudo"
echo "slurm/install: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
