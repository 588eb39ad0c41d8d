#!/usr/bin/env bash
# CTest Slurm.EndToEnd: starts a one-machine Slurm cluster
# (scripts/slurm/local_cluster.sh), submits a small generated scene through
# scripts/slurm/submit.sh (tracking job, then a synthesis array job of 3
# tasks that depends on it), waits, and compares every atlas, UV mesh and
# state byte for byte with one `fluidtex run`; then every second frame
# (--frames 1-6x2), whose frames must be that run's too. The daemons are stopped by
# their pid files whatever happens. Exit 77 (skipped) only where Slurm is
# not installed or cannot run (not root); CI installs it.
#   tests/farm/slurm_end_to_end.sh FLUIDTEX_EXE
set -euo pipefail
exe=$(realpath "${1:?usage: $0 FLUIDTEX_EXE}")
root=$(cd "$(dirname "$0")/../.." && pwd)

for tool in munged slurmctld slurmd sbatch sinfo; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool not found: Slurm is not installed (apt-get install slurmctld slurmd slurm-client munge)"
    exit 77
  fi
done
if [[ $(id -u) != 0 ]]; then
  echo "SKIPPED: the local Slurm cluster runs its daemons as root"
  exit 77
fi

tmp=$(mktemp -d)
cleanup() {
  "$root/scripts/slurm/local_cluster.sh" stop "$tmp/cluster" || true
  rm -rf "$tmp"
}
trap cleanup EXIT
start=$SECONDS
"$root/scripts/slurm/local_cluster.sh" start "$tmp/cluster"
export SLURM_CONF=$tmp/cluster/slurm.conf

"$exe" gen rotation -o "$tmp/scene" --frames 6 --resolution 16 --exemplar gravel --exemplar-size 32 >/dev/null
options=(-i "$tmp/scene/rotation.####.ply" -e "$tmp/scene/gravel.png" --atlas-size 128 --seed 5 --aov weight)
"$exe" run -q "${options[@]}" -o "$tmp/one"
# Submitted from another folder: the script and the nodes use absolute paths.
(cd "$tmp/scene" && "$root/scripts/slurm/submit.sh" -o ../farm --frames 1-6 --frames-per-task 2 --wait \
  --fluidtex "$exe" -- "${options[@]}")

status=0
for f in 1 2 3 4 5 6; do
  for name in $(printf 'atlas.%04d.exr mesh.%04d.obj aov/weight.%04d.exr state/patches.%04d.bin' $f $f $f $f); do
    if ! cmp -s "$tmp/one/$name" "$tmp/farm/$name"; then
      echo "FAIL: $name differs between one run and the Slurm job" >&2
      status=1
    fi
  done
done
# Each array task logged its two frames and wrote its own stats file.
for range in 1-2 3-4 5-6; do
  [[ -f $tmp/farm/stats/synth.$range.jsonl ]] || { echo "FAIL: no stats/synth.$range.jsonl" >&2; status=1; }
done
frames=$(cat "$tmp"/farm/logs/fluidtex-synth.*.log | grep -c '^synth frame ' || true)
[[ $frames == 6 ]] || { echo "FAIL: the array tasks logged $frames frames, not 6" >&2; status=1; }
((status)) && { tail -n 20 "$tmp"/farm/logs/*.log "$tmp"/cluster/*.log >&2 || true; exit 1; }

# Every second frame: tracked through frames 2 and 4, textured by two tasks
# (frames 1 and 3, and 5), identical to the every-frame run's frames 1, 3 and 5.
"$root/scripts/slurm/submit.sh" -o "$tmp/step" --frames 1-6x2 --frames-per-task 2 --wait \
  --fluidtex "$exe" -- "${options[@]}"
for f in 1 3 5; do
  for name in $(printf 'atlas.%04d.exr mesh.%04d.obj aov/weight.%04d.exr' $f $f $f); do
    if ! cmp -s "$tmp/one/$name" "$tmp/step/$name"; then
      echo "FAIL: $name of the stepped Slurm job differs from the every-frame run's" >&2
      status=1
    fi
  done
done
for f in 2 4 6; do
  [[ -e $(printf '%s/step/atlas.%04d.exr' "$tmp" $f) ]] && { echo "FAIL: the stepped job wrote frame $f" >&2; status=1; }
done
for range in 1_3 5; do
  [[ -f $tmp/step/stats/synth.$range.jsonl ]] || { echo "FAIL: no stats/synth.$range.jsonl" >&2; status=1; }
done
((status)) && { tail -n 20 "$tmp"/step/logs/*.log "$tmp"/cluster/*.log >&2 || true; exit 1; }
echo "Slurm end to end: 6 frames, and every second frame, identical to one run ($((SECONDS - start)) s with the cluster's start)"
