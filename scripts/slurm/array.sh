#!/bin/bash
# One array task: shard $SLURM_ARRAY_TASK_ID of $SHARDS (sweep.conf) into
# $PARTS/$NAME.K.h5.  Submitted by submit.sh (which sets --array from
# SHARDS), or again for the shards merge.sh names:
#   sbatch --array=1,4 scripts/slurm/array.sh
# --resume: a part that is already complete (checked, not just present) is
# kept, so resubmitting the whole array recomputes only what is missing.
# --failed-ok: a complete part with failed cases is a success for Slurm
# (exit 0; the failures are in the part's status/message).
#SBATCH --job-name=rps3-shard
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=logs/%x-%A_%a.out
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
# shellcheck source=sweep.conf
. "${RPS3_CONF:-scripts/slurm/sweep.conf}"
k=${SLURM_ARRAY_TASK_ID:?run as a Slurm array task (sbatch --array=...)}
if [ "$k" -ge "$SHARDS" ]; then
    echo "array task $k: the sweep has $SHARDS shards (sweep.conf)" >&2
    exit 2
fi
exec "$RPS3_RUN" "$SCENE" -o "$PARTS/$NAME.$k.h5" --shard "$k/$SHARDS" \
    -j "${SLURM_CPUS_PER_TASK:-$CPUS}" -q --resume --failed-ok
