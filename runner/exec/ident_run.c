/* ident_run.c - see ident_run.h: the plan and one fit. */
#include "ident_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* row block k of Y and F0: the trajectory at sample k, its inverse
   dynamics and regressor; 0 or the failing status with d->err */
static int plan_sample(ident_plan *p, rps3_data *d, size_t k, double *t) {
  const rps3_model *m = &p->c.model;
  double Yk[3][RPS3_NPAPER];
  size_t i, j;
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
  if ((rc = rps3_regressor(m, d, Yk)) != RPS3_OK) return rc;
  for (i = 0; i < 3; i++)
    for (j = 0; j < p->p; j++) p->Y[(3 * k + i) * p->p + j] = Yk[i][p->col[j]];
  return RPS3_OK;
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
  double Yk[3][RPS3_NPAPER];
  size_t i, j;
  int rc;
  memcpy(d->l, t->value[k], sizeof d->l);
  if ((rc = rps3_fk(m, d)) != RPS3_OK) return rc;
  memcpy(d->dl, t->rate[k], sizeof d->dl);
  if ((rc = rps3_joint_velocity(m, d)) != RPS3_OK ||
      (rc = pose_accel(m, d, d2, t->acc[k])) != RPS3_OK ||
      (rc = rps3_regressor(m, d, Yk)) != RPS3_OK)
    return rc;
  for (i = 0; i < 3; i++) {
    p->F0[3 * k + i] = t->force[k][i];
    for (j = 0; j < p->p; j++) p->Y[(3 * k + i) * p->p + j] = Yk[i][p->col[j]];
  }
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

int ident_plan_make(const scene *s, ident_plan *p, scene_error *err) {
  double pi[RPS3_NPAPER];
  rps3_check chk;
  size_t k, j;
  memset(p, 0, sizeof *p);
  if (scene_case_build(s, 0, &p->c, err) || plan_columns(s, p, err)) return -1;
  p->ids = s->base.ids;
  p->measured = s->given[K_ID_DATA];
  if (p->measured && p->ids.runs > 0)
    return scene_error_set(err, s->mark[K_ID_RUNS], "identify.monte_carlo.runs",
                           "the Monte Carlo draws noise on the noise-free "
                           "forces of a trajectory: not with identify.data");
  rps3_ident_opts_default(&p->opts);
  p->opts.level = p->ids.level;
  p->ns = p->measured ? s->table[TABLE_MEASURED].n : p->c.nt;
  p->n = 3 * p->ns;
  if (p->n <= p->p)
    return scene_error_set(err,
                           p->measured ? s->mark[K_ID_DATA] : s->section[2],
                           p->measured ? "identify.data" : "trajectory",
                           "%zu samples give %zu force rows: more than the %zu "
                           "parameters are needed",
                           p->ns, p->n, p->p);
  p->Y = malloc(p->n * p->p * sizeof *p->Y);
  p->F0 = malloc(p->n * sizeof *p->F0);
  p->ones = malloc(p->n * sizeof *p->ones);
  if (!p->Y || !p->F0 || !p->ones)
    return scene_error_set(err, s->identify, "identify", "out of memory");
  for (k = 0; k < p->n; k++) p->ones[k] = 1.0;
  if (plan_rows(s, p, err)) return -1;
  /* the truth: the scene's values (nominal ones for measured data); an
     off-axis payload's products of inertia are not in pi (the fit cannot
     recover them; said, not refused) */
  if (rps3_paper_params(&p->c.model, pi, &chk) != RPS3_OK)
    snprintf(p->warning, sizeof p->warning, "the truth is not the model's: %s",
             chk.msg);
  for (j = 0; j < p->p; j++) p->truth[j] = pi[p->col[j]];
  plan_shares(p);
  p->nunit = ((size_t)p->ids.runs + IDENT_UNIT - 1) / IDENT_UNIT;
  return 0;
}

void ident_plan_free(ident_plan *p) {
  if (!p) return;
  free(p->Y);
  free(p->F0);
  free(p->ones);
  memset(p, 0, sizeof *p);
}

size_t ident_shard_draws(const ident_plan *p, size_t k, size_t n) {
  size_t j, c = 0, runs = (size_t)p->ids.runs;
  for (j = k; j < p->nunit; j = pool_next(j, n, p->nunit))
    c += (j + 1) * IDENT_UNIT < runs ? IDENT_UNIT : runs - j * IDENT_UNIT;
  return c;
}

/* the consistent fit of the chosen columns: the paper layout restricted to
   them and renumbered (python/rps3/ident_c.py paper_layout) */
static void fit_consistent(const ident_plan *p, const rps3_ident_data *data,
                           ident_fit *r) {
  const rps3_ident_layout *pl = rps3_ident_paper_layout();
  int col[2][10], kind[RPS3_NPAPER], where[RPS3_NPAPER];
  rps3_ident_layout lay;
  rps3_ident_fit fit;
  rps3_check chk;
  size_t b, j;
  int k;
  for (k = 0; k < RPS3_NPAPER; k++) where[k] = -1;
  for (j = 0; j < p->p; j++) {
    where[p->col[j]] = (int)j;
    kind[j] = pl->kind ? pl->kind[p->col[j]] : RPS3_IDENT_FREE;
  }
  for (b = 0; b < 2 && b < pl->nbody; b++)
    for (k = 0; k < 10; k++)
      col[b][k] = pl->col[b][k] >= 0 ? where[pl->col[b][k]] : -1;
  lay.nbody = pl->nbody < 2 ? pl->nbody : 2;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  memset(&fit, 0, sizeof fit);
  fit.theta = r->ctheta;
  fit.body = &r->body[0][0];
  fit.eig = &r->eig[0][0];
  r->cstatus = rps3_ident_consistent(data, &lay, &p->opts, &fit, &chk);
  r->consistent = fit.consistent;
  r->crss = fit.rss;
  r->gap = fit.gap;
  r->niter = fit.niter;
  snprintf(r->cmsg, sizeof r->cmsg, "%s", r->cstatus == RPS3_OK ? "" : chk.msg);
}

void ident_fit_run(const ident_plan *p, const double *F, int consistent,
                   ident_fit *r) {
  rps3_ident_data data = {p->n, p->p, p->Y, F, NULL, NULL, p->names};
  rps3_ident_result res;
  rps3_check chk;
  size_t i, j;
  double ss = 0;
  memset(r, 0, sizeof *r);
  r->cstatus = -1;
  data.weight = p->ids.method == IDENT_OLS ? p->ones : NULL;
  memset(&res, 0, sizeof res);
  res.theta = r->theta;
  res.cov = r->cov;
  res.ci = &r->ci[0][0];
  res.unident = r->unident;
  r->status = rps3_ident_wls(&data, &p->opts, &res, &chk);
  snprintf(r->msg, sizeof r->msg, "%s", r->status == RPS3_OK ? "" : chk.msg);
  for (i = 0; i < 3; i++) r->sigma[i] = res.sigma[i];
  r->s2 = res.s2;
  r->cond = res.cond;
  r->rank = res.rank;
  r->dof = res.dof;
  for (j = 0; j < p->p; j++) r->std[j] = sqrt(r->cov[j * p->p + j]);
  for (i = 0; i < p->n; i++) {
    double e = F[i];
    for (j = 0; j < p->p; j++) e -= p->Y[i * p->p + j] * r->theta[j];
    ss += e * e;
  }
  r->resid_rms = sqrt(ss / (double)p->n);
  if (consistent && r->status == RPS3_OK) fit_consistent(p, &data, r);
}
