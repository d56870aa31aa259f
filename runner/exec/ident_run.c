/* ident_run.c - see ident_run.h: the plan (its rows, the general model's
   layout and base, the truth); the fits are ident_fit.c. */
#include "ident_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#define IDENT_PI 3.14159265358979323846

/* the columns to fit: the given parameters, each one whose column the
   effects fill, else the default set of the effects; 0 or -1 */
static int plan_columns(const scene *s, ident_plan *p, scene_error *err) {
  int eff = p->c.model.opt.effects, have = ident_effect_params(eff);
  int want =
      s->base.ids.params >= 0 ? s->base.ids.params : ident_default_params(eff);
  int k;
  char names[256];
  size_t len = 0;
  names[0] = '\0';
  for (k = 0; k < RPS3_NPAPER; k++)
    if (have & (1 << k))
      len += (size_t)snprintf(names + len, sizeof names - len, "%s%s",
                              len ? ", " : "", rps3_paper_name(k));
  for (k = 0; k < RPS3_NPAPER; k++) {
    if (!(want & (1 << k))) continue;
    if (!(have & (1 << k)))
      return scene_error_set(
          err, s->mark[K_ID_PARAMS], scene_key_get(K_ID_PARAMS)->path,
          "parameter '%s': the scene's effects leave its column at zero (the "
          "effects fill %s)",
          rps3_paper_name(k), names);
    p->col[p->p] = k;
    p->names[p->p++] = rps3_paper_name(k);
  }
  if (p->p == 0)
    return scene_error_set(err, s->identify, "identify",
                           "no parameter to fit: the effects fill none");
  return 0;
}

/* the layout's row of a standard regressor row ys: each layout column
   the sum of its standard columns */
static void lay_row(const ident_plan *p, const double *ys, double *out) {
  size_t j;
  int q;
  for (j = 0; j < p->nlay; j++) {
    out[j] = 0;
    for (q = 0; q < 3 && p->lay_std[j][q] >= 0; q++)
      out[j] += ys[p->lay_std[j][q]];
  }
}

/* row block k of Y (general: and of Ylay) at the point of d (its pose,
   rates and accelerations); 0 or the failing status with d->err */
static int plan_regress(ident_plan *p, rps3_data *d, size_t k) {
  const rps3_model *m = &p->c.model;
  size_t i, j;
  int rc;
  if (!p->general) {
    double Yk[3][RPS3_NPAPER];
    if ((rc = rps3_regressor(m, d, Yk)) != RPS3_OK) return rc;
    for (i = 0; i < 3; i++)
      for (j = 0; j < p->p; j++)
        p->Y[(3 * k + i) * p->p + j] = Yk[i][p->col[j]];
  } else {
    double Yk[3][RPS3_NSTD];
    if ((rc = rps3_regressor_std(m, d, Yk)) != RPS3_OK) return rc;
    for (i = 0; i < 3; i++) {
      double *row = p->Ylay + (3 * k + i) * p->nlay;
      lay_row(p, Yk[i], row);
      for (j = 0; j < p->p; j++) p->Y[(3 * k + i) * p->p + j] = row[p->col[j]];
    }
  }
  return RPS3_OK;
}

/* row block k of Y and F0: the trajectory at sample k, its inverse
   dynamics and regressor; 0 or the failing status with d->err */
static int plan_sample(ident_plan *p, rps3_data *d, size_t k, double *t) {
  const rps3_model *m = &p->c.model;
  size_t i;
  int rc;
  *t = scene_case_time(&p->c, k);
  rc = rps3_traj_eval(m, &p->c.traj, *t, d->pose, d->dpose, d->ddpose);
  if (rc != RPS3_OK) {
    snprintf(d->err.msg, sizeof d->err.msg, "the trajectory: %s",
             rps3_strerror(rc));
    return rc;
  }
  if ((rc = rps3_inverse(m, d)) != RPS3_OK) return rc;
  for (i = 0; i < 3; i++) p->F0[3 * k + i] = d->F[i];
  return plan_regress(p, d, k);
}

/* x solving the 3 x 3 system A x = b by Gaussian elimination with partial
   pivoting; 0, or -1 when A is singular */
static int solve3(double A[3][3], double b[3], double x[3]) {
  int i, j, k, piv;
  for (k = 0; k < 3; k++) {
    for (piv = k, i = k + 1; i < 3; i++)
      if (fabs(A[i][k]) > fabs(A[piv][k])) piv = i;
    if (A[piv][k] == 0) return -1;
    for (j = 0; j < 3; j++) {
      double tmp = A[k][j];
      A[k][j] = A[piv][j];
      A[piv][j] = tmp;
    }
    {
      double tmp = b[k];
      b[k] = b[piv];
      b[piv] = tmp;
    }
    for (i = k + 1; i < 3; i++) {
      double f = A[i][k] / A[k][k];
      for (j = k; j < 3; j++) A[i][j] -= f * A[k][j];
      b[i] -= f * b[k];
    }
  }
  for (k = 2; k >= 0; k--) {
    x[k] = b[k];
    for (j = k + 1; j < 3; j++) x[k] -= A[k][j] * x[j];
    x[k] /= A[k][k];
  }
  return 0;
}

/* the pose accelerations of measured link accelerations ddl at d's pose
   and rates: ddl = J ddpose + bias(pose, dpose), J and the bias by the
   link motion of unit rates and of no acceleration (rps3_link_motion, in
   the scratch d2) */
static int pose_accel(const rps3_model *m, rps3_data *d, rps3_data *d2,
                      const double ddl[3]) {
  double J[3][3], b[3];
  int i, k, rc;
  for (k = 0; k < 3; k++) {
    memcpy(d2->pose, d->pose, sizeof d2->pose);
    for (i = 0; i < 3; i++) d2->dpose[i] = i == k;
    if ((rc = rps3_link_motion(m, d2, 0)) != RPS3_OK) return rc;
    for (i = 0; i < 3; i++) J[i][k] = d2->dl[i];
  }
  memcpy(d2->dpose, d->dpose, sizeof d2->dpose);
  for (i = 0; i < 3; i++) d2->ddpose[i] = 0;
  if ((rc = rps3_link_motion(m, d2, 1)) != RPS3_OK) return rc;
  for (i = 0; i < 3; i++) b[i] = ddl[i] - d2->ddl[i];
  if (solve3(J, b, d->ddpose)) {
    snprintf(d->err.msg, sizeof d->err.msg,
             "the lengths' Jacobian is singular at this pose");
    return RPS3_ESING;
  }
  return RPS3_OK;
}

/* row block k of Y and F0 from measured row k: the pose by the forward
   kinematics of the lengths, its rates by the joint-rate route
   (rps3_fk, rps3_joint_velocity), its accelerations by pose_accel; 0 or
   the failing status with d->err */
static int plan_row(ident_plan *p, rps3_data *d, rps3_data *d2,
                    const table_data *t, size_t k) {
  const rps3_model *m = &p->c.model;
  size_t i;
  int rc;
  memcpy(d->l, t->value[k], sizeof d->l);
  if ((rc = rps3_fk(m, d)) != RPS3_OK) return rc;
  memcpy(d->dl, t->rate[k], sizeof d->dl);
  if ((rc = rps3_joint_velocity(m, d)) != RPS3_OK ||
      (rc = pose_accel(m, d, d2, t->acc[k])) != RPS3_OK ||
      (rc = plan_regress(p, d, k)) != RPS3_OK)
    return rc;
  for (i = 0; i < 3; i++) p->F0[3 * k + i] = t->force[k][i];
  return RPS3_OK;
}

/* Y and F0 at every sample (of the trajectory, or the data's rows); 0 or
   -1 with err at the row or sample that fails */
static int plan_rows(const scene *s, ident_plan *p, scene_error *err) {
  const table_data *t = &s->table[TABLE_MEASURED];
  rps3_data *d = NULL, *d2 = NULL;
  double time = 0;
  size_t k;
  int rc = RPS3_OK;
  if (rps3_data_alloc(&p->c.model, &d) || rps3_data_alloc(&p->c.model, &d2)) {
    rps3_data_free(d);
    return scene_error_set(err, s->identify, "identify", "out of memory");
  }
  for (k = 0; k < p->ns && rc == RPS3_OK; k++)
    rc = p->measured ? plan_row(p, d, d2, t, k) : plan_sample(p, d, k, &time);
  if (rc != RPS3_OK && p->measured) {
    char where[300];
    table_where(t, k - 1, where, sizeof where);
    scene_error_set(err, s->mark[K_ID_DATA], "identify.data",
                    "%s: the pose of the lengths fails: %s", where, d->err.msg);
  } else if (rc != RPS3_OK)
    scene_error_set(err, s->section[2], "trajectory",
                    "sample %zu (t = %g s): the inverse dynamics fails: %s",
                    k - 1, time, d->err.msg);
  rps3_data_free(d);
  rps3_data_free(d2);
  return rc == RPS3_OK ? 0 : -1;
}

/* ---------------------------------------------------- general model */

/* the layout (python/rps3/ident.py Layout) of the bodies and friction the
   effects fill: the platform with a platform effect, the cylinders and
   pistons with a link effect (each leg's, or one of each for identical
   legs, whose columns sum the three legs'), then the friction kinds
   selected, per leg for "each" and shared for "identical"; 0 or -1 */
static int plan_layout(const scene *s, ident_plan *p, scene_error *err) {
  static const char *const inertial[10] = {"m",   "mcx", "mcy", "mcz", "Ixx",
                                           "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
  static const char *const part[2] = {"cylinder", "piston"};
  static const char *const kind[2] = {"prismatic", "pin"};
  static const int kind_eff[2] = {RPS3_EFF_PRISMATIC_FRICTION,
                                  RPS3_EFF_PIN_FRICTION};
  int eff = p->c.model.opt.effects, same = p->ids.legs == IDENT_LEGS_IDENTICAL;
  int b, k, i, q, f;
  size_t j;
  p->nlay = p->nbody = 0;
  for (b = 0; b < RPS3_NBODY; b++) {
    /* body b of the standard order: 0 the platform, 1 + 2 i + q leg i's
       cylinder (q 0) or piston (q 1) */
    int leg = b == 0 ? -1 : (b - 1) / 2, pq = b == 0 ? 0 : (b - 1) % 2;
    int filled = b == 0 ? (eff & (RPS3_EFF_PLATFORM_GRAVITY |
                                  RPS3_EFF_PLATFORM_INERTIA)) != 0
                        : (eff & (RPS3_EFF_LINK_GRAVITY |
                                  RPS3_EFF_LINK_INERTIA)) != 0;
    size_t nb = p->nbody;
    if (!filled || (same && leg > 0)) continue;
    if (b == 0)
      snprintf(p->body_name[nb], sizeof p->body_name[nb], "platform");
    else if (same)
      snprintf(p->body_name[nb], sizeof p->body_name[nb], "%s", part[pq]);
    else
      snprintf(p->body_name[nb], sizeof p->body_name[nb], "%s%d", part[pq],
               leg + 1);
    p->body_names[nb] = p->body_name[nb];
    for (k = 0; k < 10; k++) {
      j = p->nlay++;
      snprintf(p->lay_name[j], sizeof p->lay_name[j], "%s.%s", p->body_name[nb],
               inertial[k]);
      p->lay_kind[j] = RPS3_IDENT_FREE;
      p->body_col[nb][k] = (int)j;
      for (q = 0; q < 3; q++) p->lay_std[j][q] = -1;
      if (b == 0 || !same)
        p->lay_std[j][0] = 10 * b + k;
      else
        for (i = 0; i < 3; i++) p->lay_std[j][i] = 10 * (1 + 2 * i + pq) + k;
    }
    p->nbody++;
  }
  for (f = 0; f < 2; f++) {
    if (!(eff & kind_eff[f])) continue;
    for (i = 0; i < (same ? 1 : 3); i++)
      for (k = 0; k < 2; k++) {
        j = p->nlay++;
        if (same)
          snprintf(p->lay_name[j], sizeof p->lay_name[j], "%s.%s", kind[f],
                   k ? "fc" : "fv");
        else
          snprintf(p->lay_name[j], sizeof p->lay_name[j], "%s%d.%s", kind[f],
                   i + 1, k ? "fc" : "fv");
        p->lay_kind[j] = RPS3_IDENT_NONNEG;
        for (q = 0; q < 3; q++)
          p->lay_std[j][q] =
              same || q == 0 ? 70 + 6 * f + 2 * (same ? q : i) + k : -1;
      }
  }
  for (j = 0; j < p->nlay; j++) p->lay_names[j] = p->lay_name[j];
  if (p->nlay == 0)
    return scene_error_set(err, s->identify, "identify",
                           "no parameter to fit: the effects fill no body "
                           "and select no friction");
  return 0;
}

/* the structural base parameters (IDENT_BASE_STATES): the fitted columns
   are the base columns of the layout; 0 or -1 */
static int plan_base(const scene *s, ident_plan *p, scene_error *err) {
  const rps3_model *m = &p->c.model;
  const size_t ns = IDENT_BASE_STATES, nl = p->nlay;
  const double sc = m->R / 0.2286;
  double *Ys = malloc(3 * ns * nl * sizeof *Ys), Yk[3][RPS3_NSTD];
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  rps3_data *d = NULL;
  size_t got = 0, tries = 0, j;
  int indep[IDENT_PMAX], nbase = 0, i, rc = -1;
  rps3_check chk;
  p->K = malloc(nl * nl * sizeof *p->K);
  if (!Ys || !rng || !p->K || rps3_data_alloc(m, &d)) {
    scene_error_set(err, s->identify, "identify", "out of memory");
    goto done;
  }
  gsl_rng_set(rng, IDENT_BASE_SEED);
  /* a state the library refuses (out of reach, singular) is drawn again */
  for (; got < ns && tries < 20 * ns; tries++) {
    d->pose[0] = -IDENT_PI + 2 * IDENT_PI * gsl_rng_uniform(rng);
    d->pose[1] = 0.05 + 0.4 * gsl_rng_uniform(rng);
    d->pose[2] = sc * (0.27 + 0.09 * gsl_rng_uniform(rng));
    d->dpose[0] = gsl_ran_gaussian(rng, 1.0);
    d->dpose[1] = gsl_ran_gaussian(rng, 0.5);
    d->dpose[2] = gsl_ran_gaussian(rng, 0.05 * sc);
    d->ddpose[0] = gsl_ran_gaussian(rng, 5.0);
    d->ddpose[1] = gsl_ran_gaussian(rng, 2.0);
    d->ddpose[2] = gsl_ran_gaussian(rng, 0.3 * sc);
    if (rps3_regressor_std(m, d, Yk) != RPS3_OK) continue;
    for (i = 0; i < 3; i++) lay_row(p, Yk[i], Ys + (3 * got + i) * nl);
    got++;
  }
  if (got < ns) {
    scene_error_set(err, s->identify, "identify",
                    "the structural base parameters need %zu random states "
                    "of the workspace (z_c in [%g, %g] m): %zu of %zu "
                    "reached",
                    ns, 0.27 * sc, 0.36 * sc, got, tries);
    goto done;
  }
  if (rps3_ident_base(Ys, 3 * ns, nl, IDENT_BASE_TOL, indep, p->K, &nbase,
                      &chk) != RPS3_OK) {
    scene_error_set(err, s->identify, "identify",
                    "the structural base parameters: %s", chk.msg);
    goto done;
  }
  p->p = (size_t)nbase;
  for (j = 0; j < p->p; j++) {
    p->col[j] = indep[j];
    p->names[j] = p->lay_names[indep[j]];
  }
  rc = 0;
done:
  free(Ys);
  if (rng) gsl_rng_free(rng);
  rps3_data_free(d);
  return rc;
}

/* without M the payload's columns hold the platform's disc as well (the
   disc is a body of the payload's kind, include/rps3.h): the payload's
   truth is then the payload with the disc, what its estimate converges
   to (the write-back takes the disc out again, ident_yaml.c) */
static void plan_truth_disc(ident_plan *p) {
  const rps3_model *mo = &p->c.model;
  size_t j;
  int payload = 0, fitted_m = 0;
  for (j = 0; j < p->p; j++) {
    payload |= p->col[j] >= 3 && p->col[j] <= 9;
    fitted_m |= p->col[j] == 0;
  }
  if (!payload || fitted_m ||
      !(mo->opt.effects &
        (RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA)))
    return;
  for (j = 0; j < p->p; j++) {
    int k = p->col[j];
    if (k == 3) p->truth[j] += mo->M;
    if (k >= 7 && k <= 9) p->truth[j] += mo->Ip[k - 7];
  }
}

/* the truth of the general model: the scene's standard parameters, the
   layout's (identical legs: the legs' mean, said when they differ), K
   times them */
static void plan_truth_general(ident_plan *p) {
  size_t j, k;
  int q, differ = 0;
  rps3_std_params(&p->c.model, p->std_truth);
  for (j = 0; j < p->nlay; j++) {
    double sum = 0, lo = HUGE_VAL, hi = -HUGE_VAL;
    for (q = 0; q < 3 && p->lay_std[j][q] >= 0; q++) {
      double v = p->std_truth[p->lay_std[j][q]];
      sum += v;
      lo = v < lo ? v : lo;
      hi = v > hi ? v : hi;
    }
    p->lay_truth[j] = sum / q;
    if (hi - lo > 1e-12 * (fabs(hi) + fabs(lo)) && !differ) {
      differ = 1;
      snprintf(p->warning, sizeof p->warning,
               "identify.legs: identical, but the scene's legs differ (%s "
               "from %g to %g): the truth is the legs' mean, and the data "
               "are not of the layout",
               p->lay_names[j], lo, hi);
    }
  }
  for (j = 0; j < p->p; j++) {
    double t = 0;
    for (k = 0; k < p->nlay; k++) t += p->K[j * p->nlay + k] * p->lay_truth[k];
    p->truth[j] = t;
  }
}

/* each actuator's RMS force and each column's share of the RMS force */
static void plan_shares(ident_plan *p) {
  double all = 0, col;
  size_t r, j;
  int i;
  for (i = 0; i < 3; i++) p->rms[i] = 0;
  for (r = 0; r < p->n; r++) p->rms[r % 3] += p->F0[r] * p->F0[r];
  for (i = 0; i < 3; i++) {
    all += p->rms[i];
    p->rms[i] = sqrt(p->rms[i] / (double)p->ns);
  }
  all = sqrt(all / (double)p->n);
  for (j = 0; j < p->p; j++) {
    for (col = 0, r = 0; r < p->n; r++) {
      double y = p->Y[r * p->p + j] * p->truth[j];
      col += y * y;
    }
    p->share[j] = all > 0 ? sqrt(col / (double)p->n) / all : (double)NAN;
  }
}

/* the rows the draws fit (p->nfit), the first 1 - holdout of the
   samples: enough rows, and as exciting as the whole (a WLS of the
   noise-free forces on them succeeds when one on every row does: else
   the holdout takes what makes the data exciting); 0 or -1 with err at
   the key */
static int plan_holdout(const scene *s, ident_plan *p, scene_error *err) {
  scene_mark at = s->given[K_ID_HOLDOUT] ? s->mark[K_ID_HOLDOUT]
                                         : s->mark[K_ID_RUNS];
  const char *key = scene_key_get(K_ID_HOLDOUT)->path;
  size_t need = p->general && p->ids.consistent ? p->nlay : p->p, nhold;
  ident_fit part, all;
  int rc = 0;
  p->nfit = p->n;
  if (p->ids.runs == 0 || p->ids.holdout <= 0) return 0;
  nhold = (size_t)floor(p->ids.holdout * (double)p->ns);
  p->nfit = 3 * (p->ns - nhold);
  if (nhold == 0)
    return scene_error_set(err, at, key,
                           "%g of %zu samples holds none out: use 0 for no "
                           "held-out samples, or more samples",
                           p->ids.holdout, p->ns);
  if (p->nfit <= need)
    return scene_error_set(err, at, key,
                           "%g of %zu samples leaves %zu to fit, %zu force "
                           "rows: more than the %zu parameters are needed",
                           p->ids.holdout, p->ns, p->ns - nhold, p->nfit,
                           need);
  ident_fit_rows(p, p->F0, p->nfit, 0, &part);
  if (part.status != RPS3_OK) {
    ident_fit_run(p, p->F0, 0, &all);
    if (all.status == RPS3_OK)
      rc = scene_error_set(err, at, key,
                           "the first %zu of %zu samples the draws fit do "
                           "not excite the parameters (condition number "
                           "%.3g), all of them do: hold out less: %s",
                           p->ns - nhold, p->ns, part.cond, part.msg);
    ident_fit_free(&all);
  }
  ident_fit_free(&part);
  return rc;
}

int ident_plan_make(const scene *s, ident_plan *p, scene_error *err) {
  double pi[RPS3_NPAPER];
  rps3_check chk;
  size_t k, j;
  memset(p, 0, sizeof *p);
  if (scene_case_build(s, 0, &p->c, err)) return -1;
  p->ids = s->base.ids;
  p->general = ident_model(s) == RPS3_BODIES_GENERAL;
  if (p->general ? plan_layout(s, p, err) || plan_base(s, p, err)
                 : plan_columns(s, p, err))
    return -1;
  p->measured = s->given[K_ID_DATA];
  if (p->measured && p->ids.runs > 0)
    return scene_error_set(err, s->mark[K_ID_RUNS], "identify.monte_carlo.runs",
                           "the Monte Carlo draws noise on the noise-free "
                           "forces of a trajectory: not with identify.data");
  rps3_ident_opts_default(&p->opts);
  p->opts.level = p->ids.level;
  p->opts.max_iter = p->ids.max_iter;
  /* the general model: a base combination the data excite less than the
     structural base's tolerance is not excited (the helix's, at a
     condition number of 5e7, would be fitted on noise-free forces and
     be noise with any other) */
  if (p->general) p->opts.rank_tol = IDENT_BASE_TOL;
  p->ns = p->measured ? s->table[TABLE_MEASURED].n : p->c.nt;
  p->n = 3 * p->ns;
  /* the consistent fit of the general model fits every layout column */
  if (p->n <= p->p || (p->general && p->ids.consistent && p->n <= p->nlay))
    return scene_error_set(err,
                           p->measured ? s->mark[K_ID_DATA] : s->section[2],
                           p->measured ? "identify.data" : "trajectory",
                           "%zu samples give %zu force rows: more than the %zu "
                           "parameters are needed",
                           p->ns, p->n,
                           p->general && p->ids.consistent ? p->nlay : p->p);
  p->Y = malloc(p->n * p->p * sizeof *p->Y);
  p->F0 = malloc(p->n * sizeof *p->F0);
  p->ones = malloc(p->n * sizeof *p->ones);
  if (p->general) p->Ylay = malloc(p->n * p->nlay * sizeof *p->Ylay);
  if (!p->Y || !p->F0 || !p->ones || (p->general && !p->Ylay))
    return scene_error_set(err, s->identify, "identify", "out of memory");
  for (k = 0; k < p->n; k++) p->ones[k] = 1.0;
  if (plan_rows(s, p, err)) return -1;
  if (p->general)
    plan_truth_general(p);
  else {
    /* the truth: the scene's values (nominal ones for measured data); an
       off-axis payload's products of inertia are not in pi (the fit
       cannot recover them; said, not refused) */
    if (rps3_paper_params(&p->c.model, pi, &chk) != RPS3_OK)
      snprintf(p->warning, sizeof p->warning,
               "the truth is not the model's: %s", chk.msg);
    for (j = 0; j < p->p; j++) p->truth[j] = pi[p->col[j]];
    plan_truth_disc(p);
  }
  plan_shares(p);
  p->nunit = ((size_t)p->ids.runs + IDENT_UNIT - 1) / IDENT_UNIT;
  return plan_holdout(s, p, err);
}

void ident_plan_free(ident_plan *p) {
  if (!p) return;
  free(p->Y);
  free(p->F0);
  free(p->ones);
  free(p->K);
  free(p->Ylay);
  memset(p, 0, sizeof *p);
}

size_t ident_shard_draws(const ident_plan *p, size_t k, size_t n) {
  size_t j, c = 0, runs = (size_t)p->ids.runs;
  for (j = k; j < p->nunit; j = pool_next(j, n, p->nunit))
    c += (j + 1) * IDENT_UNIT < runs ? IDENT_UNIT : runs - j * IDENT_UNIT;
  return c;
}
