/*
 * study_points.c - rps3-study's trajectories and configurations, and one
 * point computed by a configuration's route (study.h).
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "study.h"

double study_now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

double study_median(double *v, int n) {
  gsl_sort(v, 1, (size_t)n);
  return gsl_stats_median_from_sorted_data(v, 1, (size_t)n);
}

const char *const study_traj_name[NTRAJ] = {"helix", "sine_edge"};
const char *const study_traj_doc =
    "helix: Table II (r* = 0.266 mm, h = 30.48 mm, T* = 10 s, t_a = 1 s); "
    "sine_edge: alpha = pi sin(2 pi t), beta = 0.6 + 0.2 sin(2 pi 2.3 t), "
    "z_c = 0.28 + 0.03 sin(2 pi 1.7 t) m over 2 s: up to 20 rad/s, beta up to "
    "0.8 rad, condition number up to 4e2 near the singular surface";

/* sine_edge, as study_traj_doc says */
static const rps3_sine SINE_EDGE = {
    {0.0, 0.6, 0.28}, {PI, 0.2, 0.03}, {1.0, 2.3, 1.7}, {0.0, 0.0, 0.0}, 2.0};

void study_traj_sine(rps3_traj *tr, const rps3_sine *sine) {
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_SINE;
  tr->sine = *sine;
}

void study_traj_make(int k, rps3_traj *tr) {
  if (k == 0)
    rps3_traj_default(tr);
  else
    study_traj_sine(tr, &SINE_EDGE);
}

/* (2)-(7), (39) from the rotation Rz(a) Ry(b) Rz(-a), the centre (3)-(4)
   and b_i = c + rot r_i */
void study_ik_long(const rps3_model *m, const double pose[3],
                   long double theta[3]) {
  long double a = (long double)pose[0], b = (long double)pose[1];
  long double z = (long double)pose[2];
  long double ca = cosl(a), sa = sinl(a), cb = cosl(b), sb = sinl(b);
  long double r = (long double)m->rho * (long double)m->R;
  long double R = (long double)m->R;
  long double rot[3][3], c[3];
  long double s3 = sqrtl(3.0L);
  int i;
  /* Rz(a) Ry(b) Rz(-a) */
  rot[0][0] = ca * ca * cb + sa * sa;
  rot[0][1] = ca * sa * cb - ca * sa;
  rot[0][2] = ca * sb;
  rot[1][0] = sa * ca * cb - sa * ca;
  rot[1][1] = sa * sa * cb + ca * ca;
  rot[1][2] = sa * sb;
  rot[2][0] = -sb * ca;
  rot[2][1] = -sb * sa;
  rot[2][2] = cb;
  /* (3)-(4) */
  c[0] = -0.5L * r * (1.0L - cb) * cosl(2.0L * a);
  c[1] = 0.5L * r * (1.0L - cb) * sinl(2.0L * a);
  c[2] = z;
  for (i = 0; i < 3; i++) {
    long double cp = i == 0 ? 1.0L : -0.5L;
    long double sp = i == 0 ? 0.0L : (i == 1 ? 0.5L : -0.5L) * s3;
    long double bb[3], v[3];
    int k;
    for (k = 0; k < 3; k++)
      bb[k] = c[k] + rot[k][0] * r * cp + rot[k][1] * r * sp;
    v[0] = bb[0] - R * cp;
    v[1] = bb[1] - R * sp;
    v[2] = bb[2];
    theta[i] = atan2l(v[2], -(v[0] * cp + v[1] * sp));
  }
}

const char *const study_kind_name[S_NSTUDY] = {"theta", "derivative", "method",
                                               "effects", "dt"};
const char *const study_deriv_name[5] = {"exact", "fd_pose", "fd_length",
                                         "fd_samples", "spline_pose"};

static const double tols[7] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
static const double steps[6] = {FD_MARGIN, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
/* row spacings of the spline of the pose: 100 Hz is a motion-capture rate,
   1 kHz an encoder's */
static const double spacings[3] = {1e-1, 1e-2, 1e-3};
static const double dt_fracs[9] = {5e-2, 2e-2, 1e-2, 5e-3, 2e-3,
                                   1e-3, 5e-4, 2e-4, 1e-4};
/* the effects ladder: gravity only -> every effect */
static const int ladder[RPS3_NEFFECT] = {
    RPS3_EFF_PLATFORM_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY |
        RPS3_EFF_PLATFORM_INERTIA,
    RPS3_EFF_DEFAULT,
    RPS3_EFF_DEFAULT | RPS3_EFF_PAYLOAD,
    RPS3_EFF_ALL};

void study_config_base(study_config *c, study_kind s) {
  memset(c, 0, sizeof(*c));
  c->study = s;
  c->theta = RPS3_THETA_CLOSED_FORM;
  c->solver = -1;
  c->tol = 1e-12;
  c->warm = 1;
  c->deriv = D_EXACT;
  c->method = RPS3_LAGRANGE;
  c->effects = RPS3_EFF_DEFAULT;
}

/* the next configuration cfg[(*n)++]: of study s, every knob at its
   default, labelled by the format */
static study_config *add(study_config *cfg, int *n, study_kind s,
                         const char *fmt, ...) {
  study_config *c = &cfg[(*n)++];
  va_list ap;
  study_config_base(c, s);
  va_start(ap, fmt);
  vsnprintf(c->label, sizeof c->label, fmt, ap);
  va_end(ap);
  return c;
}

int study_configs_build(study_config *cfg) {
  int n = 0, s, t, w, k, e;
  study_config *c;
  add(cfg, &n, S_THETA, "closed form (39)");
  for (s = 0; s < RPS3_NSOLVER; s++)
    for (t = 0; t < 7; t++)
      for (w = 0; w < 2; w++) {
        c = add(cfg, &n, S_THETA, "%s tol=%.0e %s", rps3_solver_name(s),
                tols[t], w ? "warm" : "cold");
        c->theta = RPS3_THETA_MULTIROOT;
        c->solver = s;
        c->tol = tols[t];
        c->warm = w;
      }
  add(cfg, &n, S_DERIV, "exact rates");
  for (k = D_FD_POSE; k <= D_SPLINE; k++) {
    /* the spline's row spacings, else the steps; fd_samples is the dt
       study's */
    const double *h = k == D_SPLINE ? spacings : steps;
    int nh = k == D_SPLINE ? 3 : k == D_FD_SAMPLES ? 0 : 6;
    for (t = 0; t < nh; t++) {
      c = add(cfg, &n, S_DERIV, "%s h=%.0e s", study_deriv_name[k], h[t]);
      c->deriv = (deriv_kind)k;
      c->h = h[t];
    }
  }
  for (k = 0; k < 2; k++)
    add(cfg, &n, S_METHOD, "%s", k ? "newton_euler" : "lagrange")->method =
        k ? RPS3_NEWTON_EULER : RPS3_LAGRANGE;
  for (e = 0; e < RPS3_NEFFECT; e++)
    add(cfg, &n, S_EFFECTS, "+%s", rps3_effect_name(e))->effects = ladder[e];
  /* sample interval, exact rates and rates differenced from the samples */
  for (k = 0; k < 2; k++)
    for (t = 0; t < 9; t++) {
      c = add(cfg, &n, S_DT, "dt=T/%.0f %s", 1.0 / dt_fracs[t],
              k ? "rates from samples" : "exact rates");
      c->dt_frac = dt_fracs[t];
      c->deriv = k ? D_FD_SAMPLES : D_EXACT;
    }
  return n;
}

/*
 * Forces at time t by the configuration's route.  Exact: the trajectory's
 * derivatives and rps3_inverse.  fd_pose: central differences of the pose
 * at t +- h.  fd_length: inverse kinematics at t +- h, central differences
 * of the link lengths, then the joint-rate route (25)-(30).
 */
int study_point(study_runner *r, double t) {
  rps3_data *d = r->d;
  const rps3_model *m = &r->model;
  double h = r->c->h, p[3][3], l[2][3]; /* at t - h, t + h, t */
  int st, i, k;
  if (r->c->deriv == D_EXACT || r->c->deriv == D_FD_SAMPLES)
    return rps3_traj_eval(m, r->tr, t, d->pose, d->dpose, d->ddpose) ||
           rps3_inverse(m, d);
  if (r->c->deriv == D_SPLINE)
    return rps3_traj_eval(m, &r->table, t, d->pose, d->dpose, d->ddpose) ||
           rps3_inverse(m, d);
  if ((st = rps3_traj_eval(m, r->tr, t - h, p[0], NULL, NULL)) != RPS3_OK ||
      (st = rps3_traj_eval(m, r->tr, t + h, p[1], NULL, NULL)) != RPS3_OK ||
      (st = rps3_traj_eval(m, r->tr, t, p[2], NULL, NULL)) != RPS3_OK)
    return st;
  if (r->c->deriv == D_FD_POSE) {
    for (i = 0; i < 3; i++) {
      d->pose[i] = p[2][i];
      d->dpose[i] = (p[1][i] - p[0][i]) / (2.0 * h);
      d->ddpose[i] = (p[1][i] - 2.0 * p[2][i] + p[0][i]) / (h * h);
    }
    return rps3_inverse(m, d);
  }
  /* fd_length: the lengths at t - h and t + h, then d at t */
  for (k = 0; k < 3; k++) {
    memcpy(d->pose, p[k], sizeof(p[k]));
    if ((st = rps3_ik(m, d)) != RPS3_OK) return st;
    if (k < 2) memcpy(l[k], d->l, sizeof(l[k]));
  }
  for (i = 0; i < 3; i++) {
    d->dl[i] = (l[1][i] - l[0][i]) / (2.0 * h);
    d->ddl[i] = (l[1][i] - 2.0 * d->l[i] + l[0][i]) / (h * h);
  }
  if ((st = rps3_joint_velocity(m, d)) != RPS3_OK ||
      (st = rps3_joint_acceleration(m, d)) != RPS3_OK)
    return st;
  return rps3_invdyn(m, d);
}

/* the time of sample k of n: interior points (k + 1/2) / n of the span
   less the margins, so that no sample sits on a helix corner */
double study_sample_time(size_t k, size_t n, double span) {
  return FD_MARGIN + (span - 2.0 * FD_MARGIN) * ((double)k + 0.5) / (double)n;
}

/* spline_pose: the trajectory's poses every h (the last row at the span),
   the rates from rps3_table_spline, as rps3-run reads a table */
static int spline_rows(study_runner *r) {
  double span = rps3_traj_duration(r->tr), *time, (*pose)[3], (*rate)[3];
  size_t n = (size_t)floor(span / r->c->h + 0.5) + 1, i;
  r->rows = malloc(8 * n * sizeof(double));
  if (!r->rows) return -1;
  time = r->rows;
  pose = (double(*)[3])(void *)(r->rows + n);
  rate = (double(*)[3])(void *)(r->rows + 4 * n);
  for (i = 0; i < n; i++) {
    time[i] = i + 1 == n ? span : (double)i * r->c->h;
    if (rps3_traj_eval(&r->model, r->tr, time[i], pose[i], NULL, NULL) !=
        RPS3_OK)
      return -1;
  }
  if (rps3_table_spline(n, time, (const double(*)[3])pose, rate,
                        r->rows + 7 * n) != RPS3_OK)
    return -1;
  rps3_traj_default(&r->table);
  r->table.kind = RPS3_TRAJ_TABLE;
  r->table.table.n = n;
  r->table.table.time = time;
  r->table.table.value = (const double(*)[3])pose;
  r->table.table.rate = (const double(*)[3])rate;
  return rps3_traj_check(&r->model, &r->table, NULL) == RPS3_OK ? 0 : -1;
}

int study_runner_init(study_runner *r, const study_config *c,
                      const rps3_traj *tr, const rps3_model *base) {
  rps3_check chk;
  r->model = *base;
  r->model.opt.theta = c->theta;
  r->model.opt.solver =
      c->solver < 0 ? RPS3_SOLVER_HYBRIDSJ : (rps3_solver)c->solver;
  r->model.opt.tol = c->tol;
  r->model.opt.warm_start = c->warm;
  r->model.opt.method = c->method;
  r->model.opt.effects = c->effects;
  r->model.opt.outputs =
      c->study == S_DT ? RPS3_OUT_ALL : RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
  r->model.opt.max_iter = 100;
  if (rps3_model_init(&r->model, &chk) != RPS3_OK) {
    fprintf(stderr, "rps3-study: %s: %s\n", c->label, chk.msg);
    return -1;
  }
  r->tr = tr;
  r->c = c;
  r->d = NULL;
  r->rows = NULL;
  if (rps3_data_alloc(&r->model, &r->d) != RPS3_OK ||
      (c->deriv == D_SPLINE && spline_rows(r) < 0)) {
    fprintf(stderr, "rps3-study: %s: out of memory\n", c->label);
    return -1;
  }
  return 0;
}

double study_energy(const rps3_model *m, const rps3_data *d) {
  double T, P, wb[3] = {0, 0, 0};
  int i, k;
  /* omega in platform axes: rot^T omega */
  for (k = 0; k < 3; k++)
    for (i = 0; i < 3; i++) wb[k] += d->rot[i][k] * d->omega[i];
  T = 0.5 * m->M *
          (d->vc[0] * d->vc[0] + d->vc[1] * d->vc[1] + d->vc[2] * d->vc[2]) +
      0.5 * (m->Ip[0] * wb[0] * wb[0] + m->Ip[1] * wb[1] * wb[1] +
             m->Ip[2] * wb[2] * wb[2]);
  P = m->M * m->g * d->c[2];
  for (i = 0; i < 3; i++) {
    T += 0.5 * m->Jlink * d->dtheta[i] * d->dtheta[i];
    P += m->m * m->g * m->d * sin(d->theta[i]); /* (22) */
  }
  return T + P;
}
