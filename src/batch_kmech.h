/*
 * batch_kmech.h - the mechanics of the batch kernel (batch_kernel.c) one
 * point at a time: the model's constants hoisted out of the loop, 3-vectors
 * by value, the positions and rates of a link ((12)-(17), (5)-(7), (39),
 * (29); rps3_ik_with, rps3_velocity_with, rps3_acceleration_with), a row of
 * the constraint Jacobian of (8)-(10), the lambda system and the forces
 * (34), a row of the force transmission, and the stages' data of the
 * one-point instances.  Everything here is inlined into the loop body so
 * that it vectorises.  Internal; included by batch_kernel.c only.
 */
#ifndef RPS3_BATCH_KMECH_H
#define RPS3_BATCH_KMECH_H

#include "batch_kernel.h"
#include "batch_trig.h"
#include "links.h"
#include "loads.h"
#include "power.h"

/* the model's constants the loop reads, hoisted out of it */
typedef struct {
  double r, R, M, g, Mg3, M6, mgd, Jlink, Ip[3];
  double pin[3][2], u[3][2], body[3][2]; /* z components are zero */
  double sel[RPS3_KNEFF]; /* 1 when effect k is selected, else 0 */
  double certify, cond_lim, trans_lim;
  double rates;   /* 1 when the rates are the caller's, 0 zero */
  double w_scale; /* 2 / (3 r^2), rps3_omega_from_balls */
} kconst;

/* with GCC or clang on x86-64 (ifunc), the loop also for AVX2 + FMA and
   AVX-512: the same operations on wider vectors (no contraction into
   FMA: -ffp-contract=off), hence the same results on every CPU */
#if defined(__x86_64__) && defined(__linux__) && \
    (defined(__clang__) ? __clang_major__ >= 14 : __GNUC__ >= 12)
#define KCLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define KCLONES
#endif

/* 3-vectors by value: the loop body below is straight-line code over
   scalars once these are inlined, which is what the vectoriser needs (a
   loop over the three links inside it would stop it) */
typedef struct {
  double x, y, z;
} kv3;

/* component k (the literal 0, 1 or 2) of a kv3: the C of src/loads.h */
#define KC(v, k) KC_##k(v)
#define KC_0(v) ((v).x)
#define KC_1(v) ((v).y)
#define KC_2(v) ((v).z)

KINLINE kv3 kv(double x, double y, double z) {
  kv3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
KINLINE kv3 kadd(kv3 a, kv3 b) { return kv(a.x + b.x, a.y + b.y, a.z + b.z); }
KINLINE kv3 ksub(kv3 a, kv3 b) { return kv(a.x - b.x, a.y - b.y, a.z - b.z); }
KINLINE kv3 kscale(double s, kv3 a) { return kv(s * a.x, s * a.y, s * a.z); }
KINLINE double kdot(kv3 a, kv3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
KINLINE double knorm1(kv3 a) { return fabs(a.x) + fabs(a.y) + fabs(a.z); }
KINLINE kv3 kcross(kv3 a, kv3 b) {
  return kv(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
            a.x * b.y - a.y * b.x);
}

/* one link of one point */
typedef struct {
  kv3 b, rho, phi, dphi;     /* ball joint, b - c, directions (29) */
  double l, il, th, ok;      /* length, 1 / l, theta (39), reachable (1/0) */
  double dl, dth, ddl, ddth; /* joint rates and accelerations */
  kv3 bdd;                   /* ball-joint acceleration from those (invdyn.c) */
} klink;

/* link i from the platform frame (columns rx, ry) and centre c: (15)-(17),
   (5)-(7), (39) (theta 0 leaves it 0) and (29), as rps3_ik_with; the
   formulas are src/links.h's */
KINLINE klink link_pos(const kconst *K, int i, kv3 rx, kv3 ry, kv3 c,
                       int theta) {
  klink L;
  double l2, radial, ct, st;
  kv3 s, v;
  RPS3_LINK_BALL(KC, RPS3_MA, K->body[i][0], K->body[i][1], rx, ry, c, s, L.b);
  /* the offset as the stages hold it, from b (rps3_velocity_with) */
  L.rho = ksub(L.b, c);
  RPS3_LINK_VEC(KC, kdot, RPS3_MA, L.b, K->pin[i][0], K->pin[i][1], K->u[i][0],
                K->u[i][1], v, l2, L.l, radial);
  (void)l2;
  L.ok = RPS3_LINK_REACHABLE(L.l, v.z) ? 1.0 : 0.0;
  /* select, then divide: a division under a condition is a branch */
  L.il = 1.0 / (L.l > 0.0 ? L.l : 1.0);
  L.th = theta ? RPS3_LINK_THETA(katan2, radial, v.z > 0.0 ? v.z : 1.0) : 0.0;
  RPS3_LINK_COS_SIN(radial, v.z, L.il, ct, st);
  RPS3_LINK_PHI(KC, K->u[i][0], K->u[i][1], ct, st, L.phi);
  RPS3_LINK_DPHI(KC, K->u[i][0], K->u[i][1], ct, st, L.dphi);
  return L;
}

/* joint rates and accelerations of link L (rps3_velocity_with,
   rps3_acceleration_with), then b'' from them (lagrange_kinematics);
   src/links.h's formulas */
KINLINE klink link_rates(klink L, kv3 w, kv3 vc, kv3 dw, kv3 ac) {
  kv3 wr, bd, bb;
  RPS3_BALL_VEL(KC, RPS3_MS, w, L.rho, vc, wr, bd);
  RPS3_BALL_ACC(KC, RPS3_MS, w, dw, L.rho, wr, ac, bb);
  RPS3_LINK_VEL(kdot, L.phi, L.dphi, L.il, bd, L.dl, L.dth);
  RPS3_LINK_ACC_L(kdot, L.phi, L.l, bb, L.dth, L.ddl);
  RPS3_LINK_ACC_THETA(kdot, L.dphi, L.il, bb, L.dl, L.dth, L.ddth);
  RPS3_BALL_ACC_JOINTS(KC, L.phi, L.dphi, L.l, L.dl, L.dth, L.ddl, L.ddth,
                       L.bdd);
  return L;
}

/* row k of the constraint Jacobian of (8)-(10), f_k = |b_k - b_j|^2 - 3r^2,
   j = k + 1: Jl[k][k], Jl[k][j], Jt[k][k], Jt[k][j] */
typedef struct {
  double lc, le, ta, tb;
} krow;

KINLINE krow jac_row(klink Lk, klink Lj) {
  krow r;
  kv3 D = ksub(Lk.b, Lj.b);
  /* the scalar stages' row (src/cjac.h), over kv3 */
  RPS3_CJAC_ROW(kdot, D, Lk.phi, Lk.dphi, Lk.l, Lj.phi, Lj.dphi, Lj.l, r.lc,
                r.le, r.ta, r.tb);
  return r;
}

/* F_i = wl_i + sum_k lambda_k df_k/dl_i (34); link i is in rows i (lc)
   and i - 1 (le) */
KINLINE kv3 kforces(kv3 wl, kv3 lam, kv3 lc, kv3 le) {
  return kv(wl.x + lam.x * lc.x + lam.z * le.z,
            wl.y + lam.x * le.x + lam.y * lc.y,
            wl.z + lam.y * le.y + lam.z * lc.z);
}

/* lambda = -(Jt^-1)^T wt for Jt^-1 with rows r0, r1, r2 */
KINLINE kv3 klambda(kv3 r0, kv3 r1, kv3 r2, kv3 wt) {
  return kscale(
      -1.0, kadd(kadd(kscale(wt.x, r0), kscale(wt.y, r1)), kscale(wt.z, r2)));
}

/* the transmission row of link e: the platform twist (vc, omega) for a
   unit rate of link e, theta' = x = -Jt^-1 Jl e_e; ball i moves
   [i == e] phi_i + l_i x_i dphi_i, omega from the balls (the vc part
   drops: sum rho_i = 0), with rho_i x dphi_i in Q_i and rho_i x phi_e in
   P; returns |vc|_1 + R |omega|_1.  The twist and its measure are
   src/power.h's, as the stages' transmission of invdyn.c */
KINLINE double trans_row(const kconst *K, klink L0, klink L1, klink L2, kv3 Q0,
                         kv3 Q1, kv3 Q2, kv3 x, kv3 phi, kv3 P, kv3 a) {
  const double s0 = L0.l * x.x, s1 = L1.l * x.y, s2 = L2.l * x.z;
  kv3 v, om;
  RPS3_TRANS_TWIST(KC, K->w_scale, s0, s1, s2, L0.dphi, L1.dphi, L2.dphi, Q0,
                   Q1, Q2, phi, P, a, v, om);
  return RPS3_TRANS_MEASURE(KC, K->R, v, om);
}

/* a rate of the data: v, or NaN when the rates were not computed */
KINLINE void kput(double dst[3], kv3 v, int rates) {
  dst[0] = rates ? v.x : (double)NAN;
  dst[1] = rates ? v.y : (double)NAN;
  dst[2] = rates ? v.z : (double)NAN;
}

/* the stages' positions and rates of a point into d,
   as rps3_ik_with, rps3_velocity_with, rps3_acceleration_with and
   rps3_invdyn leave them (the one-point instance below; the block loops
   never reach it) */
KINLINE void kdata(rps3_data *d, kv3 rx, kv3 ry, kv3 rz, klink L0, klink L1,
                   klink L2, kv3 w, kv3 vc, kv3 dw, kv3 ac, int rates) {
  const klink *L[3];
  int i;
  L[0] = &L0;
  L[1] = &L1;
  L[2] = &L2;
  d->rot[0][0] = rx.x;
  d->rot[1][0] = rx.y;
  d->rot[2][0] = rx.z;
  d->rot[0][1] = ry.x;
  d->rot[1][1] = ry.y;
  d->rot[2][1] = ry.z;
  d->rot[0][2] = rz.x;
  d->rot[1][2] = rz.y;
  d->rot[2][2] = rz.z;
  for (i = 0; i < 3; i++) {
    d->b[i][0] = L[i]->b.x;
    d->b[i][1] = L[i]->b.y;
    d->b[i][2] = L[i]->b.z;
    d->phi[i][0] = L[i]->phi.x;
    d->phi[i][1] = L[i]->phi.y;
    d->phi[i][2] = L[i]->phi.z;
    d->dphi[i][0] = L[i]->dphi.x;
    d->dphi[i][1] = L[i]->dphi.y;
    d->dphi[i][2] = L[i]->dphi.z;
    d->dtheta[i] = rates ? L[i]->dth : (double)NAN;
    d->ddtheta[i] = rates ? L[i]->ddth : (double)NAN;
  }
  kput(d->vc, vc, rates);
  kput(d->omega, w, rates);
  kput(d->ac, ac, rates);
  kput(d->domega, dw, rates);
}

/* a 3-vector into component arrays dst[0..2] at point p */
KINLINE void kst(double *const dst[3], int p, kv3 v) {
  dst[0][p] = v.x;
  dst[1][p] = v.y;
  dst[2][p] = v.z;
}

/* ------------------------------------------------------------ lean pass */

/* a b + c, fused (one rounding) when fu is 1, else two roundings; fu is a
   constant of each instance of the lean pass, so the select folds away.
   Explicit, so that the block loop and the one-point function fuse the
   same operations (a compiler's contraction may differ between a vector
   loop and scalar code) */
KINLINE double kma(double a, double b, double c, int fu) {
  return kmaf(a, b, c, fu);
}
KINLINE double kdotf(kv3 a, kv3 b, int fu) {
  return kma(a.x, b.x, kma(a.y, b.y, a.z * b.z, fu), fu);
}
KINLINE kv3 kcrossf(kv3 a, kv3 b, int fu) {
  return kv(kma(a.y, b.z, -(a.z * b.y), fu), kma(a.z, b.x, -(a.x * b.z), fu),
            kma(a.x, b.y, -(a.y * b.x), fu));
}

/*
 * A pose and its rates -> the platform frame (2) by columns, its centre
 * (3)-(4), its angular and centre velocity and their rates (the scalar
 * stages' rps3_pose_frame, rps3_pose_twist and rps3_pose_twist_rate in
 * src/velocity.c), with the trigonometry they share: the one source of
 * the kernel (fu = 0) and the lean pass.  r is the platform radius;
 * in_range is 0 for an angle the sine's reduction does not serve (a point
 * left to the scalar path).
 */
typedef struct {
  double ca, sa, sb, cb, vb2, C, S, in_range;
  kv3 rx, ry, rz, c, w, vc, dw, ac;
} kpose;

KINLINE kpose kpose_eval(double r, double alpha, double beta, double z,
                         double da, double db, double dz, double dda,
                         double ddb, double ddz, int fu) {
  kpose P;
  double ca, sa, hs, hc, sb, cb, vb2, C, S;
  ksc tr = ksincos(alpha, fu);
  P.in_range =
      ((fabs(alpha) <= RPS3_KANGLE_MAX) & (fabs(beta) <= RPS3_KANGLE_MAX))
          ? 1.0
          : 0.0;
  sa = tr.s;
  ca = tr.c;
  tr = ksincos(0.5 * beta, fu);
  hs = tr.s;
  hc = tr.c;
  /* beta from its half angle; 1 - cos(beta) as 2 sin^2(beta/2) */
  sb = 2.0 * hs * hc;
  vb2 = 2.0 * hs * hs;
  cb = 1.0 - vb2;
  C = ca * ca - sa * sa;
  S = 2.0 * sa * ca;

  /* orientation Rz(alpha) Ry(beta) Rz(-alpha) (2) by columns, centre
     (3)-(4) */
  P.rx = kv(1.0 - vb2 * ca * ca, -vb2 * ca * sa, -sb * ca);
  P.ry = kv(-vb2 * ca * sa, 1.0 - vb2 * sa * sa, -sb * sa);
  P.rz = kv(sb * ca, sb * sa, cb);
  P.c = kv(-0.5 * r * vb2 * C, 0.5 * r * vb2 * S, z);

  /* angular and centre velocity and acceleration (velocity.c) */
  P.w = kv(-da * sb * ca - db * sa, -da * sb * sa + db * ca, da * vb2);
  P.vc = kv(-0.5 * r * (sb * db * C - 2.0 * vb2 * S * da),
            0.5 * r * (sb * db * S + 2.0 * vb2 * C * da), dz);
  {
    double dvb = sb * db, ddvb = cb * db * db + sb * ddb;
    double dC = -2.0 * S * da, dS = 2.0 * C * da;
    double ddC = -4.0 * C * da * da - 2.0 * S * dda;
    double ddS = -4.0 * S * da * da + 2.0 * C * dda;
    /* fu = 0: exactly kcross (x + (-y) is x - y) */
    kv3 adot = kcrossf(P.w, P.rz, fu);
    P.dw = kv(dda * -P.rz.x - da * adot.x - ddb * sa - db * da * ca,
              dda * -P.rz.y - da * adot.y + ddb * ca - db * da * sa,
              dda * vb2 - da * adot.z);
    P.ac = kv(-0.5 * r * (ddvb * C + 2.0 * dvb * dC + vb2 * ddC),
              0.5 * r * (ddvb * S + 2.0 * dvb * dS + vb2 * ddS), ddz);
  }
  P.ca = ca;
  P.sa = sa;
  P.sb = sb;
  P.cb = cb;
  P.vb2 = vb2;
  P.C = C;
  P.S = S;
  return P;
}

/* the constants of the leanest pass (outputs = RPS3_OUT_FORCES), each effect's
   selection folded into its coefficient (0 keeps a NaN: 0 * inf) */
typedef struct {
  double r, g3, m6, mgd, jl; /* r; M g / 3, M / 6, m g d, Jlink, selected */
  double cond_lim, trans_lim;
  double tb0, tb1; /* the transmission bound's (sqrt3 / 3) (1 + 4 / rho)
                      and sqrt3 r (kbare) */
  /* the geometry, read from the model where it is (the block's outputs
     are restrict pointers: the loads are hoisted out of the loop) */
  const double (*pin)[3], (*u)[3], (*body)[3]; /* z components are zero */
} kbconst;

KINLINE void kbconst_set(kbconst *K, const rps3_model *m, double margin) {
  const int e = m->opt.effects;
  K->pin = m->pin;
  K->u = m->radial;
  K->body = m->body;
  K->r = m->r;
  K->g3 = (e & RPS3_EFF_PLATFORM_GRAVITY)
              ? RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g)
              : 0.0;
  K->m6 = (e & RPS3_EFF_PLATFORM_INERTIA) ? RPS3_DISC_BALL_MASS(m->M) : 0.0;
  K->mgd = (e & RPS3_EFF_LINK_GRAVITY)
               ? RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d)
               : 0.0;
  K->jl = (e & RPS3_EFF_LINK_INERTIA) ? m->Jlink : 0.0;
  rps3_sing_certify_limits(m, margin, &K->cond_lim, &K->trans_lim);
  K->tb0 = RPS3_SQRT3 / 3.0 * (1.0 + 4.0 / m->rho);
  K->tb1 = RPS3_SQRT3 * m->r;
}

/* one link of the lean pass: the link vector v = b - pin = l phi (5)-(7),
   q = l dphi (29) (in the pin's plane, normal to v), the ball's offset
   rho from the centre; then the link's loads in scalars (the vectors die
   early: fewer values live at once) */
typedef struct {
  kv3 rho, v, q;
  double l, il, il2, ok; /* l, 1 / l, 1 / l^2, reachable (1/0) */
  double wl, wt, s;      /* l wl_i, wt_i of invdyn.c, the load's size [N] */
} kblink;

/* the fused operators of src/links.h for the lean pass: a b + c,
   a b - c d and the dot product, each fused when fu is 1 (fu is the
   instance's constant, in scope where they are used) */
#define KMA_FU(a, b, c) kma(a, b, c, fu)
#define KMS_FU(a, b, c, d) kma(a, b, -((c) * (d)), fu)
#define KDOT_FU(a, b) kdotf(a, b, fu)

/* link i at the platform frame's columns rx, ry and centre c: (15)-(17),
   (5)-(7), src/links.h with the fused operators; q = l dphi is (29) at
   (l cos theta, l sin theta), and phi = v / l, dphi = q / l are never
   formed */
KINLINE kblink kblink_pos(const kbconst *K, int i, kv3 rx, kv3 ry, kv3 c,
                          int fu) {
  kblink L;
  double l2, radial;
  kv3 b;
  RPS3_LINK_BALL(KC, KMA_FU, K->body[i][0], K->body[i][1], rx, ry, c, L.rho, b);
  RPS3_LINK_VEC(KC, KDOT_FU, KMA_FU, b, K->pin[i][0], K->pin[i][1], K->u[i][0],
                K->u[i][1], L.v, l2, L.l, radial);
  RPS3_LINK_DPHI(KC, K->u[i][0], K->u[i][1], -radial, L.v.z, L.q);
  L.ok = RPS3_LINK_REACHABLE(l2, L.v.z) ? 1.0 : 0.0;
  /* 1 / l^2 by a division beside the square root, 1 / l from both: no
     division waits for the root */
  L.il2 = 1.0 / (l2 > 0.0 ? l2 : 1.0);
  L.il = L.l * L.il2;
  return L;
}

/* the loads of link i (lagrange_effect of invdyn.c, the platform disc as
   M/2 at its centre and M/6 at each ball joint): on the ball, f = M/6 (c''
   + b'') + M g / 3 e_z with b'' the rigid platform's acceleration at the
   ball (in the pin's plane, so the projection invdyn.c takes is the same
   load); on the link, tau = m g d cos theta + Jlink theta'' with theta''
   of src/links.h at (v, q, 1 / l^2) in place of (phi, dphi, 1 / l).
   Kept: l wl = v . f, wt = q . f + tau, and s = (|v . f| + |q . f| +
   |tau|) / l, the load in the link's plane */
KINLINE kblink kblink_load(const kbconst *K, kblink L, kv3 w, kv3 vc, kv3 dw,
                           kv3 ac, int fu) {
  kv3 wr, bd, bb, f;
  double vbd, dth, ddth, tau, taug, taui, qf;
  RPS3_BALL_VEL(KC, KMS_FU, w, L.rho, vc, wr, bd);
  RPS3_BALL_ACC(KC, KMS_FU, w, dw, L.rho, wr, ac, bb);
  /* vbd = l l', dth = theta' */
  RPS3_LINK_VEL(KDOT_FU, L.v, L.q, L.il2, bd, vbd, dth);
  RPS3_LINK_ACC_THETA(KDOT_FU, L.q, L.il2, bb, vbd, dth, ddth);
  /* the platform's two loads summed into one ball force, fused (docs/
     library.md, "Left in their own form on purpose"; the loads of
     src/loads.h are its oracle in tests/test_batch_kernel.c) */
  f = kv(K->m6 * (ac.x + bb.x), K->m6 * (ac.y + bb.y),
         kma(K->m6, ac.z + bb.z, K->g3, fu));
  qf = kdotf(L.q, f, fu);
  L.wl = kdotf(L.v, f, fu);
  /* the link's: cos theta = q_z / l */
  RPS3_LOAD_LINK_GRAVITY(K->mgd, L.q.z * L.il, taug);
  RPS3_LOAD_LINK_INERTIA(K->jl, ddth, taui);
  tau = taug + taui;
  L.wt = qf + tau;
  L.s = (fabs(L.wl) + fabs(qf) + fabs(tau)) * L.il;
  return L;
}

/* what the lean pass returns for a point */
typedef struct {
  kv3 F;
  double cond, ok;
  double tbound; /* an upper bound of the force transmission */
} kbout;

/*
 * The lean pass on one point: pose, its rates and accelerations -> F of
 * the selected effects, the lambda system's condition number, and whether
 * the point is the pass's (ok: finite, reachable, within the angle range,
 * cond below the thresholds, and the forces within trans_lim times the
 * largest link load).  The multiplier form of invdyn.c in the link
 * vectors v_i = l_i phi_i and q_i = l_i dphi_i, with the constraint rows
 * halved (f_k / 2: lambda doubles, F does not change):
 *   (df/dtheta)^T lambda = -wt,  wt_i = q_i . f_i + tau_i,
 *   F_i = (v_i . f_i + lambda_i D_i . v_i - lambda_{i-1} D_{i-1} . v_i) / l_i,
 * D_k = b_k - b_{k+1} (8)-(10), (34); the 3 x 3 system by its adjugate,
 * one division for all three.
 */
KINLINE kbout kbare(const kbconst *K, double alpha, double beta, double z,
                    double da, double db, double dz, double dda, double ddb,
                    double ddz, int fu) {
  kbout o;
  double det, idet, an, in, s;
  double ta0, ta1, ta2, tb0, tb1, tb2, e0, e1, e2, g0, g1, g2, m0, m1, m2;
  kv3 rx, ry, c, w, vc, dw, ac, D;
  kv3 a0, a1, a2; /* rows of the adjugate of Jt */
  kblink L0, L1, L2;
  const kpose P =
      kpose_eval(K->r, alpha, beta, z, da, db, dz, dda, ddb, ddz, fu);
  const double in_range = P.in_range;
  rx = P.rx;
  ry = P.ry;
  c = P.c;
  w = P.w;
  vc = P.vc;
  dw = P.dw;
  ac = P.ac;

  /* the links and the halved constraint Jacobian of (8)-(10), row k =
     0, 1, 2 (j = k + 1) in theta, Jt = [ta0 tb0 0; 0 ta1 tb1; tb2 0 ta2],
     and in l, e_k = D_k . v_k (on l_k) and -g_k = -D_k . v_j (on l_j),
     times 1 / l; each row as soon as its two links are there, so that
     fewer values are live at once */
  L0 = kblink_load(K, kblink_pos(K, 0, rx, ry, c, fu), w, vc, dw, ac, fu);
  L1 = kblink_load(K, kblink_pos(K, 1, rx, ry, c, fu), w, vc, dw, ac, fu);
  D = ksub(L0.rho, L1.rho);
  ta0 = kdotf(D, L0.q, fu);
  tb0 = -kdotf(D, L1.q, fu);
  e0 = kdotf(D, L0.v, fu);
  g0 = kdotf(D, L1.v, fu);
  L2 = kblink_load(K, kblink_pos(K, 2, rx, ry, c, fu), w, vc, dw, ac, fu);
  D = ksub(L1.rho, L2.rho);
  ta1 = kdotf(D, L1.q, fu);
  tb1 = -kdotf(D, L2.q, fu);
  e1 = kdotf(D, L1.v, fu);
  g1 = kdotf(D, L2.v, fu);
  D = ksub(L2.rho, L0.rho);
  ta2 = kdotf(D, L2.q, fu);
  tb2 = -kdotf(D, L0.q, fu);
  e2 = kdotf(D, L2.v, fu);
  g2 = kdotf(D, L0.v, fu);
  det = ta0 * ta1 * ta2 + tb0 * tb1 * tb2;
  idet = 1.0 / (det != 0.0 ? det : HUGE_VAL);
  a0 = kv(ta1 * ta2, -tb0 * ta2, tb0 * tb1);
  a1 = kv(tb1 * tb2, ta0 * ta2, -ta0 * tb1);
  a2 = kv(-ta1 * tb2, tb0 * tb2, ta0 * ta1);

  /* det lambda = -adj(Jt)^T wt, then F (34), times 1 / (l_i det) */
  m0 = -kma(L0.wt, a0.x, kma(L1.wt, a1.x, L2.wt * a2.x, fu), fu);
  m1 = -kma(L0.wt, a0.y, kma(L1.wt, a1.y, L2.wt * a2.y, fu), fu);
  m2 = -kma(L0.wt, a0.z, kma(L1.wt, a1.z, L2.wt * a2.z, fu), fu);
  o.F = kv(kma(det, L0.wl, kma(m0, e0, -(m2 * g2), fu), fu) * (L0.il * idet),
           kma(det, L1.wl, kma(m1, e1, -(m0 * g0), fu), fu) * (L1.il * idet),
           kma(det, L2.wl, kma(m2, e2, -(m1 * g1), fu), fu) * (L2.il * idet));

  /* 1-norm condition of the lambda system Jt^T: the largest row sums of
     |Jt| and of |adj Jt| / |det| */
  an = fabs(ta0) + fabs(tb0);
  s = fabs(ta1) + fabs(tb1);
  an = s > an ? s : an;
  s = fabs(ta2) + fabs(tb2);
  an = s > an ? s : an;
  in = knorm1(a0);
  s = knorm1(a1);
  in = s > in ? s : in;
  s = knorm1(a2);
  in = s > in ? s : in;
  o.cond = det != 0.0 ? an * in * fabs(idet) : HUGE_VAL;

  /* an upper bound of the force transmission (invdyn.c): row i is the
     platform twist (vc, omega) at l' = e_i, the balls moving at
     b_j' = [j == i] phi_j + x_j q_j, x = -Jt^-1 (df/dl) e_i; with |D_k| =
     sqrt3 r the entries of df/dl are at most sqrt3 r (halved rows), so
     sum_j |b_j'| <= S = 1 + sqrt3 r |Jt^-1|_inf (l_1 + l_2 + l_3); then
     |vc| <= S / 3 and, the balls at r from the centre
     (rps3_omega_from_balls), |omega| <= (2 / (3 r)) 2 S, so that
     |vc|_1 + R |omega|_1 <= sqrt3 (|vc| + R |omega|) <= tb0 S.
     |Jt^-1|_inf is the adjugate's largest row sum over |det| */
  o.tbound = K->tb0 * (1.0 + K->tb1 * in * fabs(idet) * (L0.l + L1.l + L2.l));
  /* the pass's point: finite, reachable, below the thresholds, and the
     transmission provably below them too */
  /* finite F: finite loads (a load that is not finite makes F so) */
  an = fabs(o.F.x) + fabs(o.F.y) + fabs(o.F.z);
  o.ok = ((in_range * L0.ok * L1.ok * L2.ok != 0.0) &
          (an + o.cond + o.tbound <= DBL_MAX) & (o.cond <= K->cond_lim) &
          (o.tbound <= K->trans_lim))
             ? 1.0
             : 0.0;
  return o;
}

#endif /* RPS3_BATCH_KMECH_H */
