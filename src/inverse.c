/*
 * inverse.c - the whole per-point pipeline: pose -> positions -> rates ->
 * forces, computing only what the selected effects need.
 */
#include "batch_kernel.h"
#include "internal.h"
#include "linalg.h"

/*
 * The multiroot route solves (8)-(10) from the lengths of the pose, and the
 * root it reaches depends on its start: it may be another assembly mode,
 * with the same lengths and other forces.  The pose fixes its own theta,
 * (39): th39, given here by its cosine and sine (c39, s39: the pose's link
 * direction, as rps3_ik has it).  Accept the solved theta when it differs
 * from th39 by no more than the solve's own accuracy: a root with
 * max |f_k| <= tol (f in units of R^2) is within |df/dtheta^-1|_inf tol
 * R^2 of the exact one in max |theta_i| (first order), times 10 for the
 * linearization and 3 to spare, with a rounding floor (f is evaluated to
 * ~1e-15 R^2, the closed form to ~1e-15 rad).  |df/dtheta^-1|_inf is the
 * 1-norm of the inverse of the lambda system (df/dtheta)^T, cond / |A|_1 of
 * its factorization, which the inverse dynamics then reuse.  Both angles
 * lie in (0, pi), so |theta - th39| is the angle between the two
 * directions, d: with x = |sin d| and cos d > 0, d = asin x <= x (1 + x)
 * for x <= 1/2, a bound within x^2 of d that needs no atan2; else d itself
 * by atan2.
 */
static int check_own_root(const rps3_model *m, rps3_data *d, rps3_cjac *J,
                          const double c39[3], const double s39[3]) {
  double anorm = 0.0, err = 0.0, bound;
  int i, k;
  for (i = 0; i < 3; i++) {
    /* cos and sin of the solved theta_i: its link direction (29) */
    double ct = d->dphi[i][2], st = d->phi[i][2];
    double sd = fabs(s39[i] * ct - c39[i] * st), cd = c39[i] * ct + s39[i] * st;
    double e = (cd > 0.0 && sd <= 0.5) ? sd * (1.0 + sd) : atan2(sd, cd);
    if (e > err || e != e) err = e; /* a NaN stays, and is refused */
  }
  rps3_cjac_factor(J);
  for (k = 0; k < 3; k++) {
    double col = fabs(J->A[k]) + fabs(J->A[3 + k]) + fabs(J->A[6 + k]);
    if (col > anorm) anorm = col;
  }
  /* a singular root: invdyn reports it (RPS3_ESING); compare plainly */
  if (J->sing || !(anorm > 0.0))
    bound = 1e-9;
  else
    bound = 30.0 * J->cond / anorm * (m->opt.tol > 1e-15 ? m->opt.tol : 1e-15) *
                m->R * m->R +
            1e-12;
  if (!(err <= bound)) {
    d->have_theta = 0;
    RPS3_ERROR(d, RPS3_EMODE,
               "multiroot theta (%.6g, %.6g, %.6g) is not the pose's own "
               "root (%.6g, %.6g, %.6g) of (39) (assembly mode %d): start "
               "near the pose's mode or use the closed form",
               d->theta[0], d->theta[1], d->theta[2], atan2(s39[0], c39[0]),
               atan2(s39[1], c39[1]), atan2(s39[2], c39[2]), d->mode);
  }
  return RPS3_OK;
}

/*
 * The multiroot route's start, predicted from the last root along the
 * lengths.  With l(s) = l_last + s dl from the last point's lengths (s = 0)
 * to this point's (s = 1), (8)-(10) hold along theta(s):
 *   theta' = G dl,  G = -(df/dtheta)^-1 (df/dl),
 *   (df/dtheta) theta'' = x,  x_k = -2 (|D_k'|^2 + D_k . K_k),
 * the second derivative of |D_k|^2 = 3 r^2 for D_k = b_i - b_j at l'' = 0
 * (the joint acceleration's, K_k = b_i'' - b_j'' without theta''), and the
 * start theta + theta' + theta''/2 is off by O(|dl|^3): ~1e-14 rad on the
 * paper's helix at 1 kHz.  Only the lengths and the last root enter; the
 * start knows nothing of the pose's own theta (39), which the route checks
 * its root against (the predictor is src/theta.h's, rps3_theta_predict,
 * along the chord).  rps3_theta_solve takes a start within the tolerance
 * as the root, its warm Newton path otherwise, and GSL's solver where that
 * gives up.  What the prediction needs is kept
 * with the root in d's solver state (rps3_root_keep, after the own-root
 * check), private, so that a caller's writes to d's positions cannot
 * mislead it; it serves the next call only, and only while d->theta is
 * that root bit for bit (a theta the caller wrote is the start as
 * written, as in a fresh workspace).  Not taken for a step above
 * PREDICT_MAX either (a jump, where the last root is as good a start).
 */
#define PREDICT_MAX 1e-2 /* rad, as rps3_fwddyn's and the controller's */

int rps3_inverse(const rps3_model *m, rps3_data *d) {
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  /* F alone (rps3.h, enum rps3_output): the leanest pass, or the stages
     for a point it does not keep */
  if (m->opt.outputs == RPS3_OUT_FORCES && rps3_kernel_covers(m))
    return rps3_inverse_lean_point(m, d) ? RPS3_OK : rps3_inverse_stages(m, d);
  /* on the kernel's configurations (closed form, Lagrange, the paper's
     effects) the point in the kernel's one straight-line pass, which
     shares every sine and the constraint Jacobian between the stages; a
     point it does not certify goes through the stages */
  if (rps3_kernel_covers(m) && rps3_inverse_kernel_point(m, d)) return RPS3_OK;
  return rps3_inverse_stages(m, d);
}

int rps3_inverse_stages(const rps3_model *m, rps3_data *d) {
  rps3_cjac J; /* the constraint Jacobian at this point's positions */
  int status;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  /* rates only when an effect (or the certificate) needs them */
  status = rps3_inverse_motion(m, d, &J, rps3_need_rates(m));
  if (status != RPS3_OK) return status;
  return rps3_invdyn_with(m, d, &J);
}

int rps3_inverse_motion(const rps3_model *m, rps3_data *d, rps3_cjac *J,
                        int need_rates) {
  rps3_pose_trig trig;   /* sines and cosines of the pose, for every stage */
  double c39[3], s39[3]; /* cos, sin of the pose's own theta (39) */
  int status, multiroot, i;

  /* positions: the closed form (39), or the multiroot solve of (8)-(10)
     from the link lengths, warm-started from this data's previous point */
  multiroot = (m->opt.theta == RPS3_THETA_MULTIROOT);
  status = rps3_ik_with(m, d, &trig,
                        multiroot                           ? RPS3_IK_NO_THETA
                        : (m->opt.outputs & RPS3_OUT_THETA) ? RPS3_IK_THETA
                                                            : RPS3_IK_DIRS,
                        J);
  if (status != RPS3_OK) return status;
  if (multiroot) {
    double th0[3];
    int mode0 = d->mode, predicted = 0;
    /* ik left theta alone (no closed form leaks into the starting point):
       the solve starts from this data's previous solution.  Keep (39) of
       the pose's ball joints, the link direction as rps3_ik has it, to
       check the root */
    for (i = 0; i < 3; i++) {
      double v[3];
      v3_sub(v, d->b[i], m->pin[i]);
      c39[i] = -v3_dot(v, m->radial[i]) / d->l[i];
      s39[i] = v[2] / d->l[i];
    }
    v3_copy(th0, d->theta);
    if (m->opt.warm_start) predicted = rps3_root_predict(d, PREDICT_MAX);
    status = rps3_theta_solve_with(m, d, J);
    /* near the singular surface G = dtheta/dl grows and the predicted
       start can land across the fold, where the solve finds the other
       assembly mode's root (a few 1e-3 rad away): the solve again from
       the last root itself, whose mode the motion keeps */
    if (predicted && (status != RPS3_OK || (d->warn & RPS3_WARN_MODE))) {
      v3_copy(d->theta, th0);
      d->have_theta = 1;
      d->mode = mode0;
      status = rps3_theta_solve_with(m, d, J);
    }
    if (status != RPS3_OK) return status;
    status = check_own_root(m, d, J, c39, s39);
    if (status != RPS3_OK) return status;
    rps3_root_keep(m, d, J);
  }

  if (need_rates) {
    status = rps3_velocity_with(m, d, &trig);
    if (status != RPS3_OK) return status;
    status = rps3_acceleration_with(m, d, &trig);
    if (status != RPS3_OK) return status;
  }
  return RPS3_OK;
}
