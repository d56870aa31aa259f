/*
 * fwddyn_theta.c - the positions of a forward-dynamics state: theta from
 * the link lengths by the theta solve's warm Newton path
 * (rps3_theta_newton, src/fk.c) in the links' planes, in metres, and what
 * a state needs of the root's positions.
 */
#include "fwddyn_plane.h"

void rps3_fd_positions_unset(rps3_data *d) {
  const double nan = (double)NAN;
  int i, q;
  for (i = 0; i < 3; i++) {
    d->c[i] = nan;
    for (q = 0; q < 3; q++)
      d->b[i][q] = d->phi[i][q] = d->dphi[i][q] = d->rot[i][q] = nan;
  }
}

/*
 * Positions from l by the warm Newton path from d->theta: in a simulation
 * the previous evaluation's theta (or the predicted start) is within a
 * step of the answer, and one Newton step converges where GSL's hybridsj
 * costs its set-up on every call.  Its last evaluation, at the root, is
 * the state's: plane_jacobian does not form it again.  A state started
 * near the last root moves that root's cosines and sines (have_trig), and
 * the Newton steps move them by their series, instead of another sincos.
 * Returns 0 when it converged to a root that rps3_theta_solve would accept
 * (0 < theta < pi, not the spun platform), with theta's cosines and sines
 * in p->q; otherwise the caller falls back to rps3_fk, which decides and
 * reports.  The positions (ball joints, link directions, frame) are
 * written unless `positions` is 0, and the pose when `pose`.
 */
int rps3_fd_theta_newton(const rps3_model *m, rps3_data *d, plane *p,
                         int have_trig, int positions, int pose, int unset) {
  rps3_closure *q = &p->q;
  const double *c = q->c, *sn = q->s;
  int i, fold, exact;
  if (!(m->opt.warm_start && d->have_theta && v3_finite(d->theta)) ||
      !v3_finite(d->l) || !(d->l[0] > 0 && d->l[1] > 0 && d->l[2] > 0))
    return -1;
  q->R = m->R;
  q->r3 = 3.0 * m->r * m->r;
  for (i = 0; i < 3; i++) {
    q->l[i] = d->l[i];
    q->th[i] = d->theta[i];
  }
  fold = rps3_theta_newton(m, q, have_trig, d->mode, &d->solve_niter,
                           &d->solve_resid, &exact);
  if (fold < 0) return -1;
  v3_copy(d->theta, q->th);
  if (positions || fold) {
    rps3_links_from_trig(m, d, c, sn);
    rps3_frame_from_balls(m, d);
    if (d->rot[0][0] + d->rot[1][1] < 0.0) return -1; /* spun platform */
  } else if (d->solve_niter == 0 && have_trig) {
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
