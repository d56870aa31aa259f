/*
 * links.h - the positions and rates of a link, written once.
 *
 * Link i joins its pin P_i (in the base's xy plane, radial unit vector
 * u_i) to the ball joint b_i of the platform.  From the platform's frame
 * (columns rx, ry of (2)) and centre c (3)-(4):
 *   ball joint (15)-(17)   rho_i = x_i rx + y_i ry,  b_i = c + rho_i
 *                          ((x_i, y_i) the ball in the platform's plane),
 *   link vector (5)-(7)    v_i = b_i - P_i,  l_i = |v_i|,
 *                          v_i . u_i = -l_i cos theta_i,
 *                          v_i,z = l_i sin theta_i,
 *   angle (39)             theta_i = atan2(v_i,z, -v_i . u_i),
 *   directions (29)        phi_i = -cos theta_i u_i + sin theta_i e_z,
 *                          dphi_i = sin theta_i u_i + cos theta_i e_z;
 * from the platform's twist (omega, vc) and its rate (omega', ac):
 *   ball velocity (26)     b_i' = omega x rho_i + vc,
 *   ball acceleration      b_i'' = omega' x rho_i + omega x (omega x
 *                          rho_i) + ac,
 *   joint rates (28)       l' = phi . b',  theta' = dphi . b' / l,
 *                          l'' = phi . b'' + l theta'^2,
 *                          theta'' = (dphi . b'' - 2 l' theta') / l,
 * and back, the ball joint and its motion from the joint coordinates
 * and rates ((12)-(14) and its derivatives):
 *   b = P + l phi,
 *   b' = l' phi + l theta' dphi,
 *   b'' = (l'' - l theta'^2) phi + (2 l' theta' + l theta'') dphi.
 *
 * Macros over the vector type, as RPS3_CJAC_ROW of src/cjac.h and the
 * loads of src/loads.h: C(v, k) is component k (the literal 0, 1 or 2) of
 * a vector v (an lvalue for the outputs), DOT(a, b) the dot product,
 * MA(a, b, c) = a b + c and MS(a, b, c, d) = a b - c d, the last two
 * either plain (RPS3_MA, RPS3_MS) or fused into one rounding.  The staged
 * route (src/ik.c, src/velocity.c, src/invdyn.c; double[3] and the plain
 * operators), the batch kernel (src/batch_kmech.h, kv3 by value, plain)
 * and its lean pass (kv3, fused where the CPU has FMA) compile the same
 * text.  The lean pass instantiates the directions and the rates with its
 * scaled vectors v = l phi, q = l dphi in place of (phi, dphi) and 1 / l^2
 * in place of 1 / l: its theta' and theta'' are the link's, its "l'" is
 * l l'.  docs/library.md, "The formulation", says which sites instantiate
 * what.
 *
 * Not installed.
 */
#ifndef RPS3_LINKS_H
#define RPS3_LINKS_H

/* the plain operators: a b + c and a b - c d in two roundings */
#define RPS3_MA(a, b, c) ((a) * (b) + (c))
#define RPS3_MS(a, b, c, d) ((a) * (b) - (c) * (d))

/* C(v, k) of a double[3] (as in src/loads.h) */
#ifndef RPS3_V3C
#define RPS3_V3C(v, k) ((v)[k])
#endif

/* the ball joint (15)-(17) at (bx, by) in the platform's plane: its
   offset rho from the centre c and b = c + rho, rx and ry the frame's
   first two columns; clang-format would take (by) * C(...) for a cast,
   here and below */
/* clang-format off */
#define RPS3_LINK_BALL(C, MA, bx, by, rx, ry, c, rho, b)  \
  do {                                                    \
    C(rho, 0) = MA((bx), C(rx, 0), (by) * C(ry, 0));      \
    C(rho, 1) = MA((bx), C(rx, 1), (by) * C(ry, 1));      \
    C(rho, 2) = MA((bx), C(rx, 2), (by) * C(ry, 2));      \
    C(b, 0) = C(c, 0) + C(rho, 0);                        \
    C(b, 1) = C(c, 1) + C(rho, 1);                        \
    C(b, 2) = C(c, 2) + C(rho, 2);                        \
  } while (0)
/* clang-format on */

/* the link vector v = b - P (5)-(7) of the pin (px, py, 0), its squared
   length l2, length l and radial component v . u = -l cos theta of the
   pin's radial unit vector (ux, uy, 0) */
#define RPS3_LINK_VEC(C, DOT, MA, b, px, py, ux, uy, v, l2, l, radial) \
  do {                                                                 \
    C(v, 0) = C(b, 0) - (px);                                          \
    C(v, 1) = C(b, 1) - (py);                                          \
    C(v, 2) = C(b, 2);                                                 \
    (l2) = DOT(v, v);                                                  \
    (l) = sqrt(l2);                                                    \
    (radial) = MA(C(v, 0), (ux), C(v, 1) * (uy));                      \
  } while (0)

/* a link is reachable when its length (or squared length) and its
   ball's height vz above the base are positive; 1 or 0 */
#define RPS3_LINK_REACHABLE(l, vz) (((l) > 0.0) & ((vz) > 0.0))

/* theta (39) by the two-argument arc tangent ATAN2, so that theta > pi/2
   is found too */
#define RPS3_LINK_THETA(ATAN2, radial, vz) ATAN2((vz), -(radial))

/* cos and sin of theta from the radial component, the height and 1 / l */
#define RPS3_LINK_COS_SIN(radial, vz, il, ct, st) \
  do {                                            \
    (ct) = -(radial) * (il);                      \
    (st) = (vz) * (il);                           \
  } while (0)

/* the directions (29) from ct, st (cos and sin theta, or l times them)
   and the radial unit vector (ux, uy, 0): phi = -ct u + st e_z and
   dphi = st u + ct e_z, each on its own (the lean pass forms dphi
   alone) */
#define RPS3_LINK_PHI(C, ux, uy, ct, st, phi) \
  do {                                        \
    C(phi, 0) = -(ct) * (ux);                 \
    C(phi, 1) = -(ct) * (uy);                 \
    C(phi, 2) = (st);                         \
  } while (0)
#define RPS3_LINK_DPHI(C, ux, uy, ct, st, dphi) \
  do {                                          \
    C(dphi, 0) = (st) * (ux);                   \
    C(dphi, 1) = (st) * (uy);                   \
    C(dphi, 2) = (ct);                          \
  } while (0)

/* the ball's velocity (26) from the platform's twist: wr = omega x rho,
   bd = wr + vc */
#define RPS3_BALL_VEL(C, MS, w, rho, vc, wr, bd)           \
  do {                                                     \
    C(wr, 0) = MS(C(w, 1), C(rho, 2), C(w, 2), C(rho, 1)); \
    C(wr, 1) = MS(C(w, 2), C(rho, 0), C(w, 0), C(rho, 2)); \
    C(wr, 2) = MS(C(w, 0), C(rho, 1), C(w, 1), C(rho, 0)); \
    C(bd, 0) = C(wr, 0) + C(vc, 0);                        \
    C(bd, 1) = C(wr, 1) + C(vc, 1);                        \
    C(bd, 2) = C(wr, 2) + C(vc, 2);                        \
  } while (0)

/* the ball's acceleration, the derivative of (26): bb = omega' x rho +
   omega x wr + ac, wr = omega x rho of RPS3_BALL_VEL */
#define RPS3_BALL_ACC(C, MS, w, dw, rho, wr, ac, bb)                \
  do {                                                              \
    C(bb, 0) = MS(C(dw, 1), C(rho, 2), C(dw, 2), C(rho, 1)) +       \
               MS(C(w, 1), C(wr, 2), C(w, 2), C(wr, 1)) + C(ac, 0); \
    C(bb, 1) = MS(C(dw, 2), C(rho, 0), C(dw, 0), C(rho, 2)) +       \
               MS(C(w, 2), C(wr, 0), C(w, 0), C(wr, 2)) + C(ac, 1); \
    C(bb, 2) = MS(C(dw, 0), C(rho, 1), C(dw, 1), C(rho, 0)) +       \
               MS(C(w, 0), C(wr, 1), C(w, 1), C(wr, 0)) + C(ac, 2); \
  } while (0)

/* the joint rates (28) from the ball's velocity bd: dl = phi . bd,
   dth = dphi . bd / l (il = 1 / l) */
#define RPS3_LINK_VEL(DOT, phi, dphi, il, bd, dl, dth) \
  do {                                                 \
    (dl) = DOT(phi, bd);                               \
    (dth) = DOT(dphi, bd) * (il);                      \
  } while (0)

/* l'' = phi . bb + l theta'^2 from the ball's acceleration bb */
#define RPS3_LINK_ACC_L(DOT, phi, l, bb, dth, ddl) \
  ((ddl) = DOT(phi, bb) + (l) * (dth) * (dth))

/* theta'' = (dphi . bb - 2 l' theta') / l */
/* clang-format would take (dl) * (dth) for a cast */
/* clang-format off */
#define RPS3_LINK_ACC_THETA(DOT, dphi, il, bb, dl, dth, ddth) \
  ((ddth) = (DOT(dphi, bb) - 2.0 * (dl) * (dth)) * (il))
/* clang-format on */

/* the ball joint from the joint coordinates (12)-(14): b = P + l phi, P
   the pin */
/* clang-format off */
#define RPS3_BALL_AT(C, pin, l, phi, b)     \
  do {                                      \
    C(b, 0) = C(pin, 0) + (l) * C(phi, 0);  \
    C(b, 1) = C(pin, 1) + (l) * C(phi, 1);  \
    C(b, 2) = C(pin, 2) + (l) * C(phi, 2);  \
  } while (0)
/* clang-format on */

/* the ball's velocity from the joint rates: bd = l' phi + l theta' dphi */
/* clang-format off */
#define RPS3_BALL_VEL_JOINTS(C, phi, dphi, l, dl, dth, bd)  \
  do {                                                      \
    const double s_ = (l) * (dth);                          \
    C(bd, 0) = (dl) * C(phi, 0) + s_ * C(dphi, 0);          \
    C(bd, 1) = (dl) * C(phi, 1) + s_ * C(dphi, 1);          \
    C(bd, 2) = (dl) * C(phi, 2) + s_ * C(dphi, 2);          \
  } while (0)
/* clang-format on */

/* the ball's acceleration from the joint rates: bdd = (l'' - l theta'^2)
   phi + (2 l' theta' + l theta'') dphi */
/* clang-format off */
#define RPS3_BALL_ACC_JOINTS(C, phi, dphi, l, dl, dth, ddl, ddth, bdd) \
  do {                                                                 \
    const double s1_ = (ddl) - (l) * (dth) * (dth);                    \
    const double s2_ = 2.0 * (dl) * (dth) + (l) * (ddth);              \
    C(bdd, 0) = s1_ * C(phi, 0) + s2_ * C(dphi, 0);                    \
    C(bdd, 1) = s1_ * C(phi, 1) + s2_ * C(dphi, 1);                    \
    C(bdd, 2) = s1_ * C(phi, 2) + s2_ * C(dphi, 2);                    \
  } while (0)
/* clang-format on */

#endif /* RPS3_LINKS_H */
