/*
 * compute.c - the per-sample pipeline of the runner: trajectory, inverse
 * dynamics, and the copy of the results into the output block.
 */
#include "compute.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* copy the results of sample j of the block (slot and time folded) */
static void store(const rps3_model *m, const rps3_data *d, out_block *b,
                  size_t j, double t)
{
  double *F = b->force, *Fe = b->force_by_effect, *l = b->length;
  double *dl = b->length_rate, *ddl = b->length_accel, *th = b->theta;
  double *lam = b->lambda;
  int vel = (d->stage & RPS3_STAGE_VEL) != 0;
  int acc = (d->stage & RPS3_STAGE_ACC) != 0;
  size_t ne = (size_t)b->neffect, e;
  int i;

  for (i = 0; i < 3; i++) {
    F[3 * j + i] = d->F[i];
    l[3 * j + i] = d->l[i];
    dl[3 * j + i] = vel ? d->dl[i] : (double)NAN;
    ddl[3 * j + i] = acc ? d->ddl[i] : (double)NAN;
    th[3 * j + i] = d->theta[i];
    /* lambda only exists in the Lagrange formulation */
    lam[3 * j + i] = d->has_lambda ? d->lambda[i] : (double)NAN;
    for (e = 0; e < ne; e++)
      Fe[(j * ne + e) * 3 + i] = d->F_effect[b->effect[e]][i];
  }
  ((double *)b->alpha)[j] = d->pose[0];
  ((double *)b->beta)[j] = d->pose[1];
  ((double *)b->z_c)[j] = d->pose[2];
  ((double *)b->x_c)[j] = d->c[0];
  ((double *)b->y_c)[j] = d->c[1];
  /* with certify off the library writes 0: say "not computed" instead */
  ((double *)b->energy_residual)[j] =
      m->opt.certify ? d->energy_residual : (double)NAN;
  ((double *)b->energy_scale)[j] = m->opt.certify ? d->energy_scale : (double)NAN;
  ((double *)b->condition)[j] = d->cond;
  ((double *)b->transmission)[j] = d->transmission;
  ((int32_t *)b->solve_niter)[j] = d->solve_niter;
  ((double *)b->solve_resid)[j] = d->solve_resid;
  ((int32_t *)b->warn)[j] = d->warn;
  b->t[j] = t;
}

/* the per-sample fields rps3_inverse_batch returns (and the pose, its
   input): a file of only these is computed by the batch path */
#define BIT(f) ((out_mask)1 << OUT_##f)
static const out_mask batch_fields =
    BIT(force) | BIT(force_by_effect) | BIT(length) | BIT(theta) |
    BIT(alpha) | BIT(beta) | BIT(z_c) | BIT(lambda) | BIT(energy_residual) |
    BIT(condition) | BIT(solve_niter) | BIT(warn) | BIT(status) |
    BIT(failed_at) | BIT(message) | BIT(scene_resolved);
#undef BIT

/* the trajectory could not be evaluated at sample k (time t) */
static int traj_failed(out_block *b, size_t slot, int rc, double t, size_t k,
                       const double pose[3], const double dpose[3],
                       const double ddpose[3], size_t *failed_at)
{
  /* rps3_traj_eval has no data to hold a message: name what failed */
  *failed_at = k;
  snprintf(b->msg[slot], sizeof b->msg[slot],
           "t = %.9g s (sample %zu): %s: trajectory pose (%g, %g, %g), "
           "rate (%g, %g, %g), acceleration (%g, %g, %g)", t, k,
           rps3_strerror(rc), pose[0], pose[1], pose[2], dpose[0], dpose[1],
           dpose[2], ddpose[0], ddpose[1], ddpose[2]);
  return rc;
}

/* the batch's scratch in b: OUT_BATCH points of each array */
typedef struct {
  double *t, *pose, *dpose, *ddpose, *l, *theta, *F, *lambda, *Fe, *cond,
      *er;
  int *status, *warn, *niter;
} scratch;

static void scratch_of(out_block *b, scratch *x)
{
  double *p = b->bx;
  x->t = p;
  x->pose = p += OUT_BATCH;
  x->dpose = p += 3 * OUT_BATCH;
  x->ddpose = p += 3 * OUT_BATCH;
  x->l = p += 3 * OUT_BATCH;
  x->theta = p += 3 * OUT_BATCH;
  x->F = p += 3 * OUT_BATCH;
  x->lambda = p += 3 * OUT_BATCH;
  x->Fe = p += 3 * OUT_BATCH;
  x->cond = p += 3 * RPS3_NEFFECT * OUT_BATCH;
  x->er = p + OUT_BATCH;
  x->status = b->bi;
  x->warn = b->bi + OUT_BATCH;
  x->niter = b->bi + 2 * OUT_BATCH;
}

/* copy point i of a batch of n into sample j of the block */
static void store_batch(const rps3_model *m, const scratch *x, size_t n,
                        size_t i, out_block *b, size_t j)
{
  size_t ne = (size_t)b->neffect, e;
  int c;
  for (c = 0; c < 3; c++) {
    ((double *)b->force)[3 * j + c] = x->F[c * n + i];
    ((double *)b->length)[3 * j + c] = x->l[c * n + i];
    ((double *)b->theta)[3 * j + c] = x->theta[c * n + i];
    ((double *)b->lambda)[3 * j + c] = x->lambda[c * n + i];
    for (e = 0; e < ne; e++)
      ((double *)b->force_by_effect)[(j * ne + e) * 3 + (size_t)c] =
          x->Fe[((size_t)b->effect[e] * 3 + (size_t)c) * n + i];
  }
  ((double *)b->alpha)[j] = x->pose[i];
  ((double *)b->beta)[j] = x->pose[n + i];
  ((double *)b->z_c)[j] = x->pose[2 * n + i];
  ((double *)b->energy_residual)[j] = m->opt.certify ? x->er[i] : (double)NAN;
  ((double *)b->condition)[j] = x->cond[i];
  ((int32_t *)b->solve_niter)[j] = x->niter[i];
  ((int32_t *)b->warn)[j] = x->warn[i];
  b->t[j] = x->t[i];
}

/*
 * case_compute for a file of batch_fields only: the samples OUT_BATCH at a
 * time through rps3_inverse_batch, which runs the vectorised kernel where
 * it applies (closed-form theta, Lagrange, the paper's effects: the
 * numbers agree with rps3_inverse to rounding, docs/library.md) and the
 * per-point loop elsewhere (bitwise).  A case still stops at its first
 * failing sample, with the same message.
 */
static int compute_batch(const scene_case *c, rps3_data *d, size_t k0,
                         size_t nk, out_block *b, size_t slot,
                         size_t *failed_at)
{
  const rps3_model *m = &c->model;
  scratch x;
  size_t k, i, n;
  int rc;
  scratch_of(b, &x);
  for (k = k0; k < k0 + nk; k += n) {
    rps3_batch_in in;
    rps3_batch_out out;
    n = k0 + nk - k < OUT_BATCH ? k0 + nk - k : OUT_BATCH;
    /* the trajectory, structure of arrays */
    for (i = 0; i < n; i++) {
      double p[3], dp[3], ddp[3];
      int q;
      x.t[i] = scene_case_time(c, k + i);
      rc = rps3_traj_eval(m, &c->traj, x.t[i], p, dp, ddp);
      if (rc != RPS3_OK)
        return traj_failed(b, slot, rc, x.t[i], k + i, p, dp, ddp,
                           failed_at);
      for (q = 0; q < 3; q++) {
        x.pose[(size_t)q * n + i] = p[q];
        x.dpose[(size_t)q * n + i] = dp[q];
        x.ddpose[(size_t)q * n + i] = ddp[q];
      }
    }
    memset(&in, 0, sizeof in);
    memset(&out, 0, sizeof out);
    in.n = n;
    in.pose = x.pose;
    in.dpose = x.dpose;
    in.ddpose = x.ddpose;
    out.status = x.status;
    out.warn = x.warn;
    out.l = x.l;
    out.theta = x.theta;
    out.niter = x.niter;
    out.F = x.F;
    out.F_effect = x.Fe;
    out.lambda = x.lambda;
    out.cond = x.cond;
    out.energy_residual = x.er;
    rc = rps3_inverse_batch(m, d, &in, &out);
    if (rc == RPS3_OK && out.nfail)
      rc = out.status[out.first_fail];
    if (rc != RPS3_OK) {
      /* the library's message, without the batch's "point I: " */
      const char *msg = d->err.msg, *colon = strstr(msg, ": ");
      i = out.nfail ? out.first_fail : 0;
      if (strncmp(msg, "point ", 6) == 0 && colon)
        msg = colon + 2;
      *failed_at = k + i;
      snprintf(b->msg[slot], sizeof b->msg[slot],
               "t = %.9g s (sample %zu): %s: %s", x.t[i], k + i,
               rps3_strerror(rc), msg);
      return rc;
    }
    for (i = 0; i < n; i++)
      store_batch(m, &x, n, i, b, slot * b->points + (k - k0) + i);
  }
  return RPS3_OK;
}

int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at)
{
  const rps3_model *m = &c->model;
  size_t k;
  int rc;

  if (k0 == 0)
    rps3_data_reset(d);
  if ((b->fields & ~batch_fields) == 0)
    return compute_batch(c, d, k0, nk, b, slot, failed_at);

  for (k = k0; k < k0 + nk; k++) {
    double t = scene_case_time(c, k);
    /* the pose and its rates, then the whole pipeline */
    rc = rps3_traj_eval(m, &c->traj, t, d->pose, d->dpose, d->ddpose);
    if (rc != RPS3_OK)
      return traj_failed(b, slot, rc, t, k, d->pose, d->dpose, d->ddpose,
                         failed_at);
    rc = rps3_inverse(m, d);
    if (rc != RPS3_OK) {
      *failed_at = k;
      snprintf(b->msg[slot], sizeof b->msg[slot],
               "t = %.9g s (sample %zu): %s: %s", t, k, rps3_strerror(rc),
               d->err.msg);
      return rc;
    }
    store(m, d, b, slot * b->points + (k - k0), t);
  }
  return RPS3_OK;
}
