/*
 * pool.c - see pool.h.  The slots are each free, being filled by a worker,
 * queued for writing (first in, first out) or being written.  One thread
 * has one slot (it computes and writes in turn); on more, each worker holds
 * one slot at a time, so with nthread + 2 slots the writer always has one
 * to give back and no one waits forever.
 */
#include "pool.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define NO_SLOT ((size_t)-1)

typedef struct {
  const pool_job *job;
  int threaded;
  unsigned char *mem; /* the slots, job->slot_size bytes each */
  pthread_mutex_t mu;
  pthread_cond_t ready_cv; /* a slot is ready, or a worker ended */
  pthread_cond_t free_cv;  /* a slot is free, or the run stops */
  size_t nslot;
  size_t *free_ix; /* [nslot] stack of free slots */
  size_t nfree;
  size_t *ready_ix;          /* [nslot] ring of filled slots ... */
  unsigned char *ready_info; /* [nslot][info_size] ... and their infos */
  size_t ready_head, nready;
  size_t next;   /* the next item to take */
  int nactive;   /* workers still running */
  int stop;      /* 1: a callback failed */
  char err[768]; /* the first failure */
} pool;

struct pool_worker {
  pool *P;
  size_t held; /* the slot this worker fills */
  void *wctx;  /* job->worker_begin's state */
};

/* slots of a run on nthread threads */
static size_t pool_nslot(int nthread) {
  return nthread > 1 ? (size_t)nthread + 2 : 1;
}

static void *slot_at(const pool *P, size_t i) {
  return P->mem + i * P->job->slot_size;
}

void *pool_slot(pool_worker *w) { return slot_at(w->P, w->held); }

int pool_threaded(const pool_worker *w) { return w->P->threaded; }

size_t pool_next(size_t i, size_t stride, size_t nitem) {
  return nitem - i > stride ? i + stride : nitem;
}

size_t pool_count(size_t nitem, size_t first, size_t stride) {
  /* no sum that can wrap: stride may be as large as SIZE_MAX */
  return nitem > first ? 1 + (nitem - first - 1) / stride : 0;
}

/* stop the run with this error (the first one wins); mu held */
static void pool_fail(pool *P, const char *msg) {
  if (!P->stop) snprintf(P->err, sizeof P->err, "%s", msg);
  P->stop = 1;
  pthread_cond_broadcast(&P->free_cv);
  pthread_cond_broadcast(&P->ready_cv);
}

/* a free slot for w, waiting for one; -1 when the run stops (mu held) */
static int take_free(pool *P, pool_worker *w) {
  while (P->nfree == 0 && !P->stop) pthread_cond_wait(&P->free_cv, &P->mu);
  if (P->stop) return -1;
  w->held = P->free_ix[--P->nfree];
  return 0;
}

void *pool_emit(pool_worker *w, const void *info, char *err, size_t errsz) {
  pool *P = w->P;
  const pool_job *J = P->job;
  size_t r;
  /* one thread: write it now and fill the same slot again */
  if (!P->threaded)
    return J->write(J->ctx, slot_at(P, w->held), info, err, errsz)
               ? NULL
               : slot_at(P, w->held);
  pthread_mutex_lock(&P->mu);
  r = (P->ready_head + P->nready) % P->nslot;
  P->ready_ix[r] = w->held;
  if (J->info_size)
    memcpy(P->ready_info + r * J->info_size, info, J->info_size);
  P->nready++;
  w->held = NO_SLOT;
  pthread_cond_signal(&P->ready_cv);
  if (take_free(P, w)) {
    pthread_mutex_unlock(&P->mu);
    snprintf(err, errsz, "stopped");
    return NULL;
  }
  pthread_mutex_unlock(&P->mu);
  return slot_at(P, w->held);
}

/* a worker (or, on one thread, the calling thread): items in turn until
   none is left or the run stops */
static void *worker_main(void *arg) {
  pool_worker *w = arg;
  pool *P = w->P;
  const pool_job *J = P->job;
  char err[768];
  if (J->worker_begin && !(w->wctx = J->worker_begin(J->ctx))) {
    pthread_mutex_lock(&P->mu);
    pool_fail(P, "out of memory");
  } else {
    pthread_mutex_lock(&P->mu);
    /* a slot to fill; a worker that starts late may find them all queued
       for writing */
    if (take_free(P, w) == 0)
      for (;;) {
        size_t i = P->next;
        int rc;
        if (P->stop || i >= J->nitem) break;
        P->next = pool_next(i, J->stride, J->nitem);
        pthread_mutex_unlock(&P->mu);
        err[0] = '\0';
        rc = J->run(J->ctx, w->wctx, i, w, err, sizeof err);
        pthread_mutex_lock(&P->mu);
        if (rc) {
          pool_fail(P, err[0] ? err : "a worker stopped");
          break;
        }
      }
  }
  /* give the slot back (none when pool_emit stopped) */
  if (w->held != NO_SLOT) P->free_ix[P->nfree++] = w->held;
  /* the writer stops when no worker is left */
  P->nactive--;
  pthread_cond_broadcast(&P->ready_cv);
  pthread_cond_broadcast(&P->free_cv);
  pthread_mutex_unlock(&P->mu);
  if (J->worker_end) J->worker_end(J->ctx, w->wctx);
  return NULL;
}

/* the calling thread: write the slots as the workers queue them, until
   every worker is done or the run stops */
static void pool_write(pool *P) {
  const pool_job *J = P->job;
  unsigned char info[POOL_INFO_MAX];
  char err[768];
  pthread_mutex_lock(&P->mu);
  for (;;) {
    size_t ix;
    int rc;
    while (P->nready == 0 && P->nactive > 0 && !P->stop)
      pthread_cond_wait(&P->ready_cv, &P->mu);
    if (P->stop || P->nready == 0) break;
    ix = P->ready_ix[P->ready_head];
    if (J->info_size)
      memcpy(info, P->ready_info + P->ready_head * J->info_size, J->info_size);
    P->ready_head = (P->ready_head + 1) % P->nslot;
    P->nready--;
    pthread_mutex_unlock(&P->mu);
    err[0] = '\0';
    rc = J->write(J->ctx, slot_at(P, ix), info, err, sizeof err);
    pthread_mutex_lock(&P->mu);
    if (rc) {
      pool_fail(P, err);
      break;
    }
    P->free_ix[P->nfree++] = ix;
    pthread_cond_signal(&P->free_cv);
  }
  pthread_mutex_unlock(&P->mu);
}

/* the workers (started with the signals blocked: the handlers run on the
   calling thread), the writer on this thread, then the join */
static void run_threads(pool *P, int nthread) {
  pool_worker *w = calloc((size_t)nthread, sizeof *w);
  pthread_t *tid = calloc((size_t)nthread, sizeof *tid);
  sigset_t all, old;
  int started;
  pthread_mutex_lock(&P->mu);
  if (!w || !tid) pool_fail(P, "out of memory");
  pthread_mutex_unlock(&P->mu);
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  for (started = 0; w && tid && started < nthread; started++) {
    w[started].P = P;
    w[started].held = NO_SLOT;
    pthread_mutex_lock(&P->mu);
    P->nactive++;
    if (pthread_create(&tid[started], NULL, worker_main, &w[started])) {
      P->nactive--;
      pool_fail(P, "cannot start a thread");
      pthread_mutex_unlock(&P->mu);
      break;
    }
    pthread_mutex_unlock(&P->mu);
  }
  pthread_sigmask(SIG_SETMASK, &old, NULL);
  pool_write(P);
  while (started > 0) pthread_join(tid[--started], NULL);
  free(w);
  free(tid);
}

/* pool_run with the slots at mem: on this thread, or the workers and the
   writer */
static int pool_start(const pool_job *job, unsigned char *mem, int nthread,
                      char *err, size_t errsz) {
  pool P;
  pool_worker w = {NULL, NO_SLOT, NULL};
  size_t i;
  int rc = -1;
  memset(&P, 0, sizeof P);
  P.job = job;
  P.mem = mem;
  P.threaded = nthread > 1;
  P.next = job->first;
  P.nslot = pool_nslot(nthread);
  /* the free stack, the ready ring and its infos in one block */
  if (!(P.free_ix = calloc(P.nslot, 2 * sizeof(size_t) + job->info_size)))
    snprintf(err, errsz, "out of memory");
  else if (pthread_mutex_init(&P.mu, NULL) ||
           pthread_cond_init(&P.ready_cv, NULL) ||
           pthread_cond_init(&P.free_cv, NULL))
    snprintf(err, errsz, "cannot set up the threads");
  else {
    P.ready_ix = P.free_ix + P.nslot;
    P.ready_info = (unsigned char *)(P.ready_ix + P.nslot);
    for (i = 0; i < P.nslot; i++) P.free_ix[P.nfree++] = i;
    w.P = &P;
    P.nactive = !P.threaded;
    if (P.threaded)
      run_threads(&P, nthread);
    else
      worker_main(&w);
    if (P.stop) snprintf(err, errsz, "%s", P.err);
    rc = P.stop ? -1 : 0;
    pthread_cond_destroy(&P.free_cv);
    pthread_cond_destroy(&P.ready_cv);
    pthread_mutex_destroy(&P.mu);
  }
  free(P.free_ix);
  return rc;
}

int pool_run(const pool_job *job, int nthread, char *err, size_t errsz) {
  size_t i, n = pool_nslot(nthread);
  unsigned char *mem = calloc(n, job->slot_size);
  int rc = -1;
  if (job->info_size > POOL_INFO_MAX || nthread < 1) {
    snprintf(err, errsz, "bad pool: %zu bytes of info, %d threads",
             job->info_size, nthread);
    n = 0;
  }
  for (i = 0; mem && i < n; i++)
    if (job->slot_make(job->ctx, mem + i * job->slot_size, i)) break;
  if (mem && n > 0 && i == n) rc = pool_start(job, mem, nthread, err, errsz);
  for (i = 0; mem && i < n; i++)
    job->slot_free(job->ctx, mem + i * job->slot_size, i);
  free(mem);
  return rc;
}

int pool_cores(int nthread, int say) {
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (cores < 1 || nthread <= cores) return nthread;
  if (say)
    fprintf(stderr,
            "rps3-run: warning: -j %d on %ld core%s: computing on %ld "
            "thread%s\n",
            nthread, cores, cores == 1 ? "" : "s", cores,
            cores == 1 ? "" : "s");
  return (int)cores;
}
