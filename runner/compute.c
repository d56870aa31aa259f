/*
 * compute.c - the per-sample pipeline of the runner: trajectory, inverse
 * dynamics, and the copy of the results into the output block.
 */
#include "compute.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

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

int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at)
{
  const rps3_model *m = &c->model;
  size_t k;
  int rc;

  if (k0 == 0)
    rps3_data_reset(d);
  for (k = k0; k < k0 + nk; k++) {
    double t = scene_case_time(c, k);
    /* the pose and its rates, then the whole pipeline */
    rc = rps3_traj_eval(m, &c->traj, t, d->pose, d->dpose, d->ddpose);
    if (rc != RPS3_OK) {
      /* rps3_traj_eval has no data to hold a message: name what failed */
      *failed_at = k;
      snprintf(b->msg[slot], sizeof b->msg[slot],
               "t = %.9g s (sample %zu): %s: trajectory pose (%g, %g, %g), "
               "rate (%g, %g, %g), acceleration (%g, %g, %g)", t, k,
               rps3_strerror(rc), d->pose[0], d->pose[1], d->pose[2],
               d->dpose[0], d->dpose[1], d->dpose[2], d->ddpose[0],
               d->ddpose[1], d->ddpose[2]);
      return rc;
    }
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
