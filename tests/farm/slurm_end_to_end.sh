#!/usr/bin/env bash
# CTest Slurm.EndToEnd: starts a one-machine Slurm cluster
# (scripts/slurm/local_cluster.sh), submits a small generated scene through
# scripts/slurm/submit.sh (tracking job, then a synthesis array job of 3
# tasks that depends on it), waits, and compares every atlas, UV mesh and
# state byte for byte with one `fluidtex run`; then every second frame
# (--frames 1-6x2), whose frames must be that run's too. Then what a farm
# does to jobs: a tracking step that fails makes `submit.sh --wait` exit 1
# naming it; a tracking step requeued while it runs (as a preemption does)
# and a finished synthesis task requeued both end with one run's files, each
# attempt with its own log; a task re-run by hand with plain sbatch, without
# FLUIDTEX, finds the executable the job folder records. The daemons are
# stopped by their pid files whatever happens. Exit 77 (skipped) only where Slurm is
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

"$exe" gen rotation -o "$tmp/scene" --frames 6 --resolution 16 --exemplar gravel --exemplar-pixels 32 >/dev/null
options=(-i "$tmp/scene/rotation.####.ply" -e "$tmp/scene/gravel.png" --atlas-size 128 --seed 5 --aov weight)
"$exe" run -q "${options[@]}" -o "$tmp/one"
# Submitted from another folder: the script and the nodes use absolute paths.
(cd "$tmp/scene" && "$root/scripts/slurm/submit.sh" -o ../farm --frames 1-6 --frames-per-task 2 --cpus 1 --wait \
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
frames=$(cat "$tmp"/farm/logs/synth.*.attempt1.log | grep -c '^synth frame ' || true)
[[ $frames == 6 ]] || { echo "FAIL: the array tasks logged $frames frames, not 6" >&2; status=1; }
((status)) && { tail -n 20 "$tmp"/farm/logs/*.log "$tmp"/cluster/*.log >&2 || true; exit 1; }

# Every second frame: tracked through frames 2 and 4, textured by two tasks
# (frames 1 and 3, and 5), identical to the every-frame run's frames 1, 3 and 5.
"$root/scripts/slurm/submit.sh" -o "$tmp/step" --frames 1-6x2 --frames-per-task 2 --cpus 1 --wait \
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

export SUBMIT_POLL_SECONDS=1
fail() {
  echo "FAIL: $*" >&2
  tail -n 20 "$tmp"/*/logs/*.log "$tmp"/cluster/slurmctld.log >&2 || true
  exit 1
}
# The same files as one run, frames FIRST..LAST of the requeue scene.
same_as_one() {
  local f name
  for ((f = $1; f <= $2; ++f)); do
    for name in $(printf 'atlas.%04d.exr mesh.%04d.obj state/patches.%04d.bin' $f $f $f); do
      cmp -s "$tmp/long-one/$name" "$tmp/requeue/$name" || fail "$name differs from one run's after $3"
    done
  done
}
# A step Slurm requeued waits for its begin time (minutes); let it start
# sooner, but not within the second of the requeue: the node refuses a
# credential issued in the second it revoked the job's ("Job credential
# revoked"), which Slurm's own delay avoids.
start_now() {
  for _ in $(seq 100); do
    [[ $(squeue -h -j "$1" -o %T 2>/dev/null) == PENDING ]] && break
    sleep 0.1
  done
  sleep 2
  scontrol update JobId="$1" StartTime=now
}

# A tracking step that fails (its input is missing): --wait exits 1 and
# names the failed job and the cancelled tasks.
if out=$("$root/scripts/slurm/submit.sh" -o "$tmp/fail" --frames 1-4 --frames-per-task 2 --cpus 1 --wait \
  --fluidtex "$exe" -- -i "$tmp/nowhere/x.####.ply" -e "$tmp/scene/gravel.png" 2>&1); then
  fail "submit.sh --wait exited 0 although the tracking step failed: $out"
fi
grep -qE 'tracking job [0-9]+: FAILED \(exit 2:0' <<<"$out" || fail "no line names the failed tracking job: $out"
grep -qE 'synthesis task [0-9_-]+: CANCELLED \(exit [^,]*, DependencyNeverSatisfied' <<<"$out" ||
  fail "no line names the cancelled synthesis tasks: $out"

# Preempted while tracking: requeued as soon as it has written a state.
"$exe" gen rotation -o "$tmp/long" --frames 12 --resolution 40 --exemplar gravel --exemplar-pixels 32 >/dev/null
long=(-i "$tmp/long/rotation.####.ply" -e "$tmp/long/gravel.png" --atlas-size 64 --radius 0.05 --seed 3)
"$exe" run -q "${long[@]}" -o "$tmp/long-one"
env -u FLUIDTEX "$root/scripts/slurm/submit.sh" -o "$tmp/requeue" --frames 1-12 --frames-per-task 6 --cpus 1 --wait \
  --fluidtex "$exe" -- "${long[@]}" >"$tmp/requeue.out" 2>&1 &
submitter=$!
for _ in $(seq 600); do
  [[ -f $tmp/requeue/state/patches.0002.bin ]] && break
  sleep 0.1
done
track=$(sed -n 's/^tracking job \([0-9]*\) .*/\1/p' "$tmp/requeue.out")
[[ -f $tmp/requeue/state/patches.0012.bin ]] && fail "tracking ended before it could be requeued"
scontrol requeue "$track"
start_now "$track"
wait "$submitter" || fail "submit.sh --wait after a requeued tracking step: $(cat "$tmp/requeue.out")"
same_as_one 1 12 "the tracking step was requeued"
[[ -f $tmp/requeue/logs/track.$track.attempt1.log ]] || fail "no log of the first tracking attempt"
grep -q 'attempt 2 continues the job' "$tmp/requeue/logs/track.$track.attempt2.log" ||
  fail "the second tracking attempt did not resume"

# A finished task requeued (its node lost after the fact) runs again.
synth=$(sed -n '2p' "$tmp/requeue.out")
[[ $synth =~ ^[0-9]+$ ]] || fail "no synthesis job id in: $(cat "$tmp/requeue.out")"
rm "$tmp/requeue/atlas.0012.exr"
scontrol requeue "${synth}_1"
start_now "${synth}_1"
while [[ -n $(squeue -h -j "$synth" -o %i) ]]; do sleep 0.5; done
same_as_one 7 12 "a finished task was requeued"
[[ -f $tmp/requeue/logs/synth.${synth}_1.attempt2.log ]] || fail "no log of the requeued task's second attempt"

# One task re-run by hand, as docs/farm.md says, with nothing in the
# environment: the executable comes from OUT/slurm.env, the log goes to OUT/logs.
rm "$tmp/requeue/atlas.0003.exr"
rerun=$(cd "$tmp" && env -u FLUIDTEX PATH=/usr/bin:/bin sbatch --parsable --array=0 \
  "$root/scripts/slurm/synth.sbatch" "$tmp/requeue" 1 12 6 1)
rerun=${rerun%%;*}
while [[ -n $(squeue -h -j "$rerun" -o %i) ]]; do sleep 0.5; done
same_as_one 1 6 "a task was re-run by hand"
grep -q '^synth frame 3:' "$tmp/requeue/logs/synth.${rerun}_0.attempt1.log" || fail "the re-run task's log has no frame 3"
ls "$tmp"/slurm-* >/dev/null 2>&1 && fail "a log was written outside OUT/logs"

echo "Slurm end to end: 6 frames, every second frame, a failed, a requeued and a re-run step ($((SECONDS - start)) s with the cluster's start)"
