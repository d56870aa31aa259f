/*
 * sim_output.h - the HDF5 file of a simulated scene (simulate.h): its
 * schema and a writer of windows of one case at a time.
 *
 * The conventions of output.h: dimension scales case, time and link, the
 * swept keys as [case] coordinates, units and description on every
 * dataset, Fletcher-32 on every chunk, NaN (-1) for missing values,
 * status -1000 for a case not computed, the scene verbatim and each
 * case's resolved scene.  The datasets differ: the OUT_SIM rows of
 * RPS3_OUTPUT_FIELDS (outblock.h).
 */
#ifndef RPS3_RUNNER_SIM_OUTPUT_H
#define RPS3_RUNNER_SIM_OUTPUT_H

#include <stddef.h>
#include <stdint.h>

#include "output.h"
#include "scene/scene.h"

/*
 * The buffer of one window of one case: for each field of shape CT or CTL
 * `points` samples of 1 or 3 doubles, row k of field i at
 * buf[i] + k * columns (NULL for the per-case fields).
 */
typedef struct {
  size_t points;           /* samples per window */
  double *buf[OUT_NFIELD]; /* OUT_SIM fields only */
} sim_window;

/* the per-case values of a case */
typedef struct {
  double tracking_error_max, failed_time;
  int32_t status, failed_at;
  int64_t nsteps, nevals, nticks, nsat;
  char message[640];
  const char *scene_resolved;
} sim_case_values;

/* Allocate the window buffers for `points` samples: 0, or -1. */
int sim_window_alloc(sim_window *w, size_t points);
void sim_window_free(sim_window *w);

/*
 * Create the file at path for the cases of s (out_open with the OUT_SIM
 * fields); nt the most samples of any case; times the common time axis
 * (nt values) or NULL when the grid differs by case (then `time` is a
 * sample index and case_time holds the times).  Chunks are [1, points,
 * (3)], Fletcher-32, deflate at gzip.  The file is closed with out_close.
 * Returns NULL with a message in err.
 */
out_file *sim_file_create(const char *path, const scene *s, size_t nt,
                          const double *times, size_t points, int gzip,
                          const char *command_line, char *err, size_t errsz);

/* Write samples [k0, k0 + nk) of case c from the window (out_write_window;
   times when the grid differs, else NULL).  0 or -1 with err set. */
int sim_file_window(out_file *f, const sim_window *w, size_t c, size_t k0,
                    size_t nk, const double *times, char *err, size_t errsz);

/* Write the per-case values of case c (out_write_case).  0 or -1 with err
   set. */
int sim_file_case(out_file *f, const sim_case_values *v, size_t c, char *err,
                  size_t errsz);

/* Bytes of a file of ncase cases and npoint samples in all, uncompressed
   (the per-case strings estimated): an estimate for the disk check. */
double sim_file_bytes(size_t ncase, size_t npoint);

#endif /* RPS3_RUNNER_SIM_OUTPUT_H */
