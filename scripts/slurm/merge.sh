#!/bin/bash
# Join the parts of array.sh into $OUT (virtual datasets over the parts;
# MERGE_OPTS=--copy for one self-contained file).  Exit 0 when the file is
# complete, failed cases included (--failed-ok); exit 2 when shards are
# missing or incomplete: the log then says which, and how to resubmit them.
#SBATCH --job-name=rps3-merge
#SBATCH --time=00:30:00
#SBATCH --output=logs/%x-%j.out
set -uo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
# shellcheck source=sweep.conf
. "${RPS3_CONF:-scripts/slurm/sweep.conf}"
parts=()
for ((k = 0; k < SHARDS; k++)); do
    [ -e "$PARTS/$NAME.$k.h5" ] && parts+=("$PARTS/$NAME.$k.h5")
done
if [ ${#parts[@]} -eq 0 ]; then
    echo "merge.sh: no part in $PARTS/$NAME.*.h5: resubmit with" \
         "scripts/slurm/submit.sh" >&2
    exit 2
fi
err=$(mktemp)
"$RPS3_RUN" merge "$OUT" "${parts[@]}" --failed-ok ${MERGE_OPTS:-} 2>"$err"
code=$?
cat "$err" >&2
list=$(sed -n 's/^rps3-run merge: .* shards\{0,1\} to run again: //p' "$err")
rm -f "$err"
if [ -n "$list" ]; then
    echo "merge.sh: resubmit the missing shards, then the merge:" >&2
    echo "  jid=\$(sbatch --parsable --array=$list scripts/slurm/array.sh)" >&2
    echo "  sbatch --dependency=afterany:\$jid scripts/slurm/merge.sh" >&2
fi
exit "$code"
