/*
 * batch.c - the per-point stages over n points in one call: structure of
 * arrays in and out, one workspace, no allocation.  Each point goes through
 * the same public stage function a caller's loop would call, so the
 * results are bitwise those of that loop; a point that fails is recorded
 * and the next one is computed.
 */
#include <stdint.h>
#include <string.h>

#include "batch_kernel.h"
#include "internal.h"

/* component c of point i in a component-major array of n points */
#define AT(a, c, i, n) ((a)[(size_t)(c) * (n) + (i)])

/* which stage a batch runs */
typedef enum { BATCH_INVERSE, BATCH_IK, BATCH_FK } batch_kind;

/* the checks common to every batch function: a call that fails them
   computes nothing */
static int check_call(const rps3_model *m, rps3_data *d,
                      const rps3_batch_in *in, const rps3_batch_out *out,
                      const double *input, const char *input_name) {
  if (d == NULL) return RPS3_EINVAL;
  if (m == NULL || !m->valid)
    RPS3_ERROR(d, RPS3_EINVAL, "model is NULL or not initialised");
  if (in == NULL || out == NULL)
    RPS3_ERROR(d, RPS3_EINVAL, "batch %s is NULL", in == NULL ? "in" : "out");
  /* the largest index is RPS3_NEFFECT * 3 * n - 1 (F_effect) */
  if (in->n > SIZE_MAX / (3 * RPS3_NEFFECT))
    RPS3_ERROR(d, RPS3_EINVAL, "batch n = %lu is too large",
               (unsigned long)in->n);
  if (in->n > 0 && out->status == NULL)
    RPS3_ERROR(d, RPS3_EINVAL, "batch out.status is NULL");
  if (in->n > 0 && input == NULL)
    RPS3_ERROR(d, RPS3_EINVAL, "batch in.%s is NULL", input_name);
  return RPS3_OK;
}

/* NaN into the floating-point outputs of failed point i */
static void set_failed(rps3_batch_out *out, size_t i, size_t n) {
  const double nan = (double)NAN;
  int c, k;
  for (c = 0; c < 3; c++) {
    if (out->pose) AT(out->pose, c, i, n) = nan;
    if (out->l) AT(out->l, c, i, n) = nan;
    if (out->theta) AT(out->theta, c, i, n) = nan;
    if (out->F) AT(out->F, c, i, n) = nan;
    if (out->lambda) AT(out->lambda, c, i, n) = nan;
    for (k = 0; k < RPS3_NEFFECT && out->F_effect; k++)
      AT(out->F_effect, 3 * k + c, i, n) = nan;
  }
  for (c = 0; c < 3; c++) {
    if (out->dl) AT(out->dl, c, i, n) = nan;
    if (out->ddl) AT(out->ddl, c, i, n) = nan;
    if (out->c) AT(out->c, c, i, n) = nan;
  }
  if (out->cond) out->cond[i] = nan;
  if (out->energy_residual) out->energy_residual[i] = nan;
  if (out->transmission) out->transmission[i] = nan;
  if (out->energy_scale) out->energy_scale[i] = nan;
  if (out->solve_resid) out->solve_resid[i] = nan;
}

/* the results of point i, read from the data as the stage left them */
static void store(const rps3_data *d, batch_kind kind, rps3_batch_out *out,
                  size_t i, size_t n) {
  int c, k;
  for (c = 0; c < 3; c++) {
    if (out->pose && kind == BATCH_FK) AT(out->pose, c, i, n) = d->pose[c];
    if (out->l && kind != BATCH_FK) AT(out->l, c, i, n) = d->l[c];
    if (out->theta) AT(out->theta, c, i, n) = d->theta[c];
    if (kind != BATCH_INVERSE) continue;
    if (out->F) AT(out->F, c, i, n) = d->F[c];
    if (out->lambda)
      AT(out->lambda, c, i, n) = d->has_lambda ? d->lambda[c] : (double)NAN;
    for (k = 0; k < RPS3_NEFFECT && out->F_effect; k++)
      AT(out->F_effect, 3 * k + c, i, n) = d->F_effect[k][c];
  }
  for (c = 0; c < 3; c++)
    if (out->c) AT(out->c, c, i, n) = d->c[c];
  if (kind != BATCH_IK && out->solve_resid)
    out->solve_resid[i] = d->solve_resid;
  if (kind == BATCH_INVERSE) {
    /* the rates as the stages left them: NaN when they did not run */
    const double nan = (double)NAN;
    int vel = (d->stage & RPS3_STAGE_VEL) != 0;
    int acc = (d->stage & RPS3_STAGE_ACC) != 0;
    for (c = 0; c < 3; c++) {
      if (out->dl) AT(out->dl, c, i, n) = vel ? d->dl[c] : nan;
      if (out->ddl) AT(out->ddl, c, i, n) = acc ? d->ddl[c] : nan;
    }
    if (out->cond) out->cond[i] = d->cond;
    if (out->energy_residual) out->energy_residual[i] = d->energy_residual;
    if (out->transmission) out->transmission[i] = d->transmission;
    if (out->energy_scale) out->energy_scale[i] = d->energy_scale;
  }
}

/* the inputs of point i into the data; a non-finite guess is the point's
   own error (rps3_theta_solve would silently start cold instead) */
static int load(rps3_data *d, batch_kind kind, const rps3_batch_in *in,
                size_t i) {
  size_t n = in->n;
  int c;
  for (c = 0; c < 3; c++) {
    if (kind == BATCH_FK) {
      d->l[c] = AT(in->l, c, i, n);
      if (in->guess) d->theta[c] = AT(in->guess, c, i, n);
    } else {
      d->pose[c] = AT(in->pose, c, i, n);
      d->dpose[c] = in->dpose ? AT(in->dpose, c, i, n) : 0.0;
      d->ddpose[c] = in->ddpose ? AT(in->ddpose, c, i, n) : 0.0;
    }
  }
  if (kind == BATCH_FK && in->guess) {
    if (!v3_finite(d->theta))
      RPS3_ERROR(d, RPS3_EINVAL, "guess (%g, %g, %g) is not finite",
                 d->theta[0], d->theta[1], d->theta[2]);
    d->have_theta = 1;
  }
  return RPS3_OK;
}

/* prefix the data's message with the point index, once, for the first
   failing point (the message is then kept to the end of the call) */
static void name_point(rps3_data *d, int status, size_t i) {
  char prefix[32];
  size_t np, len, cap = sizeof(d->err.msg) - 1;
  if (d->err.code != status) {
    /* a stage returned without raising (cannot happen for a point of a
       valid call, kept so that the message is never stale) */
    d->err.code = status;
    d->err.func = "batch";
    d->err.file = __FILE__;
    d->err.line = __LINE__;
    snprintf(d->err.msg, sizeof(d->err.msg), "%s", rps3_strerror(status));
  }
  /* shift the message right and write the prefix before it, cutting the
     end of a message that no longer fits */
  np =
      (size_t)snprintf(prefix, sizeof(prefix), "point %lu: ", (unsigned long)i);
  len = strlen(d->err.msg);
  if (np + len > cap) len = cap - np;
  memmove(d->err.msg + np, d->err.msg, len);
  memcpy(d->err.msg, prefix, np);
  d->err.msg[np + len] = '\0';
}

/* point i by the scalar stage; the first failure's message is kept in
 *first */
static void point(const rps3_model *m, rps3_data *d, batch_kind kind,
                  const rps3_batch_in *in, rps3_batch_out *out, size_t i,
                  rps3_error *first) {
  size_t n = in->n;
  int status = load(d, kind, in, i);
  if (status == RPS3_OK) {
    if (kind == BATCH_INVERSE)
      status = rps3_inverse_stages(m, d);
    else if (kind == BATCH_IK)
      status = rps3_ik(m, d);
    else
      status = rps3_fk(m, d);
  }
  out->status[i] = status;
  if (out->warn) out->warn[i] = d->warn;
  if (out->niter) out->niter[i] = kind == BATCH_IK ? 0 : d->solve_niter;
  if (status == RPS3_OK) {
    store(d, kind, out, i, n);
    return;
  }
  set_failed(out, i, n);
  if (out->nfail++ == 0) {
    out->first_fail = i;
    name_point(d, status, i);
    *first = d->err;
  }
}

/* component c of a batch array from point i0, or the block's scratch
   when the caller did not ask for the array */
static double *dst(double *user, int c, size_t i0, size_t n, double *scratch) {
  return user ? user + (size_t)c * n + i0 : scratch;
}

/* the statuses of a block the kernel computed: a point it did not certify
   goes through the scalar path (its status, warnings and outputs), a
   certified one has no warning and no solve */
static void finish_block(const rps3_model *m, rps3_data *d,
                         const rps3_batch_in *in, rps3_batch_out *out,
                         size_t i0, int nb, const rps3_kblock *kb,
                         rps3_error *first) {
  int p;
  for (p = 0; p < nb; p++) {
    size_t i = i0 + (size_t)p;
    if (kb->ok[p] == 0.0) {
      point(m, d, BATCH_INVERSE, in, out, i, first);
      continue;
    }
    out->status[i] = RPS3_OK;
    if (out->warn) out->warn[i] = 0;
    if (out->niter) out->niter[i] = 0;
  }
}

/* NaN into component c of a batch output at the points of the block
   that computed (status RPS3_OK) */
static void lean_fill(double *a, int c, size_t i0, int nb, size_t n,
                      const int *status, double v) {
  int p;
  if (a == NULL) return;
  for (p = 0; p < nb; p++)
    if (status[i0 + (size_t)p] == RPS3_OK) AT(a, c, i0 + (size_t)p, n) = v;
}

/* NaN into the arrays of the outputs left out of opt.outputs at the
   points of the block that computed, as rps3_outputs_clear leaves d (and
   theta, on the kernel's closed-form route); lean: the leanest pass, which
   writes F and cond alone */
static void clear_block(const rps3_model *m, rps3_batch_out *out, size_t i0,
                        int nb, size_t n) {
  const double nan = (double)NAN;
  const int o = m->opt.outputs;
  const int *st = out->status;
  int c, k;
  for (c = 0; c < 3; c++) {
    if (!(o & RPS3_OUT_FORCES)) lean_fill(out->F, c, i0, nb, n, st, nan);
    if (!(o & RPS3_OUT_THETA)) lean_fill(out->theta, c, i0, nb, n, st, nan);
    if (!(o & RPS3_OUT_LAMBDA)) lean_fill(out->lambda, c, i0, nb, n, st, nan);
    for (k = 0; k < RPS3_NEFFECT && !(o & RPS3_OUT_EFFECTS); k++)
      lean_fill(out->F_effect, 3 * k + c, i0, nb, n, st, nan);
  }
  if (!(o & RPS3_OUT_TRANSMISSION))
    lean_fill(out->transmission, 0, i0, nb, n, st, nan);
  if (!(o & RPS3_OUT_CERTIFY)) {
    lean_fill(out->energy_residual, 0, i0, nb, n, st, nan);
    lean_fill(out->energy_scale, 0, i0, nb, n, st, nan);
  }
}

/* the points i0 .. i0 + nb - 1 of rps3_inverse_batch through the kernel,
   which writes into the caller's arrays; then the points it does not
   certify by the scalar path, which overwrites them */
static void kernel_block(const rps3_model *m, rps3_data *d,
                         const rps3_batch_in *in, rps3_batch_out *out,
                         size_t i0, int nb, int rates, rps3_kblock *kb,
                         rps3_error *first) {
  size_t n = in->n;
  rps3_kout o;
  int c, k, p;
  rps3_kout_of_block(&o, kb);
  for (c = 0; c < 3; c++) {
    o.l[c] = dst(out->l, c, i0, n, o.l[c]);
    o.theta[c] = dst(out->theta, c, i0, n, o.theta[c]);
    o.F[c] = dst(out->F, c, i0, n, o.F[c]);
    o.lambda[c] = dst(out->lambda, c, i0, n, o.lambda[c]);
    for (k = 0; k < RPS3_KNEFF; k++)
      o.Fe[k][c] = dst(out->F_effect, 3 * k + c, i0, n, o.Fe[k][c]);
  }
  for (c = 0; c < 3; c++) {
    o.dl[c] = dst(out->dl, c, i0, n, o.dl[c]);
    o.ddl[c] = dst(out->ddl, c, i0, n, o.ddl[c]);
  }
  o.c[0] = dst(out->c, 0, i0, n, o.c[0]);
  o.c[1] = dst(out->c, 1, i0, n, o.c[1]);
  o.cond = dst(out->cond, 0, i0, n, o.cond);
  o.trans = dst(out->transmission, 0, i0, n, o.trans);
  o.eres = dst(out->energy_residual, 0, i0, n, o.eres);
  o.scale = dst(out->energy_scale, 0, i0, n, o.scale);
  /* neither theta nor the certificate when no one reads them; the
     summed load solved once only where rps3_inverse solves it so
     (rps3_kernel_summed), so that every point is bitwise what
     rps3_inverse gives it */
  rps3_kernel_block(m, in, i0, nb, rates,
                    rps3_kernel_summed(m) ? RPS3_KFORCES
                    : (m->opt.outputs & RPS3_OUT_CERTIFY) ||
                            (out->theta && (m->opt.outputs & RPS3_OUT_THETA))
                        ? RPS3_KFULL
                        : RPS3_KLEAN,
                    &o);
  /* z_c is the pose's own; without rates (no effect nor the certificate
     needs them) the rates are not computed, as in rps3_inverse; closed
     form: no solve */
  if (out->c)
    memcpy(out->c + 2 * n + i0, in->pose + 2 * n + i0,
           (size_t)nb * sizeof(double));
  for (c = 0; c < 3 && !rates; c++)
    for (p = 0; p < nb; p++) {
      if (out->dl) AT(out->dl, c, i0 + (size_t)p, n) = (double)NAN;
      if (out->ddl) AT(out->ddl, c, i0 + (size_t)p, n) = (double)NAN;
    }
  if (out->solve_resid)
    memset(out->solve_resid + i0, 0, (size_t)nb * sizeof(double));
  /* the shares of effects not selected are exactly zero */
  for (c = 0; c < 3; c++)
    for (k = 0; k < RPS3_NEFFECT && out->F_effect; k++)
      if (k >= RPS3_KNEFF || !(m->opt.effects & (1 << k)))
        memset(out->F_effect + (size_t)(3 * k + c) * n + i0, 0,
               (size_t)nb * sizeof(double));
  finish_block(m, d, in, out, i0, nb, kb, first);
  /* the outputs left out: NaN, as rps3_inverse leaves them (the scalar
     path's points are NaN already) */
  clear_block(m, out, i0, nb, n);
}

/* outputs = RPS3_OUT_FORCES: the points i0 .. i0 + nb - 1 through the
   leanest pass, F and cond into the caller's arrays, the points it does
   not keep by the scalar path; then, as rps3_inverse leaves nothing else
   for them, NaN into every other output of the points computed */
static void lean_block(const rps3_model *m, rps3_data *d,
                       const rps3_batch_in *in, rps3_batch_out *out, size_t i0,
                       int nb, int rates, rps3_kblock *kb, rps3_error *first) {
  const double nan = (double)NAN;
  size_t n = in->n;
  double *F[3];
  int c, p;
  for (c = 0; c < 3; c++) F[c] = dst(out->F, c, i0, n, kb->F[c]);
  rps3_kernel_block_bare(m, in, i0, nb, rates, F,
                         dst(out->cond, 0, i0, n, kb->cond), kb->ok);
  finish_block(m, d, in, out, i0, nb, kb, first);
  clear_block(m, out, i0, nb, n);
  /* the pass's own points have no kinematics (rps3_inverse leaves l, c,
     dl, ddl NaN for them); the stages' points keep theirs */
  for (p = 0;
       p < nb && (out->l || out->dl || out->ddl || out->c || out->solve_resid);
       p++) {
    size_t i = i0 + (size_t)p;
    if (kb->ok[p] == 0.0) continue;
    for (c = 0; c < 3; c++) {
      if (out->l) AT(out->l, c, i, n) = nan;
      if (out->dl) AT(out->dl, c, i, n) = nan;
      if (out->ddl) AT(out->ddl, c, i, n) = nan;
      if (out->c) AT(out->c, c, i, n) = nan;
    }
    if (out->solve_resid) out->solve_resid[i] = nan;
  }
}

int rps3_inverse_kernel_point(const rps3_model *m, rps3_data *d) {
  /* without shares, theta and the certificate the pass solves the summed
     load once; either way d is left as the stages leave it */
  const int lean = rps3_kernel_summed(m);
  const int need_rates = rps3_need_rates(m);
  rps3_batch_in in;
  rps3_kout o;
  double theta[3], Fe[RPS3_KNEFF][3], eres, scale, mode, ok;
  int c, k;
  /* a component-major batch of one point is the data's own arrays */
  memset(&in, 0, sizeof(in));
  in.n = 1;
  in.pose = d->pose;
  in.dpose = d->dpose;
  in.ddpose = d->ddpose;
  for (c = 0; c < 3; c++) {
    o.l[c] = &d->l[c];
    o.theta[c] = lean ? &theta[c] : &d->theta[c];
    o.F[c] = &d->F[c];
    o.lambda[c] = &d->lambda[c];
    o.dl[c] = &d->dl[c];
    o.ddl[c] = &d->ddl[c];
    for (k = 0; k < RPS3_KNEFF; k++)
      o.Fe[k][c] = lean ? &Fe[k][c] : &d->F_effect[k][c];
  }
  o.c[0] = &d->c[0];
  o.c[1] = &d->c[1];
  o.cond = &d->cond;
  o.trans = &d->transmission;
  o.eres = &eres;
  o.scale = &scale;
  o.mode = &mode;
  o.ok = &ok;
  o.d = d;
  rps3_kernel_block(m, &in, 0, 1, need_rates, lean ? RPS3_KFORCES : RPS3_KDATA,
                    &o);
  if (ok == 0.0) return 0;
  d->c[2] = d->pose[2];
  for (c = 0; c < 3; c++) {
    /* theta by (39) only when asked for (rps3.h, RPS3_OUT_THETA) */
    if (!(m->opt.outputs & RPS3_OUT_THETA)) d->theta[c] = (double)NAN;
    if (!need_rates) d->dl[c] = d->ddl[c] = (double)NAN;
  }
  /* the effects beyond the kernel's four are not selected */
  for (k = RPS3_KNEFF; k < RPS3_NEFFECT; k++)
    for (c = 0; c < 3; c++) d->F_effect[k][c] = 0.0;
  d->has_lambda = 1;
  d->mode = (int)mode;
  d->warn = 0;
  d->energy_residual = eres;
  d->energy_scale = scale;
  /* the outputs left out: NaN (the shares of the summed solve included) */
  rps3_outputs_clear(m, d);
  /* everything the stages leave: positions (theta by (39) when asked
     for), rates and accelerations when needed, the dynamics */
  d->have_theta = (m->opt.outputs & RPS3_OUT_THETA) != 0;
  d->stage = RPS3_STAGE_POS | RPS3_STAGE_DYN |
             (need_rates ? RPS3_STAGE_VEL | RPS3_STAGE_ACC : 0);
  return 1;
}

/* the loop shared by the three batch functions */
static void run(const rps3_model *m, rps3_data *d, batch_kind kind,
                const rps3_batch_in *in, rps3_batch_out *out) {
  size_t i, n = in->n;
  rps3_error first;
  memset(&first, 0, sizeof(first));
  out->nfail = 0;
  out->first_fail = n;
  for (i = 0; i < n; i++) point(m, d, kind, in, out, i, &first);
  /* the first failure's message, not the last one's */
  if (out->nfail > 0) d->err = first;
}

int rps3_inverse_batch(const rps3_model *m, rps3_data *d,
                       const rps3_batch_in *in, rps3_batch_out *out) {
  int status, need_rates;
  status = check_call(m, d, in, out, in ? in->pose : NULL, "pose");
  if (status != RPS3_OK) return status;
  /* the rates are read only when an effect (or the certificate) needs
     them, as in rps3_inverse */
  need_rates = rps3_need_rates(m);
  if (need_rates && in->n > 0 && (in->dpose == NULL || in->ddpose == NULL))
    RPS3_ERROR(d, RPS3_EINVAL,
               "batch in.%s is NULL, and the selected effects or the "
               "certificate need rates and accelerations",
               in->dpose == NULL ? "dpose" : "ddpose");
  if (!rps3_kernel_covers(m)) {
    run(m, d, BATCH_INVERSE, in, out);
    return RPS3_OK;
  }
  {
    rps3_kblock kb; /* one block's results, on the stack */
    rps3_error first;
    size_t i0, n = in->n;
    memset(&first, 0, sizeof(first));
    out->nfail = 0;
    out->first_fail = n;
    const int lean = m->opt.outputs == RPS3_OUT_FORCES;
    for (i0 = 0; i0 < n; i0 += RPS3_KBLOCK) {
      int nb = n - i0 < RPS3_KBLOCK ? (int)(n - i0) : RPS3_KBLOCK;
      if (lean)
        lean_block(m, d, in, out, i0, nb, need_rates, &kb, &first);
      else
        kernel_block(m, d, in, out, i0, nb, need_rates, &kb, &first);
    }
    if (out->nfail > 0) d->err = first;
  }
  return RPS3_OK;
}

int rps3_ik_batch(const rps3_model *m, rps3_data *d, const rps3_batch_in *in,
                  rps3_batch_out *out) {
  int status = check_call(m, d, in, out, in ? in->pose : NULL, "pose");
  if (status != RPS3_OK) return status;
  run(m, d, BATCH_IK, in, out);
  return RPS3_OK;
}

int rps3_fk_batch(const rps3_model *m, rps3_data *d, const rps3_batch_in *in,
                  rps3_batch_out *out) {
  rps3_model warm;
  int status = check_call(m, d, in, out, in ? in->l : NULL, "l");
  if (status != RPS3_OK) return status;
  if (in->guess == NULL) {
    run(m, d, BATCH_FK, in, out);
    return RPS3_OK;
  }
  /* a guess is a warm start the caller gives: the solve must take it
     whatever the model says, so run with a copy that warm-starts (a copy
     on the stack: m stays const, nothing is allocated) */
  warm = *m;
  warm.opt.warm_start = 1;
  run(&warm, d, BATCH_FK, in, out);
  return RPS3_OK;
}

/* the regressor's batch (src/ident.c) names its first failing point as
   these do */
void rps3_batch_name_point(rps3_data *d, int status, size_t i) {
  name_point(d, status, i);
}
