#!/usr/bin/env bash
# A reproduction sweep over a Slurm job array: task k of N runs
# `tissuebench reproduce --shard k/N` into $TB_SHARDS/k (default shards/k),
# then one more job merges the N folders into results/.
#
#   jid=$(sbatch --parsable --array=0-7 scripts/slurm-array.sh --full)
#   sbatch --dependency=afterok:$jid --wrap "scripts/slurm-array.sh --merge 8"
#
# Arguments are passed to `reproduce` (default --full); after --merge N, to
# `merge` (e.g. --out DIR; default results/). The task's k and N
# come from SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_MIN and
# SLURM_ARRAY_TASK_COUNT, so any contiguous --array range works. Run in the
# repository (sbatch copies the script elsewhere: it starts in
# SLURM_SUBMIT_DIR). Without Slurm, set those variables by hand, e.g. with
# GNU parallel (what the tests do):
#   parallel SLURM_ARRAY_TASK_ID={} SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_COUNT=3 \
#     scripts/slurm-array.sh --full ::: 0 1 2 && scripts/slurm-array.sh --merge 3
#SBATCH --job-name=tissuebench
#SBATCH --cpus-per-task=2
#SBATCH --time=24:00:00
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-$(dirname "$0")/..}"
shards=${TB_SHARDS:-shards}

build=${TB_BUILD_DIR:-$PWD/build}
# Set-up and build once (the tasks may share this folder), then the binary.
mkdir -p "$shards"
flock "$shards/.build.lock" ./tissuebench --version >/dev/null
tb="$build/tissuebench"

if [ "${1:-}" = "--merge" ]; then
  n=${2:?"--merge N: the number of shards"}
  shift 2
  dirs=()
  for k in $(seq 1 "$n"); do dirs+=("$shards/$k"); done
  exec "$tb" merge "${dirs[@]}" "$@"
fi

id=${SLURM_ARRAY_TASK_ID:?"not a Slurm array task (sbatch --array=0-N scripts/slurm-array.sh)"}
min=${SLURM_ARRAY_TASK_MIN:-0}
n=${SLURM_ARRAY_TASK_COUNT:?"SLURM_ARRAY_TASK_COUNT unset"}
k=$((id - min + 1))
[ $# -gt 0 ] || set -- --full
exec "$tb" reproduce "$@" --shard "$k/$n" --results "$shards/$k"
