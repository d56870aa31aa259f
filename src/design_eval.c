/*
 * design_eval.c - the indices a designer compares designs by, over a set of
 * poses (reachability, force transmission (LTI), homogeneous conditioning,
 * parasitic motion; a task's are design_task.c's), in a workspace
 * allocated once.  The positions are rps3_inverse's (one formula
 * of each quantity in the library); this file adds only what it measures
 * on them.  docs/design.md has the definitions.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "design_int.h"
#include "internal.h"
#include "linalg.h"

/* -------------------------------------------------------------- workspace */

int rps3_design_ws_alloc(rps3_design_ws **out) {
  rps3_design_ws *w;
  int st;
  if (out == NULL) return RPS3_EINVAL;
  *out = NULL;
  w = (rps3_design_ws *)calloc(1, sizeof(*w));
  if (w == NULL) return RPS3_ENOMEM;
  w->scr = (struct rps3_design_scratch *)calloc(1, sizeof(*w->scr));
  if (w->scr == NULL) {
    free(w);
    return RPS3_ENOMEM;
  }
  /* the data serves every model with the default solver: every design's */
  rps3_model_default(&w->model);
  if (rps3_model_init(&w->model, NULL) != RPS3_OK) {
    free(w->scr);
    free(w);
    return RPS3_EINVAL;
  }
  st = rps3_data_alloc(&w->model, &w->d);
  if (st != RPS3_OK) {
    free(w->scr);
    free(w);
    return st;
  }
  w->model.valid = 0; /* no design evaluated yet */
  *out = w;
  return RPS3_OK;
}

void rps3_design_ws_free(rps3_design_ws *w) {
  if (w == NULL) return;
  rps3_data_free(w->d);
  free(w->scr);
  free(w);
}

int rps3_design_ws_set(rps3_design_ws *w, const rps3_design *ds,
                       const rps3_design_opts *o) {
  rps3_check chk;
  rps3_model *s = &w->scr->stat;
  if (rps3_design_model(ds, &w->model, &chk) != RPS3_OK) {
    w->model.valid = 0;
    RPS3_ERROR(w, RPS3_EINVAL, "%.250s", chk.msg);
  }
  if (o != NULL &&
      !(o->lti_good >= 0.0 && o->lti_good <= 1.0 && o->length >= 0.0 &&
        isfinite(o->length) && o->cond_sing >= 1.0 && isfinite(o->cond_sing)))
    RPS3_ERROR(w, RPS3_EINVAL,
               "design options (lti_good = %g, length = %g, cond_sing = %g): "
               "lti_good must be in [0, 1], length finite and >= 0, "
               "cond_sing finite and >= 1",
               o->lti_good, o->length, o->cond_sing);
  /* the indices' model: positions and the force transmission only */
  *s = w->model;
  s->opt.effects = RPS3_EFF_PLATFORM_GRAVITY;
  s->opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
  s->opt.cond_max = 1e300;
  s->opt.trans_max = 1e300;
  s->opt.trans_warn = 1e300;
  s->opt.cond_warn = 1e300;
  if (rps3_model_init(s, NULL) != RPS3_OK)
    RPS3_ERROR(w, RPS3_EINVAL, "design model: internal options refused");
  return RPS3_OK;
}

/* --------------------------------------------------------------- geometry */

/*
 * Least distance between the segments p0 + s u and q0 + t v, s, t in
 * [0, 1], |u|, |v| > 0: the unconstrained closest pair, clamped to the
 * first segment, then the second's parameter for it, clamped, and the
 * first's again for that (Ericson, Real-Time Collision Detection, 5.1.9).
 */
static double seg_dist(const double p0[3], const double u[3],
                       const double q0[3], const double v[3]) {
  double r[3], a = v3_dot(u, u), e = v3_dot(v, v), f, c, b, den, s, t;
  double x[3];
  v3_sub(r, p0, q0);
  f = v3_dot(v, r);
  c = v3_dot(u, r);
  b = v3_dot(u, v);
  den = a * e - b * b;
  s = den > 0.0 ? (b * f - c * e) / den : 0.0;
  s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
  t = (b * s + f) / e;
  /* t outside [0, 1]: clamp it, and s to the point nearest that end */
  if (t < 0.0 || t > 1.0) {
    t = t < 0.0 ? 0.0 : 1.0;
    s = (b * t - c) / a;
    s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
  }
  v3_axpy(x, r, s, u);
  v3_axpy(x, x, -t, v);
  return v3_norm(x);
}

/*
 * The transmission indices and the homogeneous condition number of the
 * positions in d (rps3.h, rps3_design_out): the overall Jacobian G with
 * rows (f, (b_i - c) x f / L), f = phi_i (actuation) and the pin axis
 * (constraint); the output twist of row k is column k of G^-1, twist
 * (v, L omega); b_k's velocity v + omega x (b_k - c), in units where L
 * is 1: v + (L omega) x (b_k - c) / L.
 */
static void transmission_indices(const rps3_model *m, const rps3_data *d,
                                 double L, pose_res *r) {
  double G[36], LU[36], X[36], p[3][3], fro_g = 0.0, fro_x = 0.0;
  int perm[6], i, k;
  for (i = 0; i < 3; i++) {
    v3_sub(p[i], d->b[i], d->c);
    v3_scale(p[i], 1.0 / L, p[i]);
  }
  for (k = 0; k < 6; k++) {
    const double *f = k < 3 ? d->phi[k] : m->axis[k - 3];
    double mo[3];
    v3_cross(mo, p[k % 3], f);
    for (i = 0; i < 3; i++) {
      G[6 * k + i] = f[i];
      G[6 * k + 3 + i] = mo[i];
    }
  }
  memcpy(LU, G, sizeof(G));
  r->oti = r->cti = 1.0;
  if (rps3_lu_factor(6, LU, perm) != 0) {
    /* exactly singular: no output twist transmits anything */
    r->oti = r->cti = r->lti = 0.0;
    r->cond_h = HUGE_VAL;
    return;
  }
  rps3_lu6_inverse(LU, perm, X);
  for (k = 0; k < 6; k++) {
    const double *f = k < 3 ? d->phi[k] : m->axis[k - 3];
    double v[3], w[3], vb[3], eta, nv;
    /* column k of G^-1: the output twist (v, L omega) of row k */
    for (i = 0; i < 3; i++) {
      v[i] = X[6 * i + k];
      w[i] = X[6 * (i + 3) + k];
    }
    /* velocity of ball k % 3 under it */
    v3_cross(vb, w, p[k % 3]);
    v3_axpy(vb, vb, 1.0, v);
    nv = v3_norm(vb);
    eta = nv > 0.0 ? fabs(v3_dot(f, vb)) / (v3_norm(f) * nv) : 0.0;
    if (!(eta <= 1.0)) eta = isfinite(nv) ? 1.0 : 0.0; /* rounding */
    if (k < 3) {
      if (eta < r->oti) r->oti = eta;
    } else if (eta < r->cti) {
      r->cti = eta;
    }
  }
  for (i = 0; i < 36; i++) {
    fro_g += G[i] * G[i];
    fro_x += X[i] * X[i];
  }
  r->lti = r->oti < r->cti ? r->oti : r->cti;
  /* Frobenius condition number, normalised to 1 for an isotropic G */
  r->cond_h = sqrt(fro_g * fro_x) / 6.0;
  if (!isfinite(r->cond_h)) {
    r->cond_h = HUGE_VAL;
    r->oti = r->cti = r->lti = 0.0;
  }
}

void rps3_design_eval_pose(rps3_design_ws *w, const rps3_design *ds, double L,
                           double cond_sing, const double pose[3],
                           pose_res *r) {
  const rps3_model *m = &w->scr->stat;
  rps3_data *d = w->d;
  double a[3], u[3][3];
  int i, j, st;
  memset(r, 0, sizeof(*r));
  for (i = 0; i < 3; i++) {
    d->pose[i] = pose[i];
    d->dpose[i] = d->ddpose[i] = 0.0;
  }
  /* positions (2)-(7), (39) and the force transmission: rps3_inverse */
  st = rps3_inverse(m, d);
  r->status = st;
  if (st != RPS3_OK && !(st == RPS3_ESING && (d->stage & RPS3_STAGE_POS))) {
    double nan = (double)NAN;
    r->flags = RPS3_DESIGN_ASSEMBLY;
    for (i = 0; i < 3; i++) r->l[i] = r->theta[i] = r->ball[i] = r->c[i] = nan;
    r->clearance = r->lti = r->oti = r->cti = r->cond_h = r->trans = r->spin =
        nan;
    return;
  }
  if (st == RPS3_ESING) r->flags |= RPS3_DESIGN_SINGULAR;
  r->trans = st == RPS3_OK ? d->transmission : HUGE_VAL;
  for (i = 0; i < 3; i++) {
    r->l[i] = d->l[i];
    r->theta[i] = d->theta[i];
    r->c[i] = d->c[i];
    a[i] = d->rot[i][2];
  }
  /* joint limits: stroke, pin range, ball joint cone */
  for (i = 0; i < 3; i++) {
    double x[3];
    v3_cross(x, d->phi[i], a);
    r->ball[i] = atan2(v3_norm(x), v3_dot(d->phi[i], a));
    if (!(r->l[i] >= ds->l_min && r->l[i] <= ds->l_max))
      r->flags |= RPS3_DESIGN_STROKE;
    if (!(r->theta[i] >= ds->theta_min && r->theta[i] <= ds->theta_max))
      r->flags |= RPS3_DESIGN_PIN;
    if (!(r->ball[i] <= ds->ball_max)) r->flags |= RPS3_DESIGN_BALL;
    v3_sub(u[i], d->b[i], m->pin[i]);
  }
  /* interference: the links' axes as segments pin - ball */
  r->clearance = HUGE_VAL;
  for (i = 0; i < 3; i++)
    for (j = i + 1; j < 3; j++) {
      double s = seg_dist(m->pin[i], u[i], m->pin[j], u[j]);
      if (s < r->clearance) r->clearance = s;
    }
  r->clearance -= 2.0 * ds->link_radius;
  if (ds->link_radius > 0.0 && r->clearance < 0.0)
    r->flags |= RPS3_DESIGN_INTERFERE;
  /* force transmission and conditioning */
  transmission_indices(m, d, L, r);
  if (!(r->cond_h <= cond_sing)) r->flags |= RPS3_DESIGN_SINGULAR;
  /* parasitic spin: yaw of the Z-Y-X decomposition of rot */
  r->spin = atan2(d->rot[1][0], d->rot[0][0]);
}

/* write r into the outputs of pose i of n */
static void put_pose(rps3_design_out *out, size_t n, size_t i,
                     const pose_res *r) {
  int j;
  if (out == NULL) return;
  out->flags[i] = r->flags;
  for (j = 0; j < 3; j++) {
    if (out->l) out->l[j * n + i] = r->l[j];
    if (out->theta) out->theta[j * n + i] = r->theta[j];
    if (out->ball) out->ball[j * n + i] = r->ball[j];
    if (out->c) out->c[j * n + i] = r->c[j];
  }
  if (out->clearance) out->clearance[i] = r->clearance;
  if (out->lti) out->lti[i] = r->lti;
  if (out->oti) out->oti[i] = r->oti;
  if (out->cti) out->cti[i] = r->cti;
  if (out->cond_h) out->cond_h[i] = r->cond_h;
  if (out->transmission) out->transmission[i] = r->trans;
  if (out->spin) out->spin[i] = r->spin;
}

static void sum_start(rps3_design_summary *s) {
  memset(s, 0, sizeof(*s));
  s->l_lo = HUGE_VAL;
  s->l_hi = 0.0;
  s->lti_min = HUGE_VAL;
}

static void sum_add(rps3_design_summary *s, const pose_res *r,
                    double lti_good) {
  int k;
  s->n++;
  s->flags_any |= r->flags;
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
    if (r->flags & (1 << k)) s->nflag[k]++;
  if (r->flags) return;
  s->nreach++;
  s->gti += r->lti; /* a sum until sum_end */
  if (r->lti >= lti_good) s->good_fraction += 1.0;
  s->lti_min = fmin_(s->lti_min, r->lti);
  s->cond_h_max = fmax_(s->cond_h_max, r->cond_h);
  s->trans_max = fmax_(s->trans_max, r->trans);
  s->xc_max = fmax_(s->xc_max, fabs(r->c[0]));
  s->yc_max = fmax_(s->yc_max, fabs(r->c[1]));
  s->spin_max = fmax_(s->spin_max, fabs(r->spin));
  for (k = 0; k < 3; k++) {
    s->l_lo = fmin_(s->l_lo, r->l[k]);
    s->l_hi = fmax_(s->l_hi, r->l[k]);
  }
}

static int sum_end(rps3_design_ws *w, rps3_design_summary *s,
                   double cell_volume) {
  if (s->nreach == 0) {
    size_t n = s->n;
    int any = s->flags_any;
    size_t nf[RPS3_DESIGN_NFLAG];
    memcpy(nf, s->nflag, sizeof(nf));
    memset(s, 0, sizeof(*s));
    s->n = n;
    s->flags_any = any;
    memcpy(s->nflag, nf, sizeof(nf));
    {
      char why[160] = "";
      int k;
      size_t len = 0;
      for (k = 0; k < RPS3_DESIGN_NFLAG && len + 32 < sizeof why; k++)
        if (nf[k] > 0)
          len += (size_t)snprintf(why + len, sizeof why - len, "%s%s %zu",
                                  len ? ", " : "", rps3_design_flag_name(k),
                                  nf[k]);
      RPS3_ERROR(w, RPS3_EEMPTY,
                 "empty workspace: none of the %zu poses is reachable "
                 "(poses failing each check: %s)",
                 n, why);
    }
  }
  s->reach_fraction = (double)s->nreach / (double)s->n;
  s->volume = (double)s->nreach * cell_volume;
  if (!isfinite(s->volume))
    RPS3_ERROR(w, RPS3_ERANGE,
               "volume = %zu poses x cell_volume %g is not finite: the cell "
               "volume is too large",
               s->nreach, cell_volume);
  s->gti /= (double)s->nreach;
  s->good_fraction /= (double)s->nreach;
  return RPS3_OK;
}

/* the common part of the two evaluations: pose i from the list or the
   grid */
static int eval_set(rps3_design_ws *w, const rps3_design *ds,
                    const rps3_design_opts *o, size_t n, const double *pose,
                    const rps3_design_grid *gr, double cell_volume,
                    rps3_design_out *out, rps3_design_summary *sum) {
  rps3_design_opts def;
  rps3_design_summary own;
  double L;
  size_t i;
  int st;
  if (w == NULL) return RPS3_EINVAL;
  if (o == NULL) {
    rps3_design_opts_default(&def);
    o = &def;
  }
  st = rps3_design_ws_set(w, ds, o);
  if (st != RPS3_OK) return st;
  if (n == 0) RPS3_ERROR(w, RPS3_EINVAL, "no poses to evaluate (n = 0)");
  if (out != NULL && out->flags == NULL)
    RPS3_ERROR(w, RPS3_EINVAL, "design out.flags is NULL");
  if (!(cell_volume >= 0.0 && isfinite(cell_volume)))
    RPS3_ERROR(w, RPS3_EINVAL,
               "cell_volume = %g: must be finite and >= 0 [m rad^2]",
               cell_volume);
  if (gr == NULL) {
    if (pose == NULL) RPS3_ERROR(w, RPS3_EINVAL, "pose is NULL");
    for (i = 0; i < 3 * n; i++)
      if (!isfinite(pose[i]))
        RPS3_ERROR(w, RPS3_EINVAL,
                   "pose[%zu] (%s of pose %zu) = %g is not "
                   "finite",
                   i,
                   i / n == 0   ? "alpha"
                   : i / n == 1 ? "beta"
                                : "z_c",
                   i % n, pose[i]);
  }
  L = o->length > 0.0 ? o->length : w->scr->stat.r;
  if (sum == NULL) sum = &own;
  sum_start(sum);
  for (i = 0; i < n; i++) {
    double q[3];
    pose_res r;
    if (gr != NULL)
      rps3_design_grid_pose(gr, i, q);
    else {
      q[0] = pose[i];
      q[1] = pose[n + i];
      q[2] = pose[2 * n + i];
    }
    rps3_design_eval_pose(w, ds, L, o->cond_sing, q, &r);
    put_pose(out, n, i, &r);
    sum_add(sum, &r, o->lti_good);
  }
  return sum_end(w, sum, cell_volume);
}

int rps3_design_eval(rps3_design_ws *w, const rps3_design *ds,
                     const rps3_design_opts *o, size_t n, const double *pose,
                     double cell_volume, rps3_design_out *out,
                     rps3_design_summary *sum) {
  return eval_set(w, ds, o, n, pose, NULL, cell_volume, out, sum);
}

int rps3_design_eval_grid(rps3_design_ws *w, const rps3_design *ds,
                          const rps3_design_opts *o, const rps3_design_grid *gr,
                          rps3_design_out *out, rps3_design_summary *sum) {
  double cv;
  size_t n;
  if (w == NULL) return RPS3_EINVAL;
  if (rps3_design_grid_cell(gr, &cv) != RPS3_OK)
    RPS3_ERROR(w, RPS3_EINVAL,
               "design grid: NULL, a bound not finite, hi < lo or n = 0");
  n = rps3_design_grid_size(gr);
  if (n == 0)
    RPS3_ERROR(w, RPS3_EINVAL, "design grid: the number of poses overflows");
  return eval_set(w, ds, o, n, NULL, gr, cv, out, sum);
}

/* ------------------------------------------------------------------- task */
