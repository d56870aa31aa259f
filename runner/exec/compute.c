/* compute.c - the runner's per-sample pipeline: trajectory, inverse
   dynamics, the results into the output block. */
#include "compute.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* the trajectory could not be evaluated at sample k (time t) */
static int traj_failed(out_block *b, size_t slot, int rc, double t, size_t k,
                       const double pose[3], const double dpose[3],
                       const double ddpose[3], size_t *failed_at) {
  /* rps3_traj_eval has no data to hold a message: name what failed */
  *failed_at = k;
  snprintf(b->msg[slot], sizeof b->msg[slot],
           "t = %.9g s (sample %zu): %s: trajectory pose (%g, %g, %g), "
           "rate (%g, %g, %g), acceleration (%g, %g, %g)",
           t, k, rps3_strerror(rc), pose[0], pose[1], pose[2], dpose[0],
           dpose[1], dpose[2], ddpose[0], ddpose[1], ddpose[2]);
  return rc;
}

/* dst[stride i + c] = src[c n + i]: a [3][n] array of the batch into
   the block's rows of `stride` values */
static void store3(double *dst, const double *src, size_t n, size_t stride) {
  size_t i;
  for (i = 0; i < n; i++) {
    dst[stride * i] = src[i];
    dst[stride * i + 1] = src[n + i];
    dst[stride * i + 2] = src[2 * n + i];
  }
}

/* the batch of n points into samples j .. j + n - 1 of the block, one
   field at a time (each a sequential stream of writes), the fields the
   file gets; the batch wrote condition, transmission, the energy residual
   and scale and the solve residual into the block itself */
static void store_batch(const rps3_batch_in *in, const rps3_batch_out *x,
                        out_block *b, size_t j) {
  const size_t n = in->n;
  /* the [3][n] outputs, and the one-column ones */
  const struct {
    int field;
    const double *src;
  } three[] = {{OUT_force, x->F},        {OUT_length, x->l},
               {OUT_theta, x->theta},    {OUT_lambda, x->lambda},
               {OUT_length_rate, x->dl}, {OUT_length_accel, x->ddl}},
    one[] = {{OUT_alpha, in->pose},
             {OUT_beta, in->pose + n},
             {OUT_z_c, in->pose + 2 * n},
             {OUT_x_c, x->c},
             {OUT_y_c, x->c + n}};
  const size_t ne = (size_t)b->neffect;
  double *fe = (double *)b->buf[OUT_force_by_effect] + j * ne * 3;
  int32_t *niter = (int32_t *)b->buf[OUT_solve_niter] + j,
          *warn = (int32_t *)b->buf[OUT_warn] + j;
  size_t i, e, f;
  for (f = 0; f < sizeof three / sizeof three[0]; f++)
    if (OUT_HAS(b->fields, three[f].field))
      store3((double *)b->buf[three[f].field] + 3 * j, three[f].src, n, 3);
  for (f = 0; f < sizeof one / sizeof one[0]; f++)
    if (OUT_HAS(b->fields, one[f].field))
      memcpy((double *)b->buf[one[f].field] + j, one[f].src,
             n * sizeof(double));
  for (e = 0; e < ne && OUT_HAS(b->fields, OUT_force_by_effect); e++)
    store3(fe + 3 * e, x->F_effect + (size_t)b->effect[e] * 3 * n, n, 3 * ne);
  memcpy(b->t + j, b->bx, n * sizeof(double));
  for (i = 0; i < n; i++) {
    niter[i] = x->niter[i];
    warn[i] = x->warn[i];
  }
}

/* the batch's scratch in b->bx: the times, then OUT_BATCH points of each
   array, structure of arrays */
#define POSE(b) ((b)->bx + OUT_BATCH)
#define DPOSE(b) (POSE(b) + 3 * OUT_BATCH)
#define DDPOSE(b) (DPOSE(b) + 3 * OUT_BATCH)

/* the trajectory at samples k .. k + n - 1 into b's scratch, up to a
   sample it cannot give: returns the samples it gave (the batch, packed
   to their number) and the status of the one after in *trc, its pose and
   rates in p, dp, ddp */
static size_t batch_traj(const scene_case *c, out_block *b, size_t k, size_t n,
                         int *trc, double p[3], double dp[3], double ddp[3]) {
  /* the pose, its rate and acceleration: [3][n] each, 3 OUT_BATCH apart */
  double *t = b->bx, *pose = POSE(b);
  const double *val[3] = {p, dp, ddp};
  size_t i, q, a;
  *trc = RPS3_OK;
  for (i = 0; i < n; i++) {
    t[i] = scene_case_time(c, k + i);
    *trc = rps3_traj_eval(&c->model, &c->traj, t[i], p, dp, ddp);
    if (*trc != RPS3_OK) break;
    for (a = 0; a < 3; a++)
      for (q = 0; q < 3; q++) pose[3 * OUT_BATCH * a + q * n + i] = val[a][q];
  }
  /* the i samples before a failure, packed to a batch of i */
  for (a = 0; i < n && a < 3; a++)
    for (q = 1; q < 3; q++)
      memmove(pose + 3 * OUT_BATCH * a + q * i,
              pose + 3 * OUT_BATCH * a + q * n, i * sizeof(double));
  return i;
}

/* the batch's inputs and outputs: the scratch after the poses, and the
   per-point values of one column straight into the block at row j */
static void batch_io(out_block *b, size_t n, size_t j, rps3_batch_in *in,
                     rps3_batch_out *out) {
  double *p = DDPOSE(b) + 3 * OUT_BATCH;
  memset(in, 0, sizeof *in);
  memset(out, 0, sizeof *out);
  in->n = n;
  in->pose = POSE(b);
  in->dpose = DPOSE(b);
  in->ddpose = DDPOSE(b);
  out->l = p;
  out->theta = p += 3 * OUT_BATCH;
  out->F = p += 3 * OUT_BATCH;
  out->lambda = p += 3 * OUT_BATCH;
  out->F_effect = p += 3 * OUT_BATCH;
  out->dl = p += 3 * RPS3_NEFFECT * OUT_BATCH;
  out->ddl = p += 3 * OUT_BATCH;
  out->c = p + 3 * OUT_BATCH;
  out->status = b->bi;
  out->warn = b->bi + OUT_BATCH;
  out->niter = b->bi + 2 * OUT_BATCH;
  out->cond = (double *)b->buf[OUT_condition] + j;
  out->energy_residual = (double *)b->buf[OUT_energy_residual] + j;
  out->transmission = (double *)b->buf[OUT_transmission] + j;
  out->energy_scale = (double *)b->buf[OUT_energy_scale] + j;
  out->solve_resid = (double *)b->buf[OUT_solve_resid] + j;
}

/* the batch failed with rc at sample k + i: the case's message, without
   the batch's "point I: " */
static int batch_failed(const rps3_data *d, int rc, size_t k, size_t i,
                        out_block *b, size_t slot, size_t *failed_at) {
  const char *msg = d->err.msg, *colon = strstr(msg, ": ");
  if (strncmp(msg, "point ", 6) == 0 && colon) msg = colon + 2;
  *failed_at = k + i;
  snprintf(b->msg[slot], sizeof b->msg[slot], "t = %.9g s (sample %zu): %s: %s",
           b->bx[i], k + i, rps3_strerror(rc), msg);
  return rc;
}

/* case_compute: the samples OUT_BATCH at a time through rps3_inverse_batch,
   which runs the vectorised kernel where it applies (closed-form theta,
   Lagrange, the paper's effects: the numbers agree with rps3_inverse to
   rounding, docs/library.md) and the per-point loop elsewhere (bitwise).  A
   case still stops at its first failing sample, with the same message. */
int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at) {
  size_t k, n;
  if (k0 == 0) rps3_data_reset(d);
  for (k = k0; k < k0 + nk; k += n) {
    rps3_batch_in in;
    rps3_batch_out out;
    double p[3], dp[3], ddp[3];
    const size_t j = slot * b->points + (k - k0);
    int trc, rc;
    /* the trajectory up to a sample it cannot give: the samples before it
       are computed first, and one of them failing is the case's first
       failure */
    n = k0 + nk - k < OUT_BATCH ? k0 + nk - k : OUT_BATCH;
    n = batch_traj(c, b, k, n, &trc, p, dp, ddp);
    if (n == 0)
      return traj_failed(b, slot, trc, b->bx[0], k, p, dp, ddp, failed_at);
    batch_io(b, n, j, &in, &out);
    rc = rps3_inverse_batch(&c->model, d, &in, &out);
    if (rc == RPS3_OK && out.nfail) rc = out.status[out.first_fail];
    if (rc != RPS3_OK)
      return batch_failed(d, rc, k, out.nfail ? out.first_fail : 0, b, slot,
                          failed_at);
    if (trc != RPS3_OK)
      return traj_failed(b, slot, trc, b->bx[n], k + n, p, dp, ddp, failed_at);
    store_batch(&in, &out, b, j);
  }
  return RPS3_OK;
}

rps3_data *case_workspace(rps3_data *ws[RPS3_NSOLVER], const scene_case *c,
                          char *err, size_t errsz) {
  int k = (int)c->model.opt.solver;
  if (!ws[k]) {
    int rc = rps3_data_alloc(&c->model, &ws[k]);
    if (rc != RPS3_OK) {
      snprintf(err, errsz, "cannot allocate a workspace: %s",
               rps3_strerror(rc));
      return NULL;
    }
  }
  return ws[k];
}

void case_workspaces_free(rps3_data *ws[RPS3_NSOLVER]) {
  int k;
  for (k = 0; k < RPS3_NSOLVER; k++) rps3_data_free(ws[k]);
}
