/*
 * sim_shim.c - a flat C entry point for the MuJoCo cross-check of the
 * simulation (tests/test_sim_mujoco.py): rps3_sim driven open loop by a
 * table of forces held over fixed intervals, the same forces MuJoCo gets.
 * Built by the test against include/rps3.h and build/librps3.so.
 *
 * par: shim_model.h (RPS3_SHIM_NPAR numbers), + vreg last.
 */
#include <stdio.h>
#include <string.h>

#include "rps3.h"
#include "shim_model.h"

int rps3_shim_sim(const double *par, int effects, int integrator, double h,
                  double tol, const double *pose0, const double *dpose0,
                  int n, double dt, const double *F, double *l, double *T,
                  double *P, double *W, char *err, int errsz);

/* the force table, one row per interval of dt (zero-order hold) */
typedef struct {
  const double *F;
  int n;
  double dt;
} table;

static int from_table(void *state, double t, const double l[3],
                      const double dl[3], double F[3]) {
  const table *tb = (const table *)state;
  int k = (int)(t / tb->dt + 0.5);
  (void)l;
  (void)dl;
  if (k >= tb->n) k = tb->n - 1;
  memcpy(F, tb->F + 3 * k, 3 * sizeof(double));
  return RPS3_OK;
}

/* l, T, P, W (work of the forces): n + 1 samples at the interval ends.
   Returns 0, or the status of the set-up or of the run (message in err). */
int rps3_shim_sim(const double *par, int effects, int integrator, double h,
                  double tol, const double *pose0, const double *dpose0,
                  int n, double dt, const double *F, double *l, double *T,
                  double *P, double *W, char *err, int errsz) {
  rps3_model m;
  rps3_check chk;
  rps3_sim_options o;
  rps3_sim *s = NULL;
  rps3_controller c;
  table tb;
  int k, st;
  shim_model(&m, par, effects);
  m.friction.vreg = par[RPS3_SHIM_NPAR];
  st = rps3_model_init(&m, &chk);
  if (st != RPS3_OK) {
    if (err != NULL && errsz > 0) snprintf(err, (size_t)errsz, "%s", chk.msg);
    return st;
  }
  rps3_sim_options_default(&o);
  o.integrator = (rps3_integrator)integrator;
  o.h = h;
  o.epsabs = o.epsrel = tol;
  st = rps3_sim_alloc(&m, &o, &s, &chk);
  if (st != RPS3_OK) {
    if (err != NULL && errsz > 0) snprintf(err, (size_t)errsz, "%s", chk.msg);
    return st;
  }
  tb.F = F;
  tb.n = n;
  tb.dt = dt;
  memset(&c, 0, sizeof(c)); /* no capabilities */
  c.fn = from_table;
  c.state = &tb;
  c.rate = 1.0 / dt;
  st = rps3_sim_start(s, 0.0, pose0, dpose0);
  for (k = 0; k <= n && st == RPS3_OK; k++) {
    if (k > 0) st = rps3_sim_advance(s, &c, k * dt);
    if (st != RPS3_OK) break;
    memcpy(l + 3 * k, rps3_sim_now(s)->y, 3 * sizeof(double));
    T[k] = rps3_sim_now(s)->T;
    P[k] = rps3_sim_now(s)->P;
    W[k] = rps3_sim_now(s)->y[6] + rps3_sim_now(s)->y[7];
  }
  if (st != RPS3_OK) {
    strncpy(err, rps3_sim_data(s)->err.msg, (size_t)errsz - 1);
    err[errsz - 1] = '\0';
  }
  rps3_sim_free(s);
  return st;
}
