#!/bin/bash
# The sweep of sweep.conf as one MPI job: rank r computes shard r/N, rank 0
# joins the parts (virtual datasets; MPI_OPTS=--copy for one
# self-contained file).  OUT's directory must be on a filesystem every
# node sees: $SCRATCH when set, else the submission directory.
#   sbatch scripts/slurm/mpi.sh
# Launched with `srun --mpi=pmix` (Slurm's PMIx plugin; `srun --mpi=list`
# shows those of a cluster); LAUNCH=mpirun uses Open MPI's own launcher
# inside the allocation instead.  Size --ntasks to at most the scene's jobs
# (`build/rps3-run SCENE --check`).
#SBATCH --job-name=rps3-mpi
#SBATCH --ntasks=2
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=logs/%x-%j.out
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
# shellcheck source=sweep.conf
. "${RPS3_CONF:-scripts/slurm/sweep.conf}"
out=${MPI_OUT:-${SCRATCH:-$PWD}/$OUT}
mkdir -p "$(dirname "$out")"
run=${RPS3_RUN_MPI:-build/rps3-run-mpi}
threads=${SLURM_CPUS_PER_TASK:-1}
if [ "${LAUNCH:-srun}" = mpirun ]; then
    exec mpirun --map-by "slot:PE=$threads" "$run" "$SCENE" -o "$out" \
        -j "$threads" --failed-ok ${MPI_OPTS:-}
fi
exec srun --mpi=pmix "$run" "$SCENE" -o "$out" -j "$threads" --failed-ok \
    ${MPI_OPTS:-}
