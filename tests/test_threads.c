/*
 * test_threads.c - one rps3_data per thread is all it takes: NTHREAD
 * threads, started together on one shared const model per configuration,
 * each with its own workspace, give results bitwise identical (memcmp of
 * the doubles) to one thread alone.  Every effect is on (each one's share
 * F_effect is compared too), for both formulations and for the closed-form
 * and the warm multiroot theta.
 */
#include <pthread.h>

#include "testutil.h"

#define NTHREAD 4
#define NPOINT 4000
#define NCONF 4

/* everything a point yields, as doubles, in a fixed order */
typedef struct {
  double status, niter;
  double theta[3], l[3], c[3], rot[3][3], b[3][3];
  double dl[3], dtheta[3], vc[3], omega[3];
  double ddl[3], ddtheta[3], ac[3], domega[3];
  double F[3], F_effect[RPS3_NEFFECT][3], lambda[3];
  double cond, power, dTdt, dPdt, friction_power, energy_residual,
      energy_scale;
} record;

static void save(record *r, int status, const rps3_data *d) {
  memset(r, 0, sizeof(*r));
  r->status = (double)status;
  r->niter = (double)d->solve_niter;
  memcpy(r->theta, d->theta, sizeof(r->theta));
  memcpy(r->l, d->l, sizeof(r->l));
  memcpy(r->c, d->c, sizeof(r->c));
  memcpy(r->rot, d->rot, sizeof(r->rot));
  memcpy(r->b, d->b, sizeof(r->b));
  memcpy(r->dl, d->dl, sizeof(r->dl));
  memcpy(r->dtheta, d->dtheta, sizeof(r->dtheta));
  memcpy(r->vc, d->vc, sizeof(r->vc));
  memcpy(r->omega, d->omega, sizeof(r->omega));
  memcpy(r->ddl, d->ddl, sizeof(r->ddl));
  memcpy(r->ddtheta, d->ddtheta, sizeof(r->ddtheta));
  memcpy(r->ac, d->ac, sizeof(r->ac));
  memcpy(r->domega, d->domega, sizeof(r->domega));
  memcpy(r->F, d->F, sizeof(r->F));
  memcpy(r->F_effect, d->F_effect, sizeof(r->F_effect));
  memcpy(r->lambda, d->lambda, sizeof(r->lambda));
  r->cond = d->cond;
  r->power = d->power;
  r->dTdt = d->dTdt;
  r->dPdt = d->dPdt;
  r->friction_power = d->friction_power;
  r->energy_residual = d->energy_residual;
  r->energy_scale = d->energy_scale;
}

/* the shared, read-only inputs */
static rps3_model models[NCONF];
static rps3_traj traj;

/* configuration k: bit 0 the method, bit 1 the theta route */
static void make_models(void) {
  uint64_t seed = 0x5eed7123ull;
  int k;
  for (k = 0; k < NCONF; k++) {
    model_entropy(&models[k]); /* all six effects, payload, friction */
    models[k].opt.method = (k & 1) ? RPS3_NEWTON_EULER : RPS3_LAGRANGE;
    models[k].opt.theta =
        (k & 2) ? RPS3_THETA_MULTIROOT : RPS3_THETA_CLOSED_FORM;
    models[k].opt.warm_start = 1;
    assert_int_equal(rps3_model_init(&models[k], NULL), RPS3_OK);
  }
  traj_random(&traj, &seed);
  assert_int_equal(rps3_traj_check(&models[0], &traj, NULL), RPS3_OK);
}

/* the whole trajectory for every configuration, with a fresh data each;
   returns the number of points that did not return RPS3_OK */
static int run_all(record *out) {
  double T = rps3_traj_duration(&traj);
  int k, p, bad = 0;
  for (k = 0; k < NCONF; k++) {
    rps3_data *d = NULL;
    if (rps3_data_alloc(&models[k], &d) != RPS3_OK) return -1;
    for (p = 0; p < NPOINT; p++) {
      double t = T * (double)p / (double)(NPOINT - 1);
      int status = rps3_traj_eval(&models[k], &traj, t, d->pose, d->dpose,
                                  d->ddpose);
      if (status == RPS3_OK) status = rps3_inverse(&models[k], d);
      if (status != RPS3_OK) bad++;
      save(&out[k * NPOINT + p], status, d);
    }
    rps3_data_free(d);
  }
  return bad;
}

typedef struct {
  pthread_barrier_t *start;
  record *out;
  int bad;
} worker_arg;

static void *worker(void *p) {
  worker_arg *a = (worker_arg *)p;
  pthread_barrier_wait(a->start); /* all threads compute at once */
  a->bad = run_all(a->out);
  return NULL;
}

static void threads_match_one_thread(void **state) {
  static record ref[NCONF * NPOINT], res[NTHREAD][NCONF * NPOINT];
  pthread_t tid[NTHREAD];
  worker_arg arg[NTHREAD];
  pthread_barrier_t start;
  int i, k, p;
  (void)state;
  make_models();

  /* one thread: the reference */
  assert_int_equal(run_all(ref), 0);

  /* NTHREAD threads at once, each with its own data */
  assert_int_equal(pthread_barrier_init(&start, NULL, NTHREAD), 0);
  for (i = 0; i < NTHREAD; i++) {
    arg[i].start = &start;
    arg[i].out = res[i];
    arg[i].bad = -2;
    assert_int_equal(pthread_create(&tid[i], NULL, worker, &arg[i]), 0);
  }
  for (i = 0; i < NTHREAD; i++) assert_int_equal(pthread_join(tid[i], NULL), 0);
  pthread_barrier_destroy(&start);

  for (i = 0; i < NTHREAD; i++) {
    assert_int_equal(arg[i].bad, 0);
    for (k = 0; k < NCONF; k++) {
      for (p = 0; p < NPOINT; p++) {
        const record *a = &ref[k * NPOINT + p], *b = &res[i][k * NPOINT + p];
        if (memcmp(a, b, sizeof(*a)) != 0) {
          print_error("thread %d, configuration %d (%s, %s), point %d "
                      "differs from the single-thread run\n",
                      i, k, (k & 1) ? "Newton-Euler" : "Lagrange",
                      (k & 2) ? "multiroot" : "closed form", p);
          fail();
        }
      }
    }
  }
  /* the multiroot runs did iterate, and the forces are not trivial */
  assert_true(ref[3 * NPOINT + NPOINT / 2].niter > 0);
  assert_true(fabs(ref[NPOINT / 2].F_effect[4][0]) > 0);
  print_message("%d threads x %d configurations x %d points: bitwise "
                "identical to one thread\n", NTHREAD, NCONF, NPOINT);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(threads_match_one_thread),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
