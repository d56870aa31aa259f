/*
 * test_pool.c - the runner's worker pool (runner/exec/pool.h), compiled in:
 * every item of a job's stride is run once and every emitted slot written
 * once, with its own info, on the calling thread, whatever the threads; a
 * slot is never filled by two workers at a time; the first error of a run
 * or a write stops the run and is the one returned; each worker's state is
 * made and freed once.
 */
#include <pthread.h>
#include <time.h>

#include "testutil.h"

#include "../runner/exec/pool.c"

#define NITEM 97 /* items of the job: a prime, so strides cut it unevenly */
#define PARTS 3  /* slots each item emits */

/* a slot: what its filler wrote, checked by the writer */
typedef struct {
  size_t item;
  int part;
  int filling; /* 1 while a worker fills it */
} slot_t;

/* what describes a filled slot */
typedef struct {
  size_t item;
  int part;
} info_t;

typedef struct {
  pthread_t writer; /* the thread that calls pool_run */
  int written[NITEM][PARTS];
  int clash;                   /* a slot filled by two workers at a time */
  int mismatch;                /* a slot's content not its info's */
  int off_thread;              /* a write off the calling thread */
  size_t fail_run, fail_write; /* item whose run / write fails (NITEM: none) */
  int begun, ended;            /* worker states made and freed */
  pthread_mutex_t mu;
} job_t;

static void nap(void) {
  struct timespec ts = {0, 20000};
  nanosleep(&ts, NULL);
}

static void *begin(void *ctx) {
  job_t *J = ctx;
  pthread_mutex_lock(&J->mu);
  J->begun++;
  pthread_mutex_unlock(&J->mu);
  return malloc(16);
}

static void end(void *ctx, void *wctx) {
  job_t *J = ctx;
  assert_non_null(wctx);
  free(wctx);
  pthread_mutex_lock(&J->mu);
  J->ended++;
  pthread_mutex_unlock(&J->mu);
}

static int run(void *ctx, void *wctx, size_t i, pool_worker *w, char *err,
               size_t errsz) {
  job_t *J = ctx;
  slot_t *s = pool_slot(w);
  int part;
  (void)wctx;
  if (i == J->fail_run) {
    snprintf(err, errsz, "item %zu failed", i);
    return -1;
  }
  for (part = 0; part < PARTS; part++) {
    info_t info;
    pthread_mutex_lock(&J->mu);
    if (s->filling) J->clash = 1;
    s->filling = 1;
    pthread_mutex_unlock(&J->mu);
    s->item = i;
    s->part = part;
    nap();
    s->filling = 0;
    info.item = i;
    info.part = part;
    if (!(s = pool_emit(w, &info, err, errsz))) return -1;
  }
  return 0;
}

static int write_slot(void *ctx, void *slot, const void *info, char *err,
                      size_t errsz) {
  job_t *J = ctx;
  const slot_t *s = slot;
  const info_t *in = info;
  if (!pthread_equal(pthread_self(), J->writer)) J->off_thread = 1;
  if (s->item != in->item || s->part != in->part || s->filling) J->mismatch = 1;
  if (in->item == J->fail_write) {
    snprintf(err, errsz, "cannot write item %zu", in->item);
    return -1;
  }
  J->written[in->item][in->part]++;
  return 0;
}

/* pool_job.slot_make, slot_free of a plain slot */
static int plain_make(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)slot;
  (void)i;
  return 0;
}

static void plain_free(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)slot;
  (void)i;
}

/* run a job of stride `stride` from `first` on nthread threads */
static int run_job(job_t *J, int nthread, size_t first, size_t stride,
                   char *err, size_t errsz) {
  pool_job job;
  memset(&job, 0, sizeof job);
  job.ctx = J;
  job.nitem = NITEM;
  job.first = first;
  job.stride = stride;
  job.slot_size = sizeof(slot_t);
  job.slot_make = plain_make;
  job.slot_free = plain_free;
  job.info_size = sizeof(info_t);
  job.worker_begin = begin;
  job.worker_end = end;
  job.run = run;
  job.write = write_slot;
  J->writer = pthread_self();
  return pool_run(&job, nthread, err, errsz);
}

static void job_init(job_t *J) {
  memset(J, 0, sizeof *J);
  J->fail_run = J->fail_write = NITEM;
  pthread_mutex_init(&J->mu, NULL);
}

static void every_item_once(void **state) {
  static const int threads[] = {1, 2, 4, 7};
  static const size_t strides[][2] = {{0, 1}, {1, 3}, {5, 10}, {0, 200}};
  size_t t, q, i;
  (void)state;
  for (t = 0; t < sizeof threads / sizeof *threads; t++)
    for (q = 0; q < sizeof strides / sizeof *strides; q++) {
      job_t J;
      char err[256] = "";
      int part;
      job_init(&J);
      assert_int_equal(run_job(&J, threads[t], strides[q][0], strides[q][1],
                               err, sizeof err),
                       0);
      for (i = 0; i < NITEM; i++)
        for (part = 0; part < PARTS; part++)
          assert_int_equal(
              J.written[i][part],
              i >= strides[q][0] && (i - strides[q][0]) % strides[q][1] == 0);
      assert_false(J.clash);
      assert_false(J.mismatch);
      assert_false(J.off_thread);
      assert_int_equal(J.begun, threads[t]);
      assert_int_equal(J.ended, threads[t]);
      pthread_mutex_destroy(&J.mu);
    }
}

static void first_error_stops(void **state) {
  static const int threads[] = {1, 3};
  size_t t;
  (void)state;
  for (t = 0; t < 2; t++) {
    job_t J;
    char err[256] = "";
    job_init(&J);
    J.fail_run = 40;
    assert_int_equal(run_job(&J, threads[t], 0, 1, err, sizeof err), -1);
    assert_string_equal(err, "item 40 failed");
    assert_int_equal(J.written[40][0], 0);
    assert_int_equal(J.begun, J.ended);
    pthread_mutex_destroy(&J.mu);

    job_init(&J);
    J.fail_write = 13;
    assert_int_equal(run_job(&J, threads[t], 0, 1, err, sizeof err), -1);
    assert_string_equal(err, "cannot write item 13");
    /* on one thread nothing runs after the failed write */
    if (threads[t] == 1) assert_int_equal(J.written[14][0], 0);
    assert_int_equal(J.begun, J.ended);
    pthread_mutex_destroy(&J.mu);
  }
}

static void slots_and_bad_jobs(void **state) {
  job_t J;
  char err[256];
  (void)state;
  assert_int_equal(pool_nslot(1), 1);
  assert_int_equal(pool_nslot(4), 6);
  /* a shard's items: 5, 15, ..., 95; a stride that would wrap */
  assert_int_equal(pool_count(NITEM, 5, 10), 10);
  assert_int_equal(pool_count(NITEM, NITEM, 1), 0);
  assert_int_equal(pool_count(NITEM, 3, SIZE_MAX), 1);
  assert_int_equal(pool_next(3, 10, NITEM), 13);
  assert_int_equal(pool_next(3, SIZE_MAX, NITEM), NITEM);
  job_init(&J);
  assert_int_equal(run_job(&J, 0, 0, 1, err, sizeof err), -1);
  assert_non_null(strstr(err, "0 threads"));
  pthread_mutex_destroy(&J.mu);
}

/* the slots pool_run makes: calls to make and free each */
static int made[8], freed[8];
static size_t make_fails; /* the slot whose make fails (8: none) */

static int make_slot(void *ctx, void *slot, size_t i) {
  (void)ctx;
  assert_true(i < 8);
  made[i]++;
  /* zeroed when made */
  assert_int_equal(((slot_t *)slot)->filling, 0);
  return i == make_fails ? -1 : 0;
}

static void free_slot(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)slot;
  assert_true(i < 8);
  freed[i]++;
}

/* each slot is made and freed once, and every item runs; a slot that
   cannot be made stops the run before any item, with the caller's err,
   and every slot is freed (made or not) */
static void pool_made_slots(void **state) {
  static const int threads[] = {1, 3};
  size_t t, i;
  (void)state;
  for (t = 0; t < 4; t++) {
    job_t J;
    pool_job job;
    char err[256] = "caller's";
    size_t n = pool_nslot(threads[t % 2]);
    job_init(&J);
    memset(made, 0, sizeof made);
    memset(freed, 0, sizeof freed);
    make_fails = t < 2 ? 8 : n - 1;
    memset(&job, 0, sizeof job);
    job.ctx = &J;
    job.nitem = NITEM;
    job.stride = 1;
    job.slot_size = sizeof(slot_t);
    job.slot_make = make_slot;
    job.slot_free = free_slot;
    job.info_size = sizeof(info_t);
    job.run = run;
    job.write = write_slot;
    J.writer = pthread_self();
    assert_int_equal(pool_run(&job, threads[t % 2], err, sizeof err),
                     t < 2 ? 0 : -1);
    for (i = 0; i < 8; i++) {
      assert_int_equal(made[i], i < n);
      assert_int_equal(freed[i], i < n);
    }
    assert_int_equal(J.written[NITEM - 1][0], t < 2);
    assert_int_equal(J.written[0][0], t < 2);
    if (t >= 2) assert_string_equal(err, "caller's");
    assert_false(J.clash);
    pthread_mutex_destroy(&J.mu);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(every_item_once),
      cmocka_unit_test(first_error_stops),
      cmocka_unit_test(slots_and_bad_jobs),
      cmocka_unit_test(pool_made_slots),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
