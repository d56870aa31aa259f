/*
 * study_accuracy.c - rps3-study accuracy: what accuracy costs in time.
 * The two trajectories, every configuration (a knob turned from the
 * defaults) and one point by a configuration's route; each configuration
 * on both trajectories: its errors against a precise reference in one
 * untimed pass, then the median time of R timed passes; the file of both
 * (main_study.c says what it holds).
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"
#include "study_accuracy_h5.h"
#include "study_ref.h"

#define NREF_PEAK 200001

/* sine_edge, as study_traj_doc (study_accuracy_h5.c) says */
static const rps3_sine SINE_EDGE = {
    {0.0, 0.6, 0.28}, {PI, 0.2, 0.03}, {1.0, 2.3, 1.7}, {0.0, 0.0, 0.0}, 2.0};

static void study_traj_make(int k, rps3_traj *tr) {
  if (k == 0)
    rps3_traj_default(tr);
  else
    study_traj_sine(tr, &SINE_EDGE);
}

/* inverse kinematics in long double, independent of src/ik.c: the
   reference angles theta_i of the pose, by (2)-(7), (39) from the rotation
   Rz(a) Ry(b) Rz(-a), the centre (3)-(4) and b_i = c + rot r_i */
static void study_ik_long(const rps3_model *m, const double pose[3],
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

/*
 * Forces at time t by the configuration's route (an rps3_status).  Exact: the
 * trajectory's derivatives and rps3_inverse.  fd_pose: central differences of
 * the pose at t +- h.  fd_length: inverse kinematics at t +- h, central
 * differences of the link lengths, then the joint-rate route (25)-(30).
 */
static int study_point(study_runner *r, double t) {
  rps3_data *d = r->d;
  const rps3_model *m = &r->model;
  double h = r->c->h, p[3][3], l[2][3]; /* at t - h, t + h, t */
  int st, i, k;
  if (r->c->deriv == D_EXACT || r->c->deriv == D_FD_SAMPLES ||
      r->c->deriv == D_SPLINE)
    return (st = rps3_traj_eval(m, r->c->deriv == D_SPLINE ? &r->table : r->tr,
                                t, d->pose, d->dpose, d->ddpose)) != RPS3_OK
               ? st
               : rps3_inverse(m, d);
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
static double study_sample_time(size_t k, size_t n, double span) {
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

/* r for configuration c on tr from the model base; 0, or -1 with a
   message on stderr */
static int study_runner_init(study_runner *r, const study_config *c,
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

/* T + P of the default effects at the data's state, written here from
   vc, omega and dtheta (not by the library) */
static double study_energy(const rps3_model *m, const rps3_data *d) {
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

/*
 * The reference forces of `effects` at the n grid samples, by study_ref.c
 * (Kane's equations in long double, from the model's inputs: nothing of the
 * library's dynamics).  Its own floor: the same code in double lands at
 * some distance from it, the rounding of double amplified by the
 * formulation; in long double that amplification costs LDBL_EPSILON /
 * DBL_EPSILON as much.
 */
static int reference_forces(const rps3_model *base, const rps3_traj *tr,
                            int effects, study_reference *ref) {
  size_t k;
  int i;
  double dev = 0.0;
  ref->fscale = 0.0;
  for (k = 0; k < ref->n; k++) {
    double t = study_sample_time(k, ref->n, ref->span), q[3], dq[3], ddq[3],
           Fd[3];
    double *F = &ref->F[3 * k];
    if (rps3_traj_eval(base, tr, t, q, dq, ddq) != RPS3_OK ||
        study_ref_forces(base, effects, q, dq, ddq, F) != 0 ||
        study_ref_forces_double(base, effects, q, dq, ddq, Fd) != 0) {
      fprintf(stderr, "rps3-study: reference fails at t = %g\n", t);
      return -1;
    }
    for (i = 0; i < 3; i++) {
      if (fabs(F[i]) > ref->fscale) ref->fscale = fabs(F[i]);
      if (fabs(F[i] - Fd[i]) > dev) dev = fabs(F[i] - Fd[i]);
    }
  }
  ref->floor_ref = dev / ref->fscale * ((double)LDBL_EPSILON / DBL_EPSILON);
  return 0;
}

static int reference_build(const rps3_model *base, const rps3_traj *tr,
                           size_t n, study_reference *ref) {
  study_config c;
  study_runner r;
  size_t k;
  int i;
  ref->n = n;
  ref->span = rps3_traj_duration(tr);
  ref->F = malloc(3 * n * sizeof(double));
  ref->theta = malloc(3 * n * sizeof(long double));
  if (!ref->F || !ref->theta) return -1;
  if (reference_forces(base, tr, RPS3_EFF_DEFAULT, ref) < 0) return -1;
  /* theta: inverse kinematics in long double; its floor against the
     library's closed form */
  study_config_base(&c, S_METHOD);
  if (study_runner_init(&r, &c, tr, base) < 0) return -1;
  ref->floor_theta = ref->peak = 0.0;
  for (k = 0; k < n; k++) {
    double t = study_sample_time(k, n, ref->span);
    if (study_point(&r, t) != RPS3_OK) {
      fprintf(stderr, "rps3-study: closed form fails at t = %g: %s\n", t,
              r.d->err.msg);
      return -1;
    }
    study_ik_long(&r.model, r.d->pose, &ref->theta[3 * k]);
    for (i = 0; i < 3; i++) {
      double dth = fabs(r.d->theta[i] - (double)ref->theta[3 * k + i]);
      if (dth > ref->floor_theta) ref->floor_theta = dth;
    }
  }
  rps3_data_free(r.d);
  /* the peak force: a dense grid, ends and both sides of corners included */
  for (k = 0; k < NREF_PEAK; k++) {
    double t = ref->span * (double)k / (double)(NREF_PEAK - 1), q[3], dq[3],
           ddq[3], F[3];
    if (rps3_traj_eval(base, tr, t, q, dq, ddq) != RPS3_OK ||
        study_ref_forces(base, RPS3_EFF_DEFAULT, q, dq, ddq, F) != 0)
      return -1;
    for (i = 0; i < 3; i++)
      if (fabs(F[i]) > ref->peak) ref->peak = fabs(F[i]);
  }
  return 0;
}

/* one pass over the fixed grid; with out != NULL record the errors */
static int pass_grid(study_runner *r, const study_reference *ref,
                     study_result *out) {
  size_t k;
  int i, st;
  double ferr = 0.0, terr = 0.0, iters = 0.0;
  rps3_data_reset(r->d);
  for (k = 0; k < ref->n; k++) {
    st = study_point(r, study_sample_time(k, ref->n, ref->span));
    if (st != RPS3_OK) {
      if (!out) continue;
      if (out->nfail++ == 0) out->status = st;
      /* the next sample must not warm-start from a failed one */
      rps3_data_reset(r->d);
      continue;
    }
    if (!out) continue;
    iters += r->d->solve_niter;
    for (i = 0; i < 3; i++) {
      double fe = fabs(r->d->F[i] - ref->F[3 * k + i]);
      double te = fabs(r->d->theta[i] - (double)ref->theta[3 * k + i]);
      if (fe > ferr) ferr = fe;
      if (te > terr) terr = te;
    }
  }
  if (out) {
    int nok = (int)ref->n - out->nfail;
    out->force_err = nok ? ferr / ref->fscale : DNAN;
    out->theta_err = nok ? terr : DNAN;
    out->mean_iter = nok ? iters / nok : DNAN;
  }
  return 0;
}

/* sample k of n at interval dt with the rates differenced from the
   samples (what a logger gives): central differences of the sampled
   poses, one-sided and without acceleration at the ends; forces into
   r->d, an rps3_status */
static int sampled_rates(study_runner *r, size_t k, size_t n, double dt,
                         double span) {
  size_t at[3] = {k ? k - 1 : 0, k, k + 1 < n ? k + 1 : n - 1}, j;
  double q[3][3], d = (double)(at[2] - at[0]) * dt;
  int i, st;
  for (j = 0; j < 3; j++)
    if ((st = rps3_traj_eval(&r->model, r->tr,
                             at[j] == n - 1 ? span : (double)at[j] * dt, q[j],
                             NULL, NULL)) != RPS3_OK)
      return st;
  for (i = 0; i < 3; i++) {
    r->d->pose[i] = q[1][i];
    r->d->dpose[i] = (q[2][i] - q[0][i]) / d;
    r->d->ddpose[i] = at[2] - at[0] == 2
                          ? (q[2][i] - 2.0 * q[1][i] + q[0][i]) / (dt * dt)
                          : 0.0;
  }
  return rps3_inverse(&r->model, r->d);
}

/*
 * The sample-interval study: samples t_k = k dt over the whole span.  The
 * peak |F| over the samples against the reference peak; and the work of the
 * actuators over each interval (trapezoid of the power sum F_i dl_i) against
 * the change of T + P.  With exact rates the residual is the trapezoid's
 * O(dt^2); with rates differenced from the samples it also carries their
 * error.
 */
static int pass_dt(study_runner *r, const study_reference *ref,
                   study_result *out) {
  double span = ref->span, dt = r->c->dt_frac * span;
  size_t n = (size_t)floor(span / dt + 0.5) + 1, k;
  double peak = 0.0, Wmax = 0.0, resmax = 0.0, Eprev = 0.0, Pprev = 0.0;
  double tprev = 0.0;
  int i, st;
  rps3_data_reset(r->d);
  for (k = 0; k < n; k++) {
    double t = k == n - 1 ? span : (double)k * dt, E, P = 0.0;
    st = r->c->deriv == D_EXACT ? study_point(r, t)
                                : sampled_rates(r, k, n, dt, span);
    if (st != RPS3_OK) {
      if (out && out->nfail++ == 0) out->status = st;
      return 0;
    }
    if (!out) continue;
    for (i = 0; i < 3; i++) {
      if (fabs(r->d->F[i]) > peak) peak = fabs(r->d->F[i]);
      P += r->d->F[i] * r->d->dl[i];
    }
    E = study_energy(&r->model, r->d);
    if (k > 0) {
      double W = 0.5 * (P + Pprev) * (t - tprev);
      if (fabs(W) > Wmax) Wmax = fabs(W);
      if (fabs(W - (E - Eprev)) > resmax) resmax = fabs(W - (E - Eprev));
    }
    Eprev = E;
    Pprev = P;
    tprev = t;
  }
  if (out) {
    out->peak_err = (ref->peak - peak) / ref->peak;
    out->energy_err = resmax / Wmax;
  }
  return 0;
}

/* samples of one pass of configuration c */
static size_t pass_points(const study_config *c, const study_reference *ref) {
  return c->study == S_DT ? (size_t)floor(1.0 / c->dt_frac + 0.5) + 1 : ref->n;
}

/* one pass of configuration c; with res != NULL, record its errors */
static void pass(study_runner *r, const study_reference *ref,
                 study_result *res) {
  if (r->c->study == S_DT)
    pass_dt(r, ref, res);
  else
    pass_grid(r, ref, res);
}

/*
 * The timed passes, round-robin over the configurations (repeat k of every
 * configuration before repeat k + 1 of any), so that a burst of load from
 * other processes spreads over all of them instead of shifting a few; the
 * median of each configuration's passes is its time per point.
 */
static int measure_times(study_runner *r, const study_config *cfg, int ncfg,
                         const study_reference *ref, int repeats,
                         study_result *res) {
  double *ns = malloc((size_t)ncfg * (size_t)repeats * sizeof(double));
  int c, k;
  if (!ns) return -1;
  for (k = 0; k < repeats; k++)
    for (c = 0; c < ncfg; c++) {
      double t0 = study_now_ns();
      pass(&r[c], ref, NULL);
      ns[c * repeats + k] =
          (study_now_ns() - t0) / (double)pass_points(&cfg[c], ref);
    }
  for (c = 0; c < ncfg; c++) {
    double *v = &ns[c * repeats];
    res[c].ns_point = study_median(v, repeats); /* sorts v */
    res[c].ns_q1 = v[repeats / 4];
    res[c].ns_q3 = v[(3 * repeats) / 4];
    res[c].ns_second =
        res[c].ns_point * (double)pass_points(&cfg[c], ref) / ref->span;
  }
  free(ns);
  return 0;
}

/* the model of the study: Table II, plus a payload and pin friction so that
   the effects ladder has something to add; the other studies use the
   default effects (the paper's four).  0, or -1 with a message */
static int accuracy_model(rps3_model *base) {
  rps3_check chk;
  rps3_model_default(base);
  base->payload.mass = 0.05;
  base->payload.com[0] = 0.011;
  base->payload.com[2] = 0.023;
  base->payload.inertia[0] = base->payload.inertia[1] = 1.3e-5;
  base->payload.inertia[2] = 2.1e-5;
  base->friction.viscous = 0.011;
  base->friction.coulomb = 0.0023;
  if (rps3_model_init(base, &chk) != RPS3_OK) {
    fprintf(stderr, "rps3-study: %s\n", chk.msg);
    return -1;
  }
  return 0;
}

/* trajectory t: its reference ref, then every configuration's errors and
   times into res[0..ncfg); 0 or -1 */
static int measure_trajectory(const rps3_model *base, int t, size_t nsamp,
                              int repeats, const study_config *cfg, int ncfg,
                              study_runner *run, study_reference *ref,
                              study_result *res) {
  rps3_check chk;
  int c;
  rps3_traj tr;
  study_reference rall;
  study_traj_make(t, &tr);
  if (rps3_traj_check(base, &tr, &chk) != RPS3_OK) {
    fprintf(stderr, "rps3-study: %s: %s\n", study_traj_name[t], chk.msg);
    return -1;
  }
  if (reference_build(base, &tr, nsamp, ref) < 0) return -1;
  fprintf(
      stderr,
      "rps3-study: %s: reference |F|max %.4g N, peak %.6g N, floors: reference "
      "(long double) %.2g, theta closed form - long double %.2g rad\n",
      study_traj_name[t], ref->fscale, ref->peak, ref->floor_ref,
      ref->floor_theta);
  /* the effects ladder's error is against the model with every effect */
  rall = *ref;
  rall.F = malloc(3 * nsamp * sizeof(double));
  if (!rall.F || reference_forces(base, &tr, RPS3_EFF_ALL, &rall) < 0)
    return -1;
  /* the first, untimed pass: each configuration's errors */
  for (c = 0; c < ncfg; c++) {
    study_result *e = &res[c];
    memset(e, 0, sizeof(*e));
    e->peak_err = e->energy_err = DNAN;
    if (study_runner_init(&run[c], &cfg[c], &tr, base) < 0) return -1;
    pass(&run[c], cfg[c].study == S_EFFECTS ? &rall : ref, e);
    if (cfg[c].study == S_DT) e->force_err = e->theta_err = e->mean_iter = DNAN;
  }
  free(rall.F);
  if (measure_times(run, cfg, ncfg, ref, repeats, res) < 0) return -1;
  for (c = 0; c < ncfg; c++) {
    rps3_data_free(run[c].d);
    free(run[c].rows);
  }
  return 0;
}

int study_accuracy(const char *path, const char *cmdline, size_t nsamp,
                   int repeats) {
  static study_config cfg[MAXCFG];
  static study_result res[NTRAJ][MAXCFG];
  static study_runner run[MAXCFG];
  study_reference ref[NTRAJ];
  rps3_model base;
  int ncfg = study_configs_build(cfg), t, rc = 0;
  double t_start = study_now_ns();
  /* the measurements, trajectory by trajectory */
  if (accuracy_model(&base) < 0) return EXIT_IO;
  for (t = 0; t < NTRAJ; t++)
    if (measure_trajectory(&base, t, nsamp, repeats, cfg, ncfg, run, &ref[t],
                           res[t]) < 0)
      return EXIT_IO;
  fprintf(
      stderr,
      "rps3-study: accuracy: %d configurations x %d trajectories in %.1f s\n",
      ncfg, NTRAJ, 1e-9 * (study_now_ns() - t_start));
  /* the file */
  if (study_accuracy_write(path, cmdline, cfg, ncfg,
                           (const study_result(*)[MAXCFG])res, ref, nsamp,
                           repeats) < 0)
    rc = -1;
  for (t = 0; t < NTRAJ; t++) {
    free(ref[t].F);
    free(ref[t].theta);
  }
  return rc ? EXIT_IO : EXIT_OK;
}
