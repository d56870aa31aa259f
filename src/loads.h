/*
 * loads.h - the loads of the effects on each link, the left-hand side of
 * (23), written once.
 *
 * Link i has two coordinates, l_i and theta_i; the ball joint b_i moves by
 * phi_i per unit l_i and by l_i dphi_i per unit theta_i ((12)-(14), (29)).
 * A force f on the ball joint is then the load wl = phi_i . f on l_i and
 * wt = l_i dphi_i . f on theta_i; a torque about the pin goes into wt
 * alone.  The platform, the uniform disc of (21), has the mass, centroid
 * and inertia tensor of M/2 at its centre and M/6 at each ball joint
 * (src/invdyn.c's header); since c = (b_1 + b_2 + b_3) / 3, a move of b_i
 * moves the centre by a third of it, so the centre's M/2 reaches link i
 * as M/6 too:
 *   platform gravity (22)  f = (M g / 3) e_z,
 *   platform inertia (21)  f = (M/6) (c'' + b_i''),
 *   link gravity (22)      wt = m g d cos(theta_i)  (cos theta_i = dphi_i,z),
 *   link inertia (21)      wt = Jlink theta_i'',  Jlink = m d^2 + I_c,
 *   pin friction           wt = -T_friction(theta_i')  (the law of
 *                          rps3_friction_torque, internal.h).
 * The payload, a general body on the platform, is body_load of
 * src/invdyn.c.
 *
 * Macros over the vector type, as RPS3_CJAC_ROW of src/cjac.h: C(v, k) is
 * component k (the literal 0, 1 or 2) of a vector v, so that the staged
 * route (src/invdyn.c, double[3]) and the vectorised batch kernel
 * (src/batch_kmech.h, kv3 by value) compile the same text and stay
 * bitwise one another (tests/test_batch.c).  Each coefficient is an
 * argument (the kernel folds its selection of the effect into some), each
 * formula of a coefficient a macro of its own.  docs/library.md, "The
 * formulation", says which sites instantiate what.
 *
 * Not installed.
 */
#ifndef RPS3_LOADS_H
#define RPS3_LOADS_H

/* the disc's share at each ball joint, M/6 (with the centre's M/2, see
   above) */
#define RPS3_DISC_BALL_MASS(M) ((M) / 6.0)
/* the platform's weight on each ball joint, M g / 3 */
#define RPS3_PLATFORM_BALL_WEIGHT(M, g) ((M) * (g) / 3.0)
/* the moment of a link's weight about its pin at theta = 0, m g d */
#define RPS3_LINK_WEIGHT_MOMENT(m, g, d) ((m) * (g) * (d))

/* platform gravity on link i: W = RPS3_PLATFORM_BALL_WEIGHT on the ball,
   phi_z and dphi_z the links' Z components, l its length */
#define RPS3_LOAD_PLATFORM_GRAVITY(W, phi_z, dphi_z, l, wl, wt) \
  do {                                                          \
    (wl) = (W) * (phi_z);                                       \
    (wt) = (W) * (l) * (dphi_z);                                \
  } while (0)

/* platform inertia on link i: the ball's share m6 = RPS3_DISC_BALL_MASS
   at the acceleration c'' + b_i'' (cdd, bdd), on phi and l dphi */
#define RPS3_LOAD_PLATFORM_INERTIA(C, m6, cdd, bdd, phi, dphi, l, wl, wt)  \
  do {                                                                     \
    const double f0_ = (m6) * (C(cdd, 0) + C(bdd, 0));                     \
    const double f1_ = (m6) * (C(cdd, 1) + C(bdd, 1));                     \
    const double f2_ = (m6) * (C(cdd, 2) + C(bdd, 2));                     \
    (wl) = C(phi, 0) * f0_ + C(phi, 1) * f1_ + C(phi, 2) * f2_;            \
    (wt) = (l) * (C(dphi, 0) * f0_ + C(dphi, 1) * f1_ + C(dphi, 2) * f2_); \
  } while (0)

/* link gravity on theta_i: mgd = RPS3_LINK_WEIGHT_MOMENT times
   cos(theta_i) */
#define RPS3_LOAD_LINK_GRAVITY(mgd, cos_theta, wt) ((wt) = (mgd) * (cos_theta))

/* link inertia on theta_i: Jlink theta_i'' */
#define RPS3_LOAD_LINK_INERTIA(Jlink, ddtheta, wt) ((wt) = (Jlink) * (ddtheta))

/* pin friction on theta_i: the torque Tf opposes the motion, an applied
   torque enters (23) with a minus sign */
#define RPS3_LOAD_PIN_FRICTION(Tf, wt) ((wt) = -(Tf))

/* C(v, k) of a double[3] (src/links.h defines it too) */
#ifndef RPS3_V3C
#define RPS3_V3C(v, k) ((v)[k])
#endif

#endif /* RPS3_LOADS_H */
