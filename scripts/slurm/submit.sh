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
#   --resume               continue a tracking step that failed or was cut short
#   --prune-state          synthesis tasks remove the states they used
#   --wait                 return when the array job has finished (exit 1 if a task failed)
#   --sbatch "ARGS"        extra sbatch options for both jobs (partition, time, memory)
#   --fluidtex PATH        the executable on the nodes (default: fluidtex on PATH)
#   RUN_OPTIONS            everything else `fluidtex run` takes: -i, -e, --atlas-size, ...
#
# Logs: OUT/logs/<job name>.<job id>[_<task>].log, one line per finished frame.
# Prints the two job ids. Exit 2 on bad usage.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

usage() {
  sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

out="" frames="" per=8 resume=0 prune=0 wait=0 extra="" fluidtex="${FLUIDTEX:-fluidtex}"
while (($#)); do
  case $1 in
    -o | --output) out=${2:?-o needs a folder}; shift 2 ;;
    --frames) frames=${2:?--frames needs FIRST-LAST[xSTEP]}; shift 2 ;;
    --frames-per-task) per=${2:?--frames-per-task needs a number}; shift 2 ;;
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
command -v sbatch >/dev/null || { echo "submit.sh: sbatch not found (Slurm's client tools)" >&2; exit 2; }

mkdir -p "$out/logs"
out=$(cd "$out" && pwd)  # the nodes may start elsewhere
tasks=$(((last - first) / step / per + 1))
read -r -a sbatch_extra <<<"$extra"
export FLUIDTEX=$fluidtex

track_args=(-o "$out" --frames "$frames" "$@")
((resume)) && track_args+=(--resume)
track=$(sbatch --parsable --export=ALL "${sbatch_extra[@]}" --output="$out/logs/%x.%j.log" \
  "$here/track.sbatch" "${track_args[@]}")
track=${track%%;*}

synth_args=("$out" "$first" "$last" "$per" "$step")
((prune)) && synth_args+=(--prune-state)
wait_flag=()
((wait)) && wait_flag=(--wait)
echo "tracking job $track; synthesis array job (${tasks} tasks of up to $per frames) after it:"
status=0
synth=$(sbatch --parsable --export=ALL "${sbatch_extra[@]}" "${wait_flag[@]}" \
  --dependency="afterok:$track" --kill-on-invalid-dep=yes --array="0-$((tasks - 1))" \
  --output="$out/logs/%x.%A_%a.log" "$here/synth.sbatch" "${synth_args[@]}") || status=$?
echo "${synth%%;*}"
if ((status)); then
  echo "submit.sh: the synthesis array job failed (exit $status): see $out/logs/" >&2
  exit 1
fi
