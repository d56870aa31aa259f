/*
 * fwddyn_theta.c - the positions of a forward-dynamics state: theta from
 * the link lengths by Newton's method on (8)-(10), with theta's cosines
 * and sines moved by their series along a step instead of recomputed.
 */
#include "fwddyn_plane.h"

/*
 * Positions from l by Newton's method on (8)-(10) from the warm start: in a
 * simulation the previous evaluation's theta is within a step of the
 * answer, and one Newton step converges where GSL's hybridsj costs its
 * set-up on every call.  The same convergence test as rps3_theta_solve
 * (max |f_k| / R^2 <= opt.tol); each iteration evaluates f with its
 * Jacobian (plane_constraints), and the last evaluation, at the root, is
 * the state's: plane_jacobian does not form it again.
 * A step moves theta's cosine and sine by their Taylor series instead of
 * another sincos, and so does the predicted start of an integrator's
 * stage from the last root's (a full evaluation takes sincos of its
 * start, so that the series' rounding never accumulates over more than a
 * control period's stages).  Returns 0 when it converged to a root that
 * rps3_theta_solve would accept (0 < theta < pi, not the spun platform),
 * with theta's cosines and sines in c, sn; otherwise the caller falls back
 * to rps3_fk, which decides and reports.  The positions (ball joints, link
 * directions, frame) are written unless `positions` is 0, and the pose
 * when `pose`.
 */
#define NEWTON_MAX 8
/* largest Newton correction [rad] that moves cos and sin by trig_step's
   series (exact to the rounding up to PREDICT_MAX); a larger one, far
   from any root a warm start gives, takes sincos */
#define TAYLOR_MAX RPS3_FD_PREDICT_MAX


void rps3_fd_positions_unset(rps3_data *d) {
  const double nan = (double)NAN;
  int i, q;
  for (i = 0; i < 3; i++) {
    d->c[i] = nan;
    for (q = 0; q < 3; q++)
      d->b[i][q] = d->phi[i][q] = d->dphi[i][q] = d->rot[i][q] = nan;
  }
}

int rps3_fd_theta_newton(const rps3_model *m, rps3_data *d, plane *p,
                         int have_trig, int positions, int pose,
                         int unset) {
  /* the test of rps3_theta_solve, max |f_k| / R^2 <= tol, in m^2 */
  const double tol = m->opt.tol * m->R * m->R;
  double *c = p->c, *sn = p->s, th[3], f[3], resid;
  int it, i, fold = 0;
  if (!(m->opt.warm_start && d->have_theta && v3_finite(d->theta)) ||
      !v3_finite(d->l) || !(d->l[0] > 0 && d->l[1] > 0 && d->l[2] > 0))
    return -1;
  for (i = 0; i < 3; i++) {
    p->l[i] = d->l[i];
    th[i] = d->theta[i];
  }
  if (!have_trig)
    for (i = 0; i < 3; i++) {
      const double t = th[i]; /* one sincos */
      c[i] = cos(t);
      sn[i] = sin(t);
    }
  for (it = 0;; it++) {
    const double *a = p->at, *b = p->bt;
    double x[3], det, id, big;
    plane_constraints(m, p, f);
    resid = max2(max2(fabs(f[0]), fabs(f[1])), fabs(f[2]));
    if (!(fabs(f[0]) + fabs(f[1]) + fabs(f[2]) < HUGE_VAL)) return -1;
    if (resid <= tol) break;
    if (it == NEWTON_MAX) return -1;
    /* J x = f, J[k][k] = a_k, J[k][k+1] = b_k: the adjugate
       (plane_jacobian) */
    det = a[0] * (a[1] * a[2]) + b[0] * (b[1] * b[2]);
    if (!(fabs(det) > 0.0 && fabs(det) < HUGE_VAL)) return -1;
    id = 1.0 / det;
    x[0] = (a[1] * a[2] * f[0] - b[0] * a[2] * f[1] + b[0] * b[1] * f[2]) * id;
    x[1] = (b[1] * b[2] * f[0] + a[0] * a[2] * f[1] - a[0] * b[1] * f[2]) * id;
    x[2] = (a[0] * a[1] * f[2] - a[1] * b[2] * f[0] + b[0] * b[2] * f[1]) * id;
    big = max2(max2(fabs(x[0]), fabs(x[1])), fabs(x[2]));
    if (!(big < HUGE_VAL)) return -1;
    for (i = 0; i < 3; i++) th[i] -= x[i];
    if (big <= TAYLOR_MAX) {
      fd_trig_step(c, sn, x); /* cos and sin of theta - x */
    } else {
      for (i = 0; i < 3; i++) {
        const double t = th[i];
        c[i] = cos(t);
        sn[i] = sin(t);
      }
    }
  }
  resid /= m->R * m->R;
  d->solve_niter = it;
  d->solve_resid = resid;
  for (i = 0; i < 3; i++) {
    d->theta[i] = th[i];
    if (th[i] > 0.0 && th[i] < RPS3_PI) continue;
    d->theta[i] = remainder(th[i], 2.0 * RPS3_PI);
    fold = 1;
    if (!(d->theta[i] > 0.0 && d->theta[i] < RPS3_PI)) return -1;
    c[i] = cos(d->theta[i]);
    sn[i] = sin(d->theta[i]);
  }
  /* the state's constraint terms at the folded angles' own trig */
  if (fold) plane_constraints(m, p, f);
  if (positions || fold) {
    rps3_links_from_trig(m, d, c, sn);
    rps3_frame_from_balls(m, d);
    if (d->rot[0][0] + d->rot[1][1] < 0.0) return -1; /* spun platform */
  } else if (it == 0 && have_trig) {
    /* the start, a root that passed this test moved by at most
       RPS3_FD_PREDICT_MAX, is the root: n_x + o_y, 1 + cos(beta) >= 0 on
       the platform of (2) and 2 - O(beta^2) wherever a run goes, cannot
       have changed sign */
    if (unset) rps3_fd_positions_unset(d);
  } else {
    /* the spun platform's test alone: rot[0][0] + rot[1][1] is n_x + o_y
       of (18)-(19), from the balls' horizontal positions h_i u_i; times
       sqrt(3) r > 0, its sign is that of sqrt(3) (2 bx_0 - bx_1 - bx_2) /
       3 + by_1 - by_2, and of (2 bx_0 - bx_1 - bx_2) + sqrt(3) (by_1 -
       by_2) */
    double bx[3], by[3];
    for (i = 0; i < 3; i++) {
      const double h = m->R - d->l[i] * c[i];
      bx[i] = h * m->radial[i][0];
      by[i] = h * m->radial[i][1];
    }
    if ((2.0 * bx[0] - bx[1] - bx[2]) + RPS3_SQRT3 * (by[1] - by[2]) < 0.0)
      return -1;
    if (unset) rps3_fd_positions_unset(d);
  }
  if (pose)
    rps3_pose_from_frame(d);
  else if (unset)
    d->pose[0] = d->pose[1] = d->pose[2] = (double)NAN;
  return 0;
}
