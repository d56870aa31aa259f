/*
 * sim_shim.c - a flat C entry point for the MuJoCo cross-check of the
 * simulation (tests/test_sim_mujoco.py): rps3_sim driven open loop by a
 * table of forces held over fixed intervals, the same forces MuJoCo gets.
 * Built by the test against include/rps3.h and build/librps3.so.
 *
 * par: shim_model.h (RPS3_SHIM_NPAR numbers), + vreg last.
 *
 * The general bodies' case (rps3_shim_general_forces, rps3_shim_sim_general):
 * par's geometry and g, then body (RPS3_NBODY x 10: mass, com x3, inertia
 * Ixx Ixy Ixz Iyy Iyz Izz, in the order of rps3_model.std: platform,
 * cylinder 1, piston 1, ...) and fric (3 x 4: each leg's pin viscous and
 * Coulomb, prismatic viscous and Coulomb, exact sign).
 */
#include <stdio.h>
#include <string.h>

#include "rps3.h"
#include "shim_model.h"

int rps3_shim_sim(const double *par, int effects, int integrator, double h,
                  double tol, const double *pose0, const double *dpose0,
                  int n, double dt, const double *F, double *l, double *T,
                  double *P, double *W, char *err, int errsz);

int rps3_shim_general_forces(const double *par, const double *body,
                             const double *fric, int effects, int n,
                             const double *pose, const double *dpose,
                             const double *ddpose, double *F, char *err,
                             int errsz);
int rps3_shim_sim_general(const double *par, const double *body,
                          const double *fric, int effects, int integrator,
                          double h, double tol, const double *pose0,
                          const double *dpose0, int n, double dt,
                          const double *F, double *l, double *T, double *P,
                          double *W, char *err, int errsz);

/* the general model of par's geometry and g, body's bodies and fric's
   friction (see the top), initialised: its status, the message in err */
static int general_model(rps3_model *m, const double *par, const double *body,
                         const double *fric, int effects, char *err,
                         int errsz) {
  rps3_check chk;
  int i, k, st;
  shim_model(m, par, effects);
  m->bodies = RPS3_BODIES_GENERAL;
  for (i = 0; i < RPS3_NBODY; i++) {
    rps3_body *b = i == 0        ? &m->platform
                   : (i - 1) % 2 ? &m->leg[(i - 1) / 2].piston
                                 : &m->leg[(i - 1) / 2].cylinder;
    b->mass = body[10 * i];
    for (k = 0; k < 3; k++) b->com[k] = body[10 * i + 1 + k];
    for (k = 0; k < 6; k++) b->inertia[k] = body[10 * i + 4 + k];
  }
  for (i = 0; i < 3; i++) {
    m->leg[i].pin.viscous = fric[4 * i];
    m->leg[i].pin.coulomb = fric[4 * i + 1];
    m->leg[i].prismatic.viscous = fric[4 * i + 2];
    m->leg[i].prismatic.coulomb = fric[4 * i + 3];
  }
  st = rps3_model_init(m, &chk);
  if (st != RPS3_OK && err != NULL && errsz > 0)
    snprintf(err, (size_t)errsz, "%s", chk.msg);
  return st;
}

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

/* m's run from (pose0, dpose0) under the force table F: l, T, P, W (work
   of the forces and friction) at the n + 1 interval ends.  Returns 0, or
   the status of the set-up or of the run (message in err). */
static int run(const rps3_model *m, int integrator, double h, double tol,
               const double *pose0, const double *dpose0, int n, double dt,
               const double *F, double *l, double *T, double *P, double *W,
               char *err, int errsz) {
  rps3_check chk;
  rps3_sim_options o;
  rps3_sim *s = NULL;
  rps3_controller c;
  table tb;
  int k, st;
  rps3_sim_options_default(&o);
  o.integrator = (rps3_integrator)integrator;
  o.h = h;
  o.epsabs = o.epsrel = tol;
  st = rps3_sim_alloc(m, &o, &s, &chk);
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

/* the paper's bodies of par (see the top) */
int rps3_shim_sim(const double *par, int effects, int integrator, double h,
                  double tol, const double *pose0, const double *dpose0,
                  int n, double dt, const double *F, double *l, double *T,
                  double *P, double *W, char *err, int errsz) {
  rps3_model m;
  rps3_check chk;
  int st;
  shim_model(&m, par, effects);
  m.friction.vreg = par[RPS3_SHIM_NPAR];
  st = rps3_model_init(&m, &chk);
  if (st != RPS3_OK) {
    if (err != NULL && errsz > 0) snprintf(err, (size_t)errsz, "%s", chk.msg);
    return st;
  }
  return run(&m, integrator, h, tol, pose0, dpose0, n, dt, F, l, T, P, W, err,
             errsz);
}

/* the general bodies' run (see the top) */
int rps3_shim_sim_general(const double *par, const double *body,
                          const double *fric, int effects, int integrator,
                          double h, double tol, const double *pose0,
                          const double *dpose0, int n, double dt,
                          const double *F, double *l, double *T, double *P,
                          double *W, char *err, int errsz) {
  rps3_model m;
  int st = general_model(&m, par, body, fric, effects, err, errsz);
  if (st != RPS3_OK) return st;
  return run(&m, integrator, h, tol, pose0, dpose0, n, dt, F, l, T, P, W, err,
             errsz);
}

/* F (n x 3): the general model's inverse dynamics of the n motions */
int rps3_shim_general_forces(const double *par, const double *body,
                             const double *fric, int effects, int n,
                             const double *pose, const double *dpose,
                             const double *ddpose, double *F, char *err,
                             int errsz) {
  rps3_model m;
  rps3_data *d = NULL;
  int k, st = general_model(&m, par, body, fric, effects, err, errsz);
  if (st != RPS3_OK) return st;
  st = rps3_data_alloc(&m, &d);
  if (st != RPS3_OK) return st;
  for (k = 0; k < n && st == RPS3_OK; k++) {
    memcpy(d->pose, pose + 3 * k, sizeof d->pose);
    memcpy(d->dpose, dpose + 3 * k, sizeof d->dpose);
    memcpy(d->ddpose, ddpose + 3 * k, sizeof d->ddpose);
    st = rps3_inverse(&m, d);
    if (st == RPS3_OK) memcpy(F + 3 * k, d->F, sizeof d->F);
  }
  if (st != RPS3_OK && err != NULL && errsz > 0)
    snprintf(err, (size_t)errsz, "point %d: %s", k - 1, d->err.msg);
  rps3_data_free(d);
  return st;
}
