/*
 * preflight.h - what rps3-run says and checks before a run starts: the
 * jobs and who has work, the output's estimated size and run time, and the
 * refusals (exit 2, nothing written) of shards that cannot have work and of
 * an output that cannot fit on its file system.
 */
#ifndef RPS3_RUNNER_PREFLIGHT_H
#define RPS3_RUNNER_PREFLIGHT_H

#include "sweep.h"

/* who runs: this process's rank of nrank (0 of 1 without MPI) */
typedef struct {
  int rank;
  int nrank;
  int copy;        /* --copy under mpirun: rank 0 writes a merged copy */
  int gzip;        /* deflate level, 0 for none */
  int quiet;       /* no size and time line before the run */
  out_mask fields; /* the fields written (--fields) */
} pre_opts;

/*
 * The jobs against the shards, ranks and threads (rank 0 speaks, on
 * stderr, even with --quiet).  --shard K/N with N above the number of jobs
 * is refused (returns -1): shards K >= jobs would compute nothing.  Ranks
 * above the jobs (mpirun -n N is set by the allocation) and -j above the
 * jobs of the shard are warned about.  Returns 0 or -1.
 */
int pre_jobs(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po);

/* --check's report on stdout: cases, samples, size, run time, jobs */
void pre_check_print(const char *scene_path, const scene *s,
                     const sweep_plan *p, const sweep_opts *o,
                     const pre_opts *po);

/*
 * Before a run (rank 0): one line with the cases, samples, estimated size
 * and run time; refuse (returns -1) when the estimate exceeds the free
 * space of out_path's file system: this process writes the cases of its
 * shard; under mpirun the parts, and with --copy rank 0's merged copy too.
 */
int pre_room(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po, const char *out_path);

#endif /* RPS3_RUNNER_PREFLIGHT_H */
