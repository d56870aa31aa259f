/*
 * bench.h - rps3-bench: per-call timings of the library's stages, printed
 * as a table and written to an HDF5 file.  Not part of the library.
 */
#ifndef RPS3_BENCH_H
#define RPS3_BENCH_H

#include <stddef.h>

/* "no value" in a double column (NAN is a float) */
#define BENCH_NONE ((double)NAN)

/* one row of the table: the per-call times of the batches of one case */
typedef struct {
  const char *name;        /* short key, e.g. "invdyn_lagrange_full" */
  const char *doc;         /* what one call does */
  double median_ns;        /* median over batches of the per-call time [ns] */
  double p10_ns, p90_ns;   /* 10th and 90th percentiles over batches [ns] */
  double min_ns, max_ns;   /* fastest and slowest batch [ns per call] */
  double cpu_median_ns;    /* median over batches of the thread CPU time per
                              call [ns] */
  double target_ns;        /* target per call [ns], NaN when none */
  double mean_iter;        /* theta-solve iterations per call, NaN if none */
  long calls;              /* calls per batch */
  long batches;            /* timed batches (after one warm-up batch) */
  long failures;           /* calls that did not return RPS3_OK */
} bench_row;

/* what the run was, for the file's root attributes */
typedef struct {
  const char *machine;     /* CPU model name from /proc/cpuinfo */
  const char *compiler;    /* compiler version string */
  const char *trajectory;  /* the points the cases loop over */
  const char *scene_full;  /* the full scene */
  const char *scene_gravity; /* the gravity-only scene */
  const char *scene_general; /* the general bodies' scene */
  const char *clock;       /* timer used */
} bench_info;

/* Write rows to the HDF5 file path (one 1-D dataset per column, every one
   with a `units` attribute, the benchmark names as the dimension scale).
   Returns 0, or -1 with a message on stderr. */
int bench_write_h5(const char *path, const bench_info *info,
                   const bench_row *rows, int nrows);

#endif /* RPS3_BENCH_H */
