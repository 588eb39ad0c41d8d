#!/usr/bin/env bash
# Submits a fluidtex job to Slurm: tracking as one job, then synthesis as an
# array job that starts when tracking succeeded (afterok), FRAMES_PER_TASK
# frames per array task. The result is byte-identical to one `fluidtex run`.
#
#   scripts/slurm/submit.sh -o OUT --frames FIRST-LAST[xSTEP] [options] -- RUN_OPTIONS...
#
#   -o OUT                 the job's output folder (shared by every node)
#   --frames FIRST-LAST    the frames to texture (a range; FIRST-LASTxSTEP
#                          textures every STEP-th, tracking the frames between)
#   --frames-per-task N    frames per synthesis task (default 8)
#   --cpus N               CPUs per step (default 2); fluidtex runs N threads
#   --mem MB               memory per step (default: from the atlas size and
#                          --cpus, docs/farm.md's table)
#   --resume               continue a tracking step that failed or was cut short
#   --prune-state          synthesis tasks remove the states they used
#   --wait                 return when the job has ended; exit 1 unless every
#                          step completed, naming each one that did not
#   --sbatch "ARGS"        extra sbatch options for both jobs (partition, time)
#   --fluidtex PATH        the executable on the nodes (default: fluidtex on PATH)
#   RUN_OPTIONS            everything else `fluidtex run` takes: -i, -e, --atlas-size, ...
#
# Records the executable in OUT/slurm.env, so that a step re-run by hand
# needs nothing else. Logs: OUT/logs/track.<job>.attempt<N>.log and
# OUT/logs/synth.<job>_<task>.attempt<N>.log (one per attempt: a requeued
# step keeps its earlier logs), Slurm's own messages in OUT/logs/*.slurm.log.
# Prints the two job ids. Exit 2 on bad usage.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

usage() {
  sed -n '2,28p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

out="" frames="" per=8 cpus=2 mem="" resume=0 prune=0 wait=0 extra="" fluidtex="${FLUIDTEX:-fluidtex}"
while (($#)); do
  case $1 in
    -o | --output) out=${2:?-o needs a folder}; shift 2 ;;
    --frames) frames=${2:?--frames needs FIRST-LAST[xSTEP]}; shift 2 ;;
    --frames-per-task) per=${2:?--frames-per-task needs a number}; shift 2 ;;
    --cpus) cpus=${2:?--cpus needs a number}; shift 2 ;;
    --mem) mem=${2:?--mem needs megabytes}; shift 2 ;;
    --resume) resume=1; shift ;;
    --prune-state) prune=1; shift ;;
    --wait) wait=1; shift ;;
    --sbatch) extra=${2:?--sbatch needs its options}; shift 2 ;;
    --fluidtex) fluidtex=${2:?--fluidtex needs a path}; shift 2 ;;
    --) shift; break ;;
    -h | --help) usage ;;
    *) echo "submit.sh: unknown option '$1' (run options go after --)" >&2; exit 2 ;;
  esac
done
[[ -n $out ]] || { echo "submit.sh: -o OUT is required" >&2; exit 2; }
if [[ ! $frames =~ ^(-?[0-9]+)-(-?[0-9]+)(x([1-9][0-9]*))?$ ]]; then
  echo "submit.sh: --frames FIRST-LAST or FIRST-LASTxSTEP is required (one range), got '$frames'" >&2
  exit 2
fi
first=${BASH_REMATCH[1]} last=${BASH_REMATCH[2]} step=${BASH_REMATCH[4]:-1}
((last >= first)) || { echo "submit.sh: --frames $frames ends before it starts" >&2; exit 2; }
last=$((first + (last - first) / step * step))  # the last frame the range textures
[[ $per =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --frames-per-task must be a positive integer" >&2; exit 2; }
[[ $cpus =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --cpus must be a positive integer" >&2; exit 2; }
[[ -z $mem || $mem =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --mem must be a positive number of megabytes" >&2; exit 2; }
command -v sbatch >/dev/null || { echo "submit.sh: sbatch not found (Slurm's client tools)" >&2; exit 2; }

# The memory a step needs: 1.5 x (400 MB + 70 bytes per atlas texel), over
# the peaks measured at 1024-8192 texels wide and 2 or 4 threads
# (docs/farm.md, "Memory").
atlas=2048
for ((i = 1; i <= $#; ++i)); do
  case ${!i} in
    --atlas-size) j=$((i + 1)); atlas=${!j:-2048} ;;
    --atlas-size=*) atlas=${!i#--atlas-size=} ;;
  esac
done
[[ $atlas =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --atlas-size '$atlas' is not a number" >&2; exit 2; }
[[ -n $mem ]] || mem=$(((400 + atlas * atlas * 70 / 1048576) * 3 / 2))

mkdir -p "$out/logs"
out=$(cd "$out" && pwd)  # the nodes may start elsewhere
# The executable as the nodes will run it, for steps re-run by hand.
if [[ $fluidtex == */* ]]; then fluidtex=$(realpath -m "$fluidtex"); fi
printf '# written by scripts/slurm/submit.sh: what the job'"'"'s Slurm steps run\nFLUIDTEX=%s\n' "$fluidtex" \
  >"$out/slurm.env"
tasks=$(((last - first) / step / per + 1))
read -r -a sbatch_extra <<<"$extra"
resources=(--cpus-per-task="$cpus" --mem="$mem")

track_args=("$out" --frames "$frames" "$@")
((resume)) && track_args+=(--resume)
track=$(sbatch --parsable "${resources[@]}" "${sbatch_extra[@]}" --output="$out/logs/%x.%j.slurm.log" \
  "$here/track.sbatch" "${track_args[@]}")
track=${track%%;*}

synth_args=("$out" "$first" "$last" "$per" "$step")
((prune)) && synth_args+=(--prune-state)
echo "tracking job $track ($cpus CPUs, $mem MB); synthesis array job (${tasks} tasks of up to $per frames) after it:"
synth=$(sbatch --parsable "${resources[@]}" "${sbatch_extra[@]}" \
  --dependency="afterok:$track" --kill-on-invalid-dep=yes --array="0-$((tasks - 1))" \
  --output="$out/logs/%x.%A_%a.slurm.log" "$here/synth.sbatch" "${synth_args[@]}")
synth=${synth%%;*}
echo "$synth"
echo "re-run task i by hand: sbatch --array=i --output='$out/logs/%x.%A_%a.slurm.log' $here/synth.sbatch ${synth_args[*]}"
((wait)) || exit 0

# Wait until neither job is queued or running (a requeued step is queued
# again), then check every step's end state: an array cancelled because
# tracking failed ends without a failed task.
poll=${SUBMIT_POLL_SECONDS:-10}
while :; do
  if queued=$(squeue -h -j "$track,$synth" -o %i 2>/dev/null); then
    [[ -z $queued ]] && break
  fi
  sleep "$poll"
done
failed=0
states() {  # JOB: "id state exit reason" per task, from the controller, else accounting
  local line id
  if lines=$(scontrol -o show job "$1" 2>/dev/null) && [[ -n $lines ]]; then
    while IFS= read -r line; do
      field() { grep -oE "(^| )$1=[^ ]*" <<<"$line" | head -1 | cut -d= -f2-; }
      id=$(field JobId)
      [[ -n $(field ArrayTaskId) ]] && id="$(field ArrayJobId)_$(field ArrayTaskId)"
      echo "$id $(field JobState) $(field ExitCode) $(field Reason)"
    done <<<"$lines"
  elif lines=$(sacct -n -X -P -j "$1" -o JobID,State,ExitCode 2>/dev/null) && [[ -n $lines ]]; then
    tr '|' ' ' <<<"$lines" | awk '{print $1, $2, $3, "-"}'
  else
    echo "$1 unknown ? neither_scontrol_nor_sacct_knows_the_job"
  fi
}
for job in "tracking job:$track" "synthesis task:$synth"; do
  while read -r id state code reason; do
    [[ $state == COMPLETED ]] && continue
    echo "submit.sh: ${job%%:*} $id: $state (exit $code, $reason); logs in $out/logs/" >&2
    failed=1
  done < <(states "${job##*:}")
done
((failed)) && exit 1
echo "submit.sh: every step completed"
