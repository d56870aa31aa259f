/*
 * fk.c - the theta solve of (8)-(10), and forward kinematics l -> theta ->
 * pose, (11)-(20).  One solve for every caller: from a warm start the
 * Newton path in the links' planes (rps3_theta_newton, which the forward
 * dynamics calls too), else, and wherever it gives up, GSL's multiroot,
 * which decides and reports; the multiroot route's start from the root
 * predictor of src/theta.h (rps3_root_keep, rps3_root_predict).  The
 * multiroot route itself is theta_gsl.c.
 */
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "linalg.h"
#include "theta.h"
#include "theta_solver.h"

int rps3_theta_guess(const rps3_model *m, rps3_data *d) {
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  for (i = 0; i < 3; i++) {
    double cth;
    if (!isfinite(d->l[i]) || !(d->l[i] > 0.0))
      RPS3_ERROR(d, RPS3_EINVAL, "link %d length %g m: needs finite and > 0",
                 i + 1, d->l[i]);
    /* level platform: the ball joint sits R - r inwards of the pin */
    cth = (m->R - m->r) / d->l[i];
    if (cth > 0.999) cth = 0.999;
    if (cth < -0.999) cth = -0.999;
    d->theta[i] = acos(cth);
  }
  return RPS3_OK;
}

/* the Newton path's most steps: from a warm start one or two converge;
   more go to the multiroot route, whose trust region copes with a start
   far from the root */
#define NEWTON_MAX 8

/* max |v_k| (fmax is a call at -O2); a NaN is dropped, and each use below
   is preceded or followed by a test that a NaN fails */
static inline double max3abs(const double v[3]) {
  const double a = fabs(v[0]), b = fabs(v[1]), c = fabs(v[2]);
  const double ab = a > b ? a : b;
  return ab > c ? ab : c;
}

int rps3_theta_newton(const rps3_model *m, rps3_closure *q, int have_trig,
                      int mode, int *niter, double *resid, int *exact) {
  /* the test of rps3_theta_solve, max |f_k| / R^2 <= tol, in q's unit */
  const double tol = m->opt.tol * q->R * q->R;
  const int max_it =
      m->opt.max_iter < NEWTON_MAX ? m->opt.max_iter : NEWTON_MAX;
  double *th = q->th, *c = q->c, *sn = q->s, f[3], res;
  int it, i, fold = 0, ex = !have_trig;
  if (!have_trig) trig3(th, c, sn);
  for (it = 0;; it++) {
    const double *a = q->at, *b = q->bt;
    double x[3], det, id, big;
    rps3_closure_eval(q, f);
    res = max3abs(f);
    if (!(fabs(f[0]) + fabs(f[1]) + fabs(f[2]) < HUGE_VAL)) return -1;
    if (res <= tol) break;
    if (it >= max_it) return -1;
    /* J x = f for the cyclic bidiagonal J = df/dtheta (J[k][k] = a_k,
       J[k][k+1] = b_k) by its adjugate: det = a0 a1 a2 + b0 b1 b2 */
    det = a[0] * (a[1] * a[2]) + b[0] * (b[1] * b[2]);
    if (!(fabs(det) > 0.0 && fabs(det) < HUGE_VAL)) return -1;
    id = 1.0 / det;
    x[0] = (a[1] * a[2] * f[0] - b[0] * a[2] * f[1] + b[0] * b[1] * f[2]) * id;
    x[1] = (b[1] * b[2] * f[0] + a[0] * a[2] * f[1] - a[0] * b[1] * f[2]) * id;
    x[2] = (a[0] * a[1] * f[2] - a[1] * b[2] * f[0] + b[0] * b[2] * f[1]) * id;
    /* a correction beyond RPS3_THETA_WARM_MAX: not a warm start (the
       multiroot route's trust region copes with it, where Newton's full
       step may jump to another root) */
    big = max3abs(x);
    if (!(big <= RPS3_THETA_WARM_MAX)) return -1;
    for (i = 0; i < 3; i++) th[i] -= x[i];
    if (big <= RPS3_THETA_PREDICT_MAX) {
      rps3_trig_step(c, sn, x); /* cos and sin of theta - x */
      ex = 0;
    } else {
      trig3(th, c, sn);
      ex = 1;
    }
  }
  /* the root's assembly mode, the sign of det(df/dtheta), must be the
     warm start's: near the singular surface the other mode's root lies
     within a step, and a step across the fold finds it, which no motion
     from the start reaches without passing the singularity */
  if (mode != RPS3_MODE_ANY) {
    const double *a = q->at, *b = q->bt;
    const double det = a[0] * (a[1] * a[2]) + b[0] * (b[1] * b[2]);
    if (!(mode > 0 ? det > 0.0 : det < 0.0)) return -1;
  }
  *niter = it;
  *resid = res / (q->R * q->R);
  /* the branch 0 < theta < pi, after folding whole turns */
  for (i = 0; i < 3; i++) {
    if (th[i] > 0.0 && th[i] < RPS3_PI) continue;
    th[i] = remainder(th[i], 2.0 * RPS3_PI);
    fold = 1;
    if (!(th[i] > 0.0 && th[i] < RPS3_PI)) return -1;
    c[i] = cos(th[i]);
    sn[i] = sin(th[i]);
  }
  /* the pair terms at the folded angles' own trig */
  if (fold) rps3_closure_eval(q, f);
  *exact = ex;
  return fold;
}

void rps3_root_keep(const rps3_model *m, rps3_data *d, const rps3_cjac *J) {
  struct rps3_solver_state *s = d->solver;
  rps3_closure *q = &s->root;
  double f[3];
  int i, k;
  s->root_ok = J->factored && !J->sing;
  if (!s->root_ok) return;
  /* the root in the links' planes, in metres: cos and sin theta are the
     link directions' vertical components (29) */
  q->R = m->R;
  q->r3 = 3.0 * m->r * m->r;
  for (i = 0; i < 3; i++) {
    q->l[i] = d->l[i];
    q->th[i] = d->theta[i];
    q->c[i] = d->dphi[i][2];
    q->s[i] = d->phi[i][2];
  }
  rps3_closure_eval(q, f);
  /* (df/dtheta)^-1 = (A^-1)^T for the lambda system A = (df/dtheta)^T,
     and G = -(df/dtheta)^-1 (df/dl) */
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++) s->root_X[i][k] = J->Ainv[3 * k + i];
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++)
      s->root_G[i][k] =
          -(s->root_X[i][0] * J->Jl[0][k] + s->root_X[i][1] * J->Jl[1][k] +
            s->root_X[i][2] * J->Jl[2][k]);
}

int rps3_root_predict(rps3_data *d, double max_step) {
  struct rps3_solver_state *s = d->solver;
  const rps3_closure *q = &s->root;
  double dl[3], u[3], x[3], hd[3], Zd[3], hdd[3], Zdd[3], Hv[3];
  int ok = s->root_ok && d->have_theta &&
           memcmp(d->theta, q->th, sizeof(q->th)) == 0;
  s->root_ok = 0; /* one use */
  if (!ok) return 0;
  /* the second order along the chord itself (tau = 1): theta'' for l' =
     dl, (df/dtheta) theta'' = x, the velocity products of (8)-(10) */
  v3_sub(dl, d->l, q->l);
  m3_mulv(u, M3C(s->root_G), dl);
  rps3_closure_bias(q, dl, u, x, hd, Zd, hdd, Zdd);
  m3_mulv(Hv, M3C(s->root_X), x);
  rps3_theta_predict(d->theta, d->l, q->l, q->th, M3C(s->root_G), Hv, 1.0,
                     max_step);
  return 1;
}

int rps3_theta_solve(const rps3_model *m, rps3_data *d) {
  return rps3_theta_solve_with(m, d, NULL);
}

/* the root th of the solve: its branch, its positions, the platform's
   frame, and its assembly mode (the Jacobian for the later stages into
   J, or a local one) */
static int accept_root(const rps3_model *m, rps3_data *d, const double th[3],
                       rps3_cjac *J, int prev_mode) {
  const struct rps3_solver_state *s = d->solver;
  rps3_cjac own;
  int i, same;
  /* the branch 0 < theta < pi, after folding whole turns */
  same = 1;
  for (i = 0; i < 3; i++) {
    double t = th[i];
    if (!(t > 0.0 && t < RPS3_PI)) t = remainder(th[i], 2.0 * RPS3_PI);
    if (!(t > 0.0 && t < RPS3_PI))
      RPS3_ERROR(d, RPS3_EBRANCH,
                 "link %d: theta = %.6g rad is outside (0, pi)", i + 1, t);
    d->theta[i] = t;
    same = same && t == s->p.q.th[i];
  }
  /* (12)-(14) with the trig of the last evaluation when it was at this
     theta (bitwise: the same cos and sin) */
  if (same)
    rps3_links_from_trig(m, d, s->p.q.c, s->p.q.s);
  else
    rps3_links_from_joints(m, d);
  rps3_frame_from_balls(m, d);
  RPS3_CHECK_FINITE(d, d->b, 9, "b");
  RPS3_CHECK_FINITE(d, d->c, 3, "c");
  RPS3_CHECK_FINITE(d, d->rot, 9, "rot");
  /* a pose (alpha, beta, z_c) has rot = Rz(alpha) Ry(beta) Rz(-alpha) (2),
     whose upper-left block has trace 2 - (1 - cos beta) >= 0.  (8)-(10)
     have a second family of roots with 0 < theta < pi: the ball joints
     reflected through the Z axis, (x, y) -> (-x, -y), each still in its
     pin plane -- the platform spun by pi about its normal, trace
     -(1 + cos beta) <= 0.  No pose describes it, so it is not a solution */
  if (d->rot[0][0] + d->rot[1][1] < 0.0) {
    d->have_theta = 0;
    RPS3_ERROR(d, RPS3_EBRANCH,
               "root theta = (%.6g, %.6g, %.6g) is the platform spun by pi "
               "about its normal (ball joints reflected through the Z axis), "
               "which no pose (alpha, beta, z_c) describes",
               d->theta[0], d->theta[1], d->theta[2]);
  }
  /* the assembly mode: flag a warm-started sequence that changed it, and
     refuse one the caller excluded.  The positions are final: the
     Jacobian for the later stages */
  if (J == NULL) J = &own;
  rps3_cjac_eval(d, J);
  d->mode = rps3_mode_of_jac(M3C(J->Jt));
  if (prev_mode != RPS3_MODE_ANY && d->mode != prev_mode)
    d->warn |= RPS3_WARN_MODE;
  if (m->opt.mode != RPS3_MODE_ANY && d->mode != m->opt.mode) {
    d->have_theta = 0;
    RPS3_ERROR(d, RPS3_EMODE,
               "root theta = (%.6g, %.6g, %.6g) is in assembly mode %d "
               "(sign of det df/dtheta; +1 the level platform's), opt.mode "
               "asks for %d",
               d->theta[0], d->theta[1], d->theta[2], d->mode, m->opt.mode);
  }
  d->have_theta = 1;
  d->stage = RPS3_STAGE_POS;
  return RPS3_OK;
}

int rps3_theta_solve_with(const rps3_model *m, rps3_data *d, rps3_cjac *J) {
  struct rps3_solver_state *s;
  double th[3];
  int i, status, prev_mode, warm;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  s = d->solver;
  if (s->kind != m->opt.solver)
    RPS3_ERROR(d, RPS3_EINVAL,
               "workspace was allocated for solver %s, the model asks for %s",
               rps3_solver_name(s->kind), rps3_solver_name(m->opt.solver));
  d->stage = 0;
  d->warn = 0;
  d->solve_niter = 0;
  d->solve_resid = 0.0;
  for (i = 0; i < 3; i++)
    if (!isfinite(d->l[i]) || !(d->l[i] > 0.0))
      RPS3_ERROR(d, RPS3_EINVAL, "link %d length %g m: needs finite and > 0",
                 i + 1, d->l[i]);
  /* starting point: explicit warm start, else the level-platform guess;
     a warm start remembers the mode it starts from */
  prev_mode = RPS3_MODE_ANY;
  warm = m->opt.warm_start && d->have_theta && v3_finite(d->theta);
  if (warm) {
    prev_mode = d->mode;
  } else {
    status = rps3_theta_guess(m, d);
    if (status != RPS3_OK) return status;
  }
  d->mode = RPS3_MODE_ANY;
  s->p.primed = 0;
  s->p.q.R = 1.0;
  s->p.q.r3 = 3.0 * m->rho * m->rho;
  for (i = 0; i < 3; i++) {
    s->p.q.l[i] = d->l[i] / m->R;
    GV(s->x, i) = d->theta[i];
  }

  /* a warm start: the Newton path in the links' planes, in units of R as
     GSL's evaluations; where it does not converge (to a root in (0, pi)),
     the multiroot route from the same start decides and reports */
  if (warm) {
    rps3_closure q = s->p.q;
    int exact;
    v3_copy(q.th, d->theta);
    if (rps3_theta_newton(m, &q, 0, prev_mode, &d->solve_niter, &d->solve_resid,
                          &exact) >= 0) {
      v3_copy(th, q.th);
      /* the root's libm trig, for the positions and the next evaluation
         there (a series-stepped one gives way to libm's below) */
      if (exact) s->p.q = q;
      return accept_root(m, d, th, J, prev_mode);
    }
    d->solve_niter = 0;
    d->solve_resid = 0.0;
  }

  status = rps3_theta_multiroot(m, d, th);
  if (status != RPS3_OK) return status;
  return accept_root(m, d, th, J, prev_mode);
}

int rps3_fk(const rps3_model *m, rps3_data *d) {
  int status = rps3_theta_solve(m, d);
  if (status != RPS3_OK) return status;
  rps3_pose_from_frame(d);
  RPS3_CHECK_FINITE(d, d->pose, 3, "pose");
  return RPS3_OK;
}

void rps3_pose_from_frame(rps3_data *d) {
  double a1, a2, a3, sb;
  /* a = rot e_z = (sin b cos a, sin b sin a, cos b) for Rz(a) Ry(b) Rz(-a) */
  a1 = d->rot[0][2];
  a2 = d->rot[1][2];
  a3 = d->rot[2][2];
  sb = hypot(a1, a2);
  d->pose[1] = atan2(sb, a3);
  if (d->pose[1] < 1e-9) {
    /* alpha is a free gauge at beta = 0: report 0 and say so */
    d->pose[0] = 0.0;
    d->warn |= RPS3_WARN_ALPHA;
  } else {
    d->pose[0] = atan2(a2, a1);
  }
  d->pose[2] = d->c[2];
}
