#!/bin/bash
# Submit the sharded sweep of scripts/slurm/sweep.conf: an array of SHARDS
# tasks (array.sh), then the join (merge.sh) once every task has ended,
# whether or not it succeeded (afterany: with afterok, one failed or
# cancelled task leaves the merge PENDING forever, DependencyNeverSatisfied;
# merge.sh instead names the missing shards and the command that reruns
# them).  Run from the directory the paths of sweep.conf are relative to:
#   scripts/slurm/submit.sh            (prints the two job ids)
set -euo pipefail
here=$(dirname "$0")
# shellcheck source=sweep.conf
. "${RPS3_CONF:=$here/sweep.conf}"
export RPS3_CONF=$(realpath "$RPS3_CONF")
mkdir -p "$PARTS" "$(dirname "$OUT")" logs
array=$(sbatch --parsable --array="0-$((SHARDS - 1))" \
    --cpus-per-task="$CPUS" "$here/array.sh")
merge=$(sbatch --parsable --dependency="afterany:$array" "$here/merge.sh")
echo "array $array merge $merge"
