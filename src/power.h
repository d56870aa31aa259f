/*
 * power.h - the energy-rate certificate and the force transmission, the
 * two measures of rps3_invdyn written by power, once.
 *
 * The certificate (src/invdyn.c's certify, the kernel's KF_CERTIFY block
 * in src/batch_kernel.c): the power the actuators and the pins put in,
 * sum F_i l_i' + sum T_i theta_i', equals d(T + P)/dt of the selected
 * effects written from the Cartesian motion (vc, omega, their rates) and
 * the link rates, independently of the forces.  Each effect's term and
 * its share of the scale (the sum of the magnitudes, term by term: the
 * tests' tolerances are eps times it):
 *   platform gravity (22)  dP/dt = M g vc_z,
 *   platform inertia (21)  dT/dt = M vc . c'' + omega . (I_world omega'),
 *                          I_world = rot diag(Ip) rot^T, so
 *                          omega . I_world omega' = sum_k Ip_k (r_k . omega)
 *                          (r_k . omega'), r_k the platform's axes;
 *   payload                the same two of the payload's mass, centre and
 *                          inertia;
 *   link gravity (22)      dP/dt = m g d sum_i cos(theta_i) theta_i',
 *   link inertia (21)      dT/dt = Jlink sum_i theta_i' theta_i'',
 *   pin friction           sum_i T_f(theta_i') theta_i' on the input side.
 *
 * The force transmission (src/invdyn.c's transmission, the kernel's
 * trans_row in src/batch_kmech.h, the forward dynamics' invdyn_limits in
 * src/fwddyn_plane.h): row e of dF/d(f, n) is, by virtual power, the
 * platform twist (vc, omega) for l_e' = 1, and the measure its
 * |vc|_1 + R |omega|_1, the largest over e.  The twist from the links:
 * theta' = G e_e (G = -(df/dtheta)^-1 df/dl), ball i moves
 * [i == e] phi_i + s_i dphi_i with s_i = l_i theta_i' ((12)-(14), (29)),
 * the centre by their mean and omega from the balls, (26)-(28) in closed
 * form: for the ball motions u_i = omega x rho_i (rho_i = b_i - c, three
 * points at 120 degrees in the plane normal to a),
 *   S = sum rho_i x u_i = (3 r^2 / 2) (omega + (a . omega) a),
 * so omega = wk S - (wk / 2) (a . S) a, wk = 2 / (3 r^2).  The centre's
 * part of u_i drops from S (sum rho_i = 0): with Q_i = rho_i x dphi_i and
 * P = rho_e x phi_e, S = sum s_i Q_i + P.
 *
 * Macros over the vector type, as RPS3_CJAC_ROW of src/cjac.h and the
 * loads of src/loads.h: C(v, k) is component k (the literal 0, 1 or 2) of
 * a vector v, an lvalue where the macro writes it, so that the staged
 * route (double[3], RPS3_V3C) and the vectorised kernel (kv3, KC) compile
 * the same text; each coefficient is an argument (the kernel folds its
 * selection of the effect into it).  docs/library.md, "The formulation",
 * says which sites instantiate what.
 *
 * Not installed.
 */
#ifndef RPS3_POWER_H
#define RPS3_POWER_H

#include <math.h>

#include "loads.h" /* RPS3_V3C */

/* ---------------------------------------------- energy-rate certificate */

/* the actuators' power p = sum F_i l_i' and its scale s = sum |F_i l_i'| */
#define RPS3_POWER_ACTUATORS(C, F, dl, p, s)                            \
  do {                                                                  \
    (p) = C(F, 0) * C(dl, 0) + C(F, 1) * C(dl, 1) + C(F, 2) * C(dl, 2); \
    (s) = fabs(C(F, 0) * C(dl, 0)) + fabs(C(F, 1) * C(dl, 1)) +         \
          fabs(C(F, 2) * C(dl, 2));                                     \
  } while (0)

/* a body's weight (22): dP/dt = (m g) v_z, its centre's vertical velocity
   v_z; mg the weight (times the selection) */
#define RPS3_POWER_BODY_GRAVITY(mg, vz, p, s) \
  do {                                        \
    (p) = (mg) * (vz);                        \
    (s) = fabs(p);                            \
  } while (0)

/* a rigid body's kinetic energy (21): dT/dt = mass v . a (its centre's
   velocity and acceleration) + kw omega . (I_world omega'), with
   I_world = sum_k I[k] r_k r_k^T (r0, r1, r2 the body's axes, I its
   principal moments, a double[3]); kw 1, or the kernel's selection.  p
   the power, s the two terms' magnitudes */
#define RPS3_POWER_BODY_INERTIA(C, mass, kw, I, r0, r1, r2, v, a, w, dw, p, s) \
  do {                                                                         \
    const double pt_ =                                                         \
        (mass) * (C(v, 0) * C(a, 0) + C(v, 1) * C(a, 1) + C(v, 2) * C(a, 2));  \
    const double pr_ = (kw) * (RPS3_POWER_AXIS_(C, (I)[0], r0, w, dw) +        \
                               RPS3_POWER_AXIS_(C, (I)[1], r1, w, dw) +        \
                               RPS3_POWER_AXIS_(C, (I)[2], r2, w, dw));        \
    (p) = pt_ + pr_;                                                           \
    (s) = fabs(pt_) + fabs(pr_);                                               \
  } while (0)
/* Ik (rk . dw) (rk . w): axis k's share of omega . I_world omega' */
#define RPS3_POWER_AXIS_(C, Ik, rk, w, dw)                                    \
  ((Ik) * (C(rk, 0) * C(dw, 0) + C(rk, 1) * C(dw, 1) + C(rk, 2) * C(dw, 2)) * \
   (C(rk, 0) * C(w, 0) + C(rk, 1) * C(w, 1) + C(rk, 2) * C(w, 2)))

/* the three links' power k sum_i x_i y_i and its scale, each link on its
   own: |k| sum_i |x_i y_i| */
#define RPS3_POWER_LINKS_(C, k, x, y, p, s)                                  \
  do {                                                                       \
    (p) = (k) * (C(x, 0) * C(y, 0) + C(x, 1) * C(y, 1) + C(x, 2) * C(y, 2)); \
    (s) = fabs(k) * (fabs(C(x, 0) * C(y, 0)) + fabs(C(x, 1) * C(y, 1)) +     \
                     fabs(C(x, 2) * C(y, 2)));                               \
  } while (0)

/* the links' weight (22): dP/dt = m g d sum cos(theta_i) theta_i', mgd =
   RPS3_LINK_WEIGHT_MOMENT (times the selection), cos theta_i = dphi_i,z */
#define RPS3_POWER_LINK_GRAVITY(C, mgd, cos_theta, dtheta, p, s) \
  RPS3_POWER_LINKS_(C, mgd, cos_theta, dtheta, p, s)

/* the links' inertia (21): dT/dt = Jlink sum theta_i' theta_i'' */
#define RPS3_POWER_LINK_INERTIA(C, Jlink, dtheta, ddtheta, p, s) \
  RPS3_POWER_LINKS_(C, Jlink, dtheta, ddtheta, p, s)

/* the pins' friction: sum T_f(theta_i') theta_i', the torques Tf (the law
   of rps3_friction_torque) on the input side of the balance */
#define RPS3_POWER_PIN_FRICTION(C, Tf, dtheta, p, s) \
  RPS3_POWER_LINKS_(C, 1.0, Tf, dtheta, p, s)

/* the certificate's residual: the power put in (the actuators', plus the
   pins' friction where there is one) less dT/dt and dP/dt; zero up to
   rounding, which the scale bounds */
#define RPS3_POWER_RESIDUAL(pin, dTdt, dPdt) ((pin) - (dTdt) - (dPdt))

/* -------------------------------------------------- force transmission */

/* omega from S = sum_i rho_i x u_i, (26)-(28) solved in closed form (see
   above), a the platform's normal and wk = 2 / (3 r^2); S by its
   components (S0, S1, S2), omega written into om */
#define RPS3_OMEGA_OF_SUM(C, wk, S0, S1, S2, a, om)                          \
  do {                                                                       \
    const double w0_ = (wk) * (S0), w1_ = (wk) * (S1), w2_ = (wk) * (S2);    \
    const double h_ = 0.5 * (C(a, 0) * w0_ + C(a, 1) * w1_ + C(a, 2) * w2_); \
    C(om, 0) = w0_ - h_ * C(a, 0);                                           \
    C(om, 1) = w1_ - h_ * C(a, 1);                                           \
    C(om, 2) = w2_ - h_ * C(a, 2);                                           \
  } while (0)

/* component k of the balls' summed motion for a unit rate of link e:
   s0 X0 + s1 X1 + s2 X2 + Y (X the dphi_i and Y phi_e for the centre, X
   the Q_i and Y P for S) */
/* clang-format would take (s0) * C(...) for a cast */
/* clang-format off */
#define RPS3_TRANS_SUM_(C, k, s0, s1, s2, X0, X1, X2, Y) \
  ((s0) * C(X0, k) + (s1) * C(X1, k) + (s2) * C(X2, k) + C(Y, k))
/* clang-format on */

/* the platform twist (vc, om) for l_e' = 1 (see above): s_i = l_i
   theta_i' of the three links, d_i their dphi_i, Q_i = rho_i x dphi_i,
   phi = phi_e, P = rho_e x phi_e, a the platform's normal, wk = 2 /
   (3 r^2) */
#define RPS3_TRANS_TWIST(C, wk, s0, s1, s2, d0, d1, d2, Q0, Q1, Q2, phi, P, a, \
                         vc, om)                                               \
  do {                                                                         \
    C(vc, 0) =                                                                 \
        (1.0 / 3.0) * RPS3_TRANS_SUM_(C, 0, s0, s1, s2, d0, d1, d2, phi);      \
    C(vc, 1) =                                                                 \
        (1.0 / 3.0) * RPS3_TRANS_SUM_(C, 1, s0, s1, s2, d0, d1, d2, phi);      \
    C(vc, 2) =                                                                 \
        (1.0 / 3.0) * RPS3_TRANS_SUM_(C, 2, s0, s1, s2, d0, d1, d2, phi);      \
    RPS3_OMEGA_OF_SUM(C, wk, RPS3_TRANS_SUM_(C, 0, s0, s1, s2, Q0, Q1, Q2, P), \
                      RPS3_TRANS_SUM_(C, 1, s0, s1, s2, Q0, Q1, Q2, P),        \
                      RPS3_TRANS_SUM_(C, 2, s0, s1, s2, Q0, Q1, Q2, P), a,     \
                      om);                                                     \
  } while (0)

/* the measure of one row: |vc|_1 + R |om|_1 (moments in units of the
   mechanism's R) */
#define RPS3_TRANS_MEASURE(C, R, vc, om)              \
  (fabs(C(vc, 0)) + fabs(C(vc, 1)) + fabs(C(vc, 2)) + \
   (R) * (fabs(C(om, 0)) + fabs(C(om, 1)) + fabs(C(om, 2))))

/* the transmission T, the largest row s so far; a row that is not finite
   is kept (the scalar routes refuse it: RPS3_ESING).  The kernel takes
   the larger of its rows by a comparison alone: a point whose rows are
   not finite is not the kernel's (its ok flag) */
#define RPS3_TRANS_MAX(T, s)                  \
  do {                                        \
    if ((s) > (T) || !isfinite(s)) (T) = (s); \
  } while (0)

#endif /* RPS3_POWER_H */
