/*
 * world.h - the MPI world of rps3-run-mpi, behind calls that the rest of
 * the runner makes without knowing MPI.  world_mpi.c is Open MPI's (linked
 * into rps3-run-mpi); world_stub.c is a world of one process (linked into
 * rps3-run), where the collectives copy their input.  Worker threads (-j)
 * never call these: only the main thread does (MPI_THREAD_FUNNELED).
 */
#ifndef RPS3_RUNNER_WORLD_H
#define RPS3_RUNNER_WORLD_H

#include <stddef.h>

/* the MPI world of this process: rank 0 of 1 without MPI */
typedef struct {
  int rank;
  int size;
} world;

/* 1 when this program is built with MPI (rps3-run-mpi), 0 otherwise */
int world_has_mpi(void);

/* Start MPI (the stub: nothing) and set w to this process's rank and the
   world's size.  Call once, before any thread starts. */
void world_init(int *argc, char ***argv, world *w);

/* End MPI (the stub: nothing). */
void world_finalize(void);

/* End every rank of the world with exit code `code`. */
void world_abort(int code);

/*
 * Wait for every rank without spinning: a rank that is done (early, or
 * waiting for rank 0's join) polls a nonblocking barrier every millisecond
 * and sleeps in between, where a blocking collective would keep its core
 * busy (Open MPI polls).
 */
void world_idle_barrier(void);

/* out[i] = the largest in[i] of all ranks, on every rank */
void world_max_int(const int *in, int *out, int n);

/* out[i] = the sum of in[i] over all ranks, on rank 0 only */
void world_sum_ulong(const unsigned long *in, unsigned long *out, int n);

/* rank r's `size` bytes of `mine` into all + r * size, on rank 0 only */
void world_gather(const char *mine, size_t size, char *all);

/* *v = rank 0's *v, on every rank */
void world_bcast_int(int *v);

#endif /* RPS3_RUNNER_WORLD_H */
