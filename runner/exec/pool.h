/*
 * pool.h - the runner's one worker pool.  A job's items (the inverse
 * sweep's jobs, the simulation's cases, the design study's units) are
 * computed on worker threads into slots (out_block tiles); each filled slot
 * goes to the calling thread, the only one that writes (HDF5 is not
 * thread-safe), and comes back free: memory is bounded by the slots, and an
 * item depends on nothing but its index, so what is written does not depend
 * on the threads.  The pool stops at the first error a callback returns (a
 * case that fails numerically is not one: the job records it in its slot).
 * The workers block the signals: core/tmpout.h's handlers run on the
 * calling thread.
 */
#ifndef RPS3_RUNNER_POOL_H
#define RPS3_RUNNER_POOL_H

#include <stddef.h>

typedef struct pool_worker pool_worker;

/* what the pool runs: plain data and callbacks; ctx is the job's own */
typedef struct {
  void *ctx;
  /* the items first, first + stride, ... below nitem (a shard's) */
  size_t nitem, first, stride;
  /* the slots, slot_size bytes each, zeroed, made by slot_make (0, or -1:
     out of memory) and freed by slot_free (made or not) */
  size_t slot_size;
  int (*slot_make)(void *ctx, void *slot, size_t i);
  void (*slot_free)(void *ctx, void *slot, size_t i);
  /* bytes of pool_emit's info, copied with the slot to the writer */
  size_t info_size;
  /* a worker's own state (workspaces), or both NULL */
  void *(*worker_begin)(void *ctx);
  void (*worker_end)(void *ctx, void *wctx);
  /* Compute item i on a worker, filling pool_slot(w) and handing it over
     with pool_emit as often as needed.  0, or -1 with err: the run stops. */
  int (*run)(void *ctx, void *wctx, size_t i, pool_worker *w, char *err,
             size_t errsz);
  /* Write a filled slot with its info, on the calling thread.  0, or -1
     with err: the run stops. */
  int (*write)(void *ctx, void *slot, const void *info, char *err,
               size_t errsz);
} pool_job;

/* the largest info_size */
#define POOL_INFO_MAX 128

/* Run every item of job on nthread worker threads (1: on the calling
   thread, each slot written as soon as it is emitted).  Returns 0, or -1
   with err set to the first error (a callback's, or "cannot start a
   thread", "out of memory"; err as the caller set it when a slot cannot
   be made). */
int pool_run(const pool_job *job, int nthread, char *err, size_t errsz);

/* The item after i of nitem items, stride apart, or nitem when none:
   without wrapping around (a stride as large as SIZE_MAX, --shard
   1/18446744073709551615, would otherwise come back to item 0). */
size_t pool_next(size_t i, size_t stride, size_t nitem);

/* Items of nitem from `first`, stride apart: a shard's. */
size_t pool_count(size_t nitem, size_t first, size_t stride);

/* At most one thread per core: -j beyond them computes nothing faster,
   and each thread holds a slot and a workspace (said on stderr when
   `say`). */
int pool_cores(int nthread, int say);

/* The slot worker w fills now (inside job->run). */
void *pool_slot(pool_worker *w);

/*
 * Hand the slot w fills, described by info (job->info_size bytes), to the
 * writer and take the next one to fill (inside job->run).  Returns that
 * slot, or NULL when the run stops (err set): run then returns -1.
 */
void *pool_emit(pool_worker *w, const void *info, char *err, size_t errsz);

/* 1 when the items run on worker threads, 0 on the calling thread */
int pool_threaded(const pool_worker *w);

#endif /* RPS3_RUNNER_POOL_H */
