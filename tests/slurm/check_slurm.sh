#!/bin/bash
# make check-slurm: the shipped scripts (scripts/slurm/) under a real,
# single-node Slurm on localhost, and every output compared with a
# single-process run.
#
# As root on Debian: installs slurm-wlm and munge if missing, starts munged,
# slurmctld and slurmd in the foreground of this script (own key, socket,
# ports 16817-16818, state and logs in a temporary directory; no cgroups:
# proctrack/linuxproc, task/none) and stops them by their PIDs at the end.
# Otherwise it says why it skips, and exits 0.
#
#  1. submit.sh: an array of 3 shards + the merge (afterany), the array
#     held; one task is cancelled, the others released: the merge job
#     names the missing shard and prints the resubmission, which is run as
#     printed; the second merge gives a file equal to the single run's.
#  2. the whole array again: every part is kept (--resume), none computed.
#  3. mpi.sh (srun --mpi=pmix, 2 ranks): equal to the single run; and with
#     MPI_OPTS=--copy, a self-contained file, equal too.
#  4. srun -n 2 of the plain build/rps3-run: refused (exit 2).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PY=${PY:-$ROOT/.venv/bin/python}

skip() { echo "check-slurm: skipped: $*"; exit 0; }
[ "$(id -u)" = 0 ] || skip "needs root (installs slurm-wlm and munge, starts munged, slurmctld and slurmd)"
command -v apt-get >/dev/null && [ -e /etc/debian_version ] ||
    skip "needs Debian (apt-get) for slurm-wlm and munge"
for f in build/rps3-run build/rps3-run-mpi; do
    [ -x "$ROOT/$f" ] || { echo "check-slurm: $f missing (make all)" >&2; exit 1; }
done
need=()
for p in slurm-wlm munge; do dpkg -s "$p" >/dev/null 2>&1 || need+=("$p"); done
if [ ${#need[@]} -gt 0 ]; then
    echo "check-slurm: installing ${need[*]}"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
        --no-install-recommends "${need[@]}" >/dev/null
fi

W=$(mktemp -d /tmp/rps3-check-slurm.XXXXXX)
pids=()
stop() {
    local p
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
    if [ "${KEEP:-0}" = 1 ]; then echo "check-slurm: kept $W"; else rm -rf "$W"; fi
}
trap stop EXIT
say() { echo "check-slurm: $*"; }
fail() { echo "check-slurm: FAILED: $*" >&2; exit 1; }

host=$(hostname -s)
mkdir -p "$W/state" "$W/spool" "$W/munge"
chmod 700 "$W/munge"
head -c 1024 /dev/urandom >"$W/munge/munge.key"
chmod 400 "$W/munge/munge.key"
munged --foreground --force --key-file="$W/munge/munge.key" \
    --socket="$W/munge/munge.sock" --pid-file="$W/munge/munged.pid" \
    --log-file="$W/munge/munged.log" --seed-file="$W/munge/munged.seed" \
    >"$W/munged.out" 2>&1 &
pids+=($!)
cat >"$W/slurm.conf" <<EOF
ClusterName=rps3check
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$W/munge/munge.sock
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/slurmctld.log
SlurmdLogFile=$W/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MinJobAge=3600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=check Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$W/slurm.conf
for _ in $(seq 50); do [ -S "$W/munge/munge.sock" ] && break; sleep 0.1; done
slurmctld -D -i -f "$SLURM_CONF" >"$W/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" >"$W/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 120); do
    state=$(sinfo -h -o %T 2>/dev/null || true)
    [ "$state" = idle ] && break
    sleep 0.5
done
[ "$state" = idle ] || fail "the node is not idle ($state): see $W/*.log (KEEP=1 keeps them)"
say "Slurm $(sinfo -V | cut -d' ' -f2) up on $host (munged ${pids[0]}, slurmctld ${pids[1]}, slurmd ${pids[2]})"

# the state and exit code of a job once it has ended
job_end() {
    local id=$1 info
    for _ in $(seq 1200); do
        info=$(scontrol -o show job "$id" 2>/dev/null || true)
        case "$info" in
        *JobState=PENDING* | *JobState=RUNNING* | *JobState=CONFIGURING* | \
            *JobState=COMPLETING* | "") sleep 0.5 ;;
        *) break ;;
        esac
    done
    echo "$info" | grep -o 'JobState=[A-Z_]* .*ExitCode=[0-9:]*' |
        sed 's/ .*ExitCode=/ ExitCode=/'
}
same() { "$PY" "$ROOT/tests/slurm/same.py" "$@"; }

# the submission directory of a user's checkout
R=$W/run
mkdir -p "$R"
for d in build configs scripts; do ln -s "$ROOT/$d" "$R/$d"; done
cd "$R"
build/rps3-run configs/grid.yaml -o "$W/ref.h5" -q
. scripts/slurm/sweep.conf

# 1. array + merge, one task cancelled, recovered as the merge log says
ids=$(SBATCH_HOLD=1 scripts/slurm/submit.sh)
array=$(echo "$ids" | cut -d' ' -f2)
merge=$(echo "$ids" | cut -d' ' -f4)
say "submitted array $array ($SHARDS tasks, held) and merge $merge (afterany)"
scancel "${array}_1"
scontrol release "${array}_0" "${array}_2" "$merge"
end=$(job_end "$merge")
log=logs/rps3-merge-$merge.out
[ "$end" = "JobState=FAILED ExitCode=2:0" ] || fail "merge with shard 1 cancelled: $end; $(cat "$log")"
grep -q "1 of 3 shards to run again: 1$" "$log" || fail "merge names no missing shard: $(cat "$log")"
say "cancelled ${array}_1: merge $merge ended $end, naming shard 1:"
sed 's/^/    /' "$log"
jid=$(eval "$(sed -n 's/^  \(jid=.*\)$/\1/p' "$log")"; echo "$jid")
[ -n "$jid" ] || fail "no resubmission in the merge log"
merge2=$(eval "$(sed -n 's/^  sbatch \(--dependency.*\)$/sbatch --parsable \1/p' "$log")")
end=$(job_end "$merge2")
[ "$end" = "JobState=COMPLETED ExitCode=0:0" ] || fail "merge after the resubmission: $end; $(cat "logs/rps3-merge-$merge2.out")"
same "$W/ref.h5" "$OUT" --virtual
say "resubmitted shard 1 (job $jid), merge $merge2: $end; $OUT (virtual datasets) equals the single-process run"

# 2. the whole array again: every part complete, kept
before=$(stat -c %Y parts/*.h5 | tr '\n' ' ')
again=$(sbatch --parsable --array="0-$((SHARDS - 1))" scripts/slurm/array.sh)
for k in $(seq 0 $((SHARDS - 1))); do
    end=$(job_end "${again}_$k")
    [ "$end" = "JobState=COMPLETED ExitCode=0:0" ] || fail "array again, task $k: $end"
done
[ "$(stat -c %Y parts/*.h5 | tr '\n' ' ')" = "$before" ] || fail "--resume rewrote a complete part"
say "array $again over complete parts: every task COMPLETED, no part rewritten (--resume)"

# 3. MPI: srun --mpi=pmix, 2 ranks; then --copy
mid=$(MPI_OUT=$R/out/mpi.h5 sbatch --parsable --ntasks=2 scripts/slurm/mpi.sh)
end=$(job_end "$mid")
[ "$end" = "JobState=COMPLETED ExitCode=0:0" ] || fail "mpi.sh: $end; $(cat "logs/rps3-mpi-$mid.out")"
same "$W/ref.h5" out/mpi.h5 --virtual
mid2=$(MPI_OUT=$R/out/mpi-copy.h5 MPI_OPTS=--copy sbatch --parsable --ntasks=2 scripts/slurm/mpi.sh)
end2=$(job_end "$mid2")
[ "$end2" = "JobState=COMPLETED ExitCode=0:0" ] || fail "mpi.sh --copy: $end2; $(cat "logs/rps3-mpi-$mid2.out")"
same "$W/ref.h5" out/mpi-copy.h5 --copy
[ -z "$(ls out | grep -v '^mpi\.h5' | grep -v '^mpi-copy\.h5$' | grep -v '^grid\.h5$' || true)" ] ||
    fail "leftovers in out/: $(ls out)"
say "mpi.sh (srun --mpi=pmix -n 2): $end, equal; with --copy: $end2, one self-contained file, equal"

# 4. the plain binary under srun -n 2
set +e
msg=$(srun -n 2 build/rps3-run configs/grid.yaml -o out/plain.h5 2>&1)
code=$?
set -e
[ "$code" -ne 0 ] && echo "$msg" | grep -q "2 tasks by srun" || fail "srun -n 2 build/rps3-run: exit $code: $msg"
[ ! -e out/plain.h5 ] || fail "srun -n 2 build/rps3-run wrote out/plain.h5"
say "srun -n 2 build/rps3-run refused (exit $code): $(echo "$msg" | grep -m1 'tasks by srun')"
say "passed"
