/*
 * estimate.h - what a run will cost before it starts (the size of its file
 * from the plan alone, its run time from a few samples computed and timed)
 * and what rps3-run says and refuses (exit 2, nothing written) before a
 * sweep: shards that cannot have work, an output that cannot fit.
 */
#ifndef RPS3_RUNNER_ESTIMATE_H
#define RPS3_RUNNER_ESTIMATE_H

#include "sweep.h"

/* "12.3 MB" (powers of 1000) into buf */
const char *est_human(double bytes, char *buf, size_t sz);

/* what a sample and a case cost, in CPU seconds */
typedef struct {
  double sample;   /* computing one sample (trajectory + rps3_inverse) */
  double per_case; /* building a case and its scene_resolved YAML */
  double write;    /* writing one sample's bytes (the writing thread) */
  double deflate;  /* deflating them (--gzip; on the workers at -j N) */
  size_t cases;    /* cases timed */
  size_t samples;  /* samples timed */
} est_cost;

/* "3.2 s", "4.1 min", "2.5 h", "3.1 days" into buf */
const char *est_human_time(double seconds, char *buf, size_t sz);

/* "about 3.2 s on 2 threads" into buf: the wall time of a run of
   `samples` samples and `cases` cases at cost c on `threads` worker
   threads (1: the calling thread computes, deflates and writes) */
const char *est_when(const est_cost *c, double samples, double cases,
                     int threads, char *buf, size_t sz);

/* This process's CPU time [s]. */
double est_cpu_now(void);

/* Refuse (-1, said on stderr) an output of `need` bytes larger than the
   free space of out_path's file system, unless deflated (gzip: need is
   then an upper bound).  Returns 0 or -1. */
int est_fits(const char *out_path, double need, int gzip);

/* --check's first line on stdout: the cases (`kind`: "" or "simulated: "),
   samples, nt per case at most (the grid common or not) and size */
void est_check_print(const char *path, const char *kind, size_t ncase,
                     size_t npoint, size_t nt, int common, double bytes);

/* Before a run: unless quiet, one line on stderr with the cases (`kind`:
   "" or "simulated "), samples, size `need` and run time `when`; then
   est_fits.  Returns 0 or -1. */
int est_room(const char *out_path, const char *kind, size_t ncase,
             size_t npoint, double need, int gzip, int quiet, const char *when);

/* who runs: this process's rank of nrank (0 of 1 without MPI) */
typedef struct {
  int rank;
  int nrank;
  int copy;        /* --copy under mpirun: rank 0 writes a merged copy */
  int gzip;        /* deflate level, 0 for none */
  int quiet;       /* no size and time line before the run */
  out_mask fields; /* the fields written (--fields) */
} pre_opts;

/* The jobs against the shards, ranks and threads (rank 0 speaks, even with
   --quiet): --shard K/N with N above the jobs is refused (-1: shards
   K >= jobs would compute nothing); ranks above the jobs (mpirun -n is set
   by the allocation) and -j above the shard's jobs are warned about. */
int pre_jobs(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po);

/* --check's report on stdout: cases, samples, size, run time, jobs */
void pre_check_print(const char *scene_path, const scene *s,
                     const sweep_plan *p, const sweep_opts *o,
                     const pre_opts *po);

/* Before a run (rank 0): one line with the cases, samples, size and run
   time; refuse (-1) an estimate above the free space of out_path's file
   system: this process writes its shard's cases; under mpirun the parts,
   and with --copy rank 0's merged copy too. */
int pre_room(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po, const char *out_path);

#endif /* RPS3_RUNNER_ESTIMATE_H */
