/*
 * estimate.h - what a run will cost before it starts: the size of its
 * output file, from the plan alone (no allocation, nothing computed).
 */
#ifndef RPS3_RUNNER_ESTIMATE_H
#define RPS3_RUNNER_ESTIMATE_H

#include "sweep.h"

/*
 * Bytes of the file rps3-run writes for the plan p of s, uncompressed:
 * every chunk that the run allocates (p->stored samples per sample field;
 * a partial edge chunk counts whole), the per-case strings, the swept
 * keys and the coordinates, plus a bound on HDF5's metadata.  With --gzip
 * the file is smaller: this is then an upper bound.  A double, because
 * absurd sweeps exceed any size_t.
 */
double est_file_bytes(const scene *s, const sweep_plan *p);

/* "12.3 MB" (powers of 1000) into buf */
const char *est_human(double bytes, char *buf, size_t sz);

#endif /* RPS3_RUNNER_ESTIMATE_H */
