/*
 * sweep_threads.c - sweep_run_opts() (sweep.h): on one thread, the
 * serial run of sweep.c; on threads, workers compute jobs into the blocks
 * of a pool and the calling thread, the only one that calls HDF5, writes
 * each tile as it comes.
 */
#include "sweep.h"
#include "sweep_int.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* -------------------------------------------------------------- threaded */

/* The pool: nblock tiles, each free, being filled by a worker, queued for
   writing (ready, first in first out) or being written.  Each worker holds
   one block at a time, so with nblock > nthread the writer always has
   something to free and no one waits forever. */
typedef struct {
  pthread_mutex_t mu;
  pthread_cond_t ready_cv; /* a tile is ready, or a worker ended */
  pthread_cond_t free_cv;  /* a block is free, or the run stops */
  out_block *block;        /* [nblock] */
  size_t nblock;
  size_t *free_ix; /* [nblock] stack of free blocks */
  size_t nfree;
  size_t *ready_ix; /* [nblock] ring of ready blocks ... */
  tile *ready_tile; /* [nblock] ... and their tiles */
  size_t ready_head, nready;
  size_t next_job; /* the next job to take */
  int nactive;     /* workers still running */
  int stop;        /* 1: a worker or the writer failed */
  char err[512];   /* the first failure */
  /* what the workers read */
  const scene *s;
  const sweep_plan *p;
  const sweep_opts *o;
  out_layout layout; /* the file's chunks, for out_pack */
} pool;

typedef struct {
  sink base;
  pool *pl;
  size_t held; /* the block this worker fills */
} worker;

/* stop the run with this error (the first one wins); mu held */
static void pool_fail(pool *pl, const char *msg) {
  if (!pl->stop) snprintf(pl->err, sizeof pl->err, "%s", msg);
  pl->stop = 1;
  pthread_cond_broadcast(&pl->free_cv);
  pthread_cond_broadcast(&pl->ready_cv);
}

static int worker_emit(sink *k, out_block **b, const tile *t, char *err,
                       size_t errsz) {
  worker *w = (worker *)k;
  pool *pl = w->pl;
  size_t r;
  /* deflate and checksum here, in parallel, not on the writing thread; a
     late failure's blank windows go through HDF5's own filters */
  (*b)->packed = 0;
  if (t->blank_below == 0 &&
      out_pack(&pl->layout, *b, t->c0, t->nc, t->k0, t->nk)) {
    snprintf(err, errsz, "cannot pack cases %zu-%zu: out of memory", t->c0,
             t->c0 + t->nc - 1);
    return -1;
  }
  pthread_mutex_lock(&pl->mu);
  /* queue the filled block */
  r = (pl->ready_head + pl->nready) % pl->nblock;
  pl->ready_ix[r] = w->held;
  pl->ready_tile[r] = *t;
  pl->nready++;
  pthread_cond_signal(&pl->ready_cv);
  /* and take a free one */
  while (pl->nfree == 0 && !pl->stop) pthread_cond_wait(&pl->free_cv, &pl->mu);
  if (pl->stop) {
    pthread_mutex_unlock(&pl->mu);
    snprintf(err, errsz, "stopped");
    return -1;
  }
  w->held = pl->free_ix[--pl->nfree];
  *b = &pl->block[w->held];
  pthread_mutex_unlock(&pl->mu);
  return 0;
}

static void *worker_main(void *arg) {
  worker *w = arg;
  pool *pl = w->pl;
  size_t nj = sweep_njob(pl->s, pl->p);
  rps3_data *ws[RPS3_NSOLVER];
  char err[512];
  memset(ws, 0, sizeof ws);
  pthread_mutex_lock(&pl->mu);
  /* a block to fill; there are more blocks than workers, but a worker that
     starts late may find them all queued for writing */
  while (pl->nfree == 0 && !pl->stop) pthread_cond_wait(&pl->free_cv, &pl->mu);
  if (pl->stop) {
    pl->nactive--;
    pthread_cond_broadcast(&pl->ready_cv);
    pthread_mutex_unlock(&pl->mu);
    return NULL;
  }
  w->held = pl->free_ix[--pl->nfree];
  for (;;) {
    size_t j = pl->next_job;
    out_block *b = &pl->block[w->held];
    if (pl->stop || j >= nj) break;
    pl->next_job = sweep_next_job(j, pl->o->nshard, nj);
    pthread_mutex_unlock(&pl->mu);
    if (sweep_job_run(pl->s, pl->p, j, &b, ws, &w->base, err, sizeof err)) {
      pthread_mutex_lock(&pl->mu);
      pool_fail(pl, err);
      break;
    }
    pthread_mutex_lock(&pl->mu);
  }
  /* give the block back; the writer stops when no worker is left */
  pl->free_ix[pl->nfree++] = w->held;
  pl->nactive--;
  pthread_cond_broadcast(&pl->ready_cv);
  pthread_cond_broadcast(&pl->free_cv);
  pthread_mutex_unlock(&pl->mu);
  sweep_workspaces_free(ws);
  return NULL;
}

/* write the tiles as the workers queue them, until all workers are done */
static int pool_write(pool *pl, out_file *f, progress *pr, sweep_stats *st) {
  char err[512];
  pthread_mutex_lock(&pl->mu);
  for (;;) {
    size_t ix;
    tile t;
    while (pl->nready == 0 && pl->nactive > 0 && !pl->stop)
      pthread_cond_wait(&pl->ready_cv, &pl->mu);
    if (pl->stop || pl->nready == 0) break;
    ix = pl->ready_ix[pl->ready_head];
    t = pl->ready_tile[pl->ready_head];
    pl->ready_head = (pl->ready_head + 1) % pl->nblock;
    pl->nready--;
    pthread_mutex_unlock(&pl->mu);
    /* the only thread that calls HDF5 */
    if (sweep_tile_write(f, &pl->block[ix], &t, err, sizeof err)) {
      pthread_mutex_lock(&pl->mu);
      pool_fail(pl, err);
      break;
    }
    sweep_tile_count(pl->s, &pl->block[ix], &t, st, pr);
    pthread_mutex_lock(&pl->mu);
    pl->free_ix[pl->nfree++] = ix;
    pthread_cond_signal(&pl->free_cv);
  }
  pthread_mutex_unlock(&pl->mu);
  return pl->stop ? -1 : 0;
}

int sweep_run_threads(const scene *s, const sweep_plan *p, out_file *f,
                      out_block *b, const sweep_opts *o, progress *pr,
                      sweep_stats *st, char *err, size_t errsz) {
  pool pl;
  worker *w = NULL;
  pthread_t *tid = NULL;
  sigset_t all, old;
  size_t i, nblock = (size_t)o->nthread + 2;
  int started = 0, rc = -1;

  memset(&pl, 0, sizeof pl);
  pl.s = s;
  pl.p = p;
  pl.o = o;
  pl.nblock = nblock;
  pl.next_job = o->shard;
  out_file_layout(f, &pl.layout);
  pl.block = calloc(nblock, sizeof *pl.block);
  pl.free_ix = calloc(nblock, sizeof *pl.free_ix);
  pl.ready_ix = calloc(nblock, sizeof *pl.ready_ix);
  pl.ready_tile = calloc(nblock, sizeof *pl.ready_tile);
  w = calloc((size_t)o->nthread, sizeof *w);
  tid = calloc((size_t)o->nthread, sizeof *tid);
  if (!pl.block || !pl.free_ix || !pl.ready_ix || !pl.ready_tile || !w ||
      !tid) {
    snprintf(err, errsz, "out of memory");
    goto done;
  }
  /* block 0 is the caller's; the others are allocated like it */
  pl.block[0] = *b;
  for (i = 1; i < nblock; i++)
    if (out_block_alloc(&pl.block[i], b->cases, b->points,
                        p->first.model.opt.effects)) {
      snprintf(err, errsz, "out of memory");
      goto done;
    } else
      pl.block[i].fields = b->fields;
  for (i = 0; i < nblock; i++) pl.free_ix[pl.nfree++] = i;
  if (pthread_mutex_init(&pl.mu, NULL) ||
      pthread_cond_init(&pl.ready_cv, NULL) ||
      pthread_cond_init(&pl.free_cv, NULL)) {
    snprintf(err, errsz, "cannot set up the threads");
    goto done;
  }

  /* workers take no signals: the handler runs on this thread */
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  for (started = 0; started < o->nthread; started++) {
    w[started].base.emit = worker_emit;
    w[started].pl = &pl;
    pthread_mutex_lock(&pl.mu);
    pl.nactive++;
    pthread_mutex_unlock(&pl.mu);
    if (pthread_create(&tid[started], NULL, worker_main, &w[started])) {
      pthread_mutex_lock(&pl.mu);
      pl.nactive--;
      pool_fail(&pl, "cannot start a thread");
      pthread_mutex_unlock(&pl.mu);
      break;
    }
  }
  pthread_sigmask(SIG_SETMASK, &old, NULL);

  rc = pool_write(&pl, f, pr, st);
  for (i = 0; i < (size_t)started; i++) pthread_join(tid[i], NULL);
  if (rc) snprintf(err, errsz, "%s", pl.err);
  pthread_cond_destroy(&pl.free_cv);
  pthread_cond_destroy(&pl.ready_cv);
  pthread_mutex_destroy(&pl.mu);

done:
  if (pl.block) {
    *b = pl.block[0];
    for (i = 1; i < nblock; i++) out_block_free(&pl.block[i]);
  }
  free(pl.block);
  free(pl.free_ix);
  free(pl.ready_ix);
  free(pl.ready_tile);
  free(w);
  free(tid);
  return rc;
}

int sweep_run_opts(const scene *s, const sweep_plan *p, out_file *f,
                   out_block *b, const sweep_opts *o, progress *pr,
                   sweep_stats *st, char *err, size_t errsz) {
  memset(st, 0, sizeof *st);
  if (o->nshard < 1 || o->shard >= o->nshard || o->nthread < 1) {
    snprintf(err, errsz, "bad shard %zu/%zu or thread count %d", o->shard,
             o->nshard, o->nthread);
    return -1;
  }
  return o->nthread == 1 ? sweep_run_serial(s, p, f, b, o, pr, st, err, errsz)
                         : sweep_run_threads(s, p, f, b, o, pr, st, err, errsz);
}

int sweep_run(const scene *s, const sweep_plan *p, out_file *f, out_block *b,
              progress *pr, sweep_stats *st, char *err, size_t errsz) {
  sweep_opts o = {1, 0, 1};
  return sweep_run_opts(s, p, f, b, &o, pr, st, err, errsz);
}
