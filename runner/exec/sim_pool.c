/*
 * sim_pool.c - rps3-run -j N on a simulated scene: N worker threads take
 * the cases in turn and simulate them window by window (sim_run.c); the
 * calling thread writes each window as it comes.  The windows circulate in
 * a pool of N + 2 tiles, so memory is bounded whatever the sweep; a case
 * depends on nothing but its scene, so the file does not depend on N.
 */
#include "sim_run.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  sim_sink base; /* the workers' sink: queue a window, take a tile */
  pthread_mutex_t mu;
  pthread_cond_t cv; /* signalled on every change below */
  const scene *s;
  sim_tile *tiles; /* the pool */
  sim_tile **full; /* windows to write, a ring of ntile */
  sim_tile **idle; /* tiles to fill, a stack */
  size_t ntile, head, nfull, nidle;
  size_t next_case; /* the next case a worker takes */
  int nworker_done;
  int stop;      /* an error: everyone stops */
  char err[768]; /* a worker's error */
} pool;

/* a tile to fill, waiting for one; NULL when stopped (mu held) */
static sim_tile *take_idle(pool *P) {
  while (P->nidle == 0 && !P->stop) pthread_cond_wait(&P->cv, &P->mu);
  return P->stop ? NULL : P->idle[--P->nidle];
}

/* the workers' sink: the window goes to the writer, a tile comes back */
static sim_tile *pool_put(sim_sink *k, sim_tile *t) {
  pool *P = (pool *)(void *)k;
  sim_tile *next;
  pthread_mutex_lock(&P->mu);
  P->full[(P->head + P->nfull++) % P->ntile] = t;
  pthread_cond_broadcast(&P->cv);
  next = take_idle(P);
  pthread_mutex_unlock(&P->mu);
  return next;
}

static void *worker(void *arg) {
  pool *P = arg;
  sim_tile *t;
  char err[768];
  pthread_mutex_lock(&P->mu);
  t = take_idle(P);
  pthread_mutex_unlock(&P->mu);
  while (t) {
    size_t i;
    pthread_mutex_lock(&P->mu);
    i = P->next_case;
    if (P->stop || i >= P->s->ncase) {
      P->idle[P->nidle++] = t;
      pthread_mutex_unlock(&P->mu);
      break;
    }
    P->next_case++;
    pthread_mutex_unlock(&P->mu);
    err[0] = '\0';
    t = sim_run_case(P->s, i, (size_t)-1, t, &P->base, err, sizeof err);
    if (!t && err[0]) {
      /* the case itself failed to run (memory): stop everyone */
      pthread_mutex_lock(&P->mu);
      if (!P->stop) snprintf(P->err, sizeof P->err, "%s", err);
      P->stop = 1;
      pthread_mutex_unlock(&P->mu);
    }
  }
  pthread_mutex_lock(&P->mu);
  P->nworker_done++;
  pthread_cond_broadcast(&P->cv);
  pthread_mutex_unlock(&P->mu);
  return NULL;
}

/* write one window (and the case's values with its last one); 0 or -1 */
static int write_tile(sim_file *f, const sim_tile *t, int common, char *err,
                      size_t errsz) {
  if (t->nk > 0 && sim_file_window(f, &t->w, t->c, t->k0, t->nk,
                                   common ? NULL : t->times, err, errsz))
    return -1;
  return t->last ? sim_file_case(f, &t->v, t->c, err, errsz) : 0;
}

/* the calling thread: write the windows as they come until every case is
   written or an error stops the run; 0 or -1 with err */
static int writer(pool *P, const sim_plan *p, sim_file *f, int nthread,
                  progress *pr, size_t *nfailed, char *err, size_t errsz) {
  size_t done = 0, points = 0;
  int rc = 0;
  pthread_mutex_lock(&P->mu);
  while (done < P->s->ncase) {
    sim_tile *t;
    while (P->nfull == 0 && !P->stop && P->nworker_done < nthread)
      pthread_cond_wait(&P->cv, &P->mu);
    if (P->nfull == 0) break; /* stopped, or the workers are gone */
    t = P->full[P->head];
    P->head = (P->head + 1) % P->ntile;
    P->nfull--;
    pthread_mutex_unlock(&P->mu);
    rc = write_tile(f, t, p->common, err, errsz);
    points += t->nk;
    if (rc == 0 && t->last) {
      done++;
      if (t->v.status != RPS3_OK) {
        ++*nfailed;
        sim_failure(P->s, pr, t);
      }
      progress_update(pr, done, points);
    }
    pthread_mutex_lock(&P->mu);
    P->idle[P->nidle++] = t;
    if (rc) P->stop = 1;
    pthread_cond_broadcast(&P->cv);
    if (rc) break;
  }
  /* idle workers waiting for a tile or a case end now */
  P->stop = 1;
  pthread_cond_broadcast(&P->cv);
  if (rc == 0 && done < P->s->ncase) {
    snprintf(err, errsz, "%s", P->err[0] ? P->err : "a worker stopped");
    rc = -1;
  }
  pthread_mutex_unlock(&P->mu);
  return rc;
}

int sim_pool_run(const scene *s, const sim_plan *p, sim_file *f, int nthread,
                 progress *pr, size_t *nfailed, char *err, size_t errsz) {
  pool P;
  pthread_t *th = calloc((size_t)nthread, sizeof *th);
  size_t i, points = p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW;
  int n, started = 0, rc = -1;
  memset(&P, 0, sizeof P);
  P.base.put = pool_put;
  P.s = s;
  P.ntile = (size_t)nthread + 2;
  P.tiles = calloc(P.ntile, sizeof *P.tiles);
  P.full = calloc(P.ntile, sizeof *P.full);
  P.idle = calloc(P.ntile, sizeof *P.idle);
  snprintf(err, errsz, "out of memory");
  if (!th || !P.tiles || !P.full || !P.idle) goto done;
  for (i = 0; i < P.ntile; i++) {
    if (sim_tile_alloc(&P.tiles[i], points)) goto done;
    P.idle[P.nidle++] = &P.tiles[i];
  }
  if (pthread_mutex_init(&P.mu, NULL)) goto done;
  if (pthread_cond_init(&P.cv, NULL)) {
    pthread_mutex_destroy(&P.mu);
    goto done;
  }
  for (n = 0; n < nthread; n++)
    if (pthread_create(&th[started], NULL, worker, &P) == 0) started++;
  if (started == 0) {
    snprintf(err, errsz, "cannot start a thread");
  } else {
    err[0] = '\0';
    rc = writer(&P, p, f, started, pr, nfailed, err, errsz);
  }
  for (n = 0; n < started; n++) pthread_join(th[n], NULL);
  pthread_cond_destroy(&P.cv);
  pthread_mutex_destroy(&P.mu);
done:
  if (P.tiles)
    for (i = 0; i < P.ntile; i++) sim_tile_free(&P.tiles[i]);
  free(P.tiles);
  free(P.full);
  free(P.idle);
  free(th);
  return rc;
}
