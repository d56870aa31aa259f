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

/* the model's constants the loop reads, hoisted out of it */
typedef struct {
  double r, R, M, g, Mg3, M6, mgd, Jlink, Ip[3];
  double pin[3][2], u[3][2], body[3][2]; /* z components are zero */
  double sel[RPS3_KNEFF];  /* 1 when effect k is selected, else 0 */
  double certify, cond_lim, trans_lim;
  double rates;            /* 1 when the rates are the caller's, 0 zero */
  double w_scale;          /* 2 / (3 r^2), rps3_omega_from_balls */
} kconst;

/* with GCC or clang on x86-64 (ifunc), the loop also for AVX2 + FMA and
   AVX-512: the same operations on wider vectors (no contraction into
   FMA: -ffp-contract=off), hence the same results on every CPU */
#if defined(__x86_64__) && defined(__linux__) &&                              \
    (defined(__clang__) ? __clang_major__ >= 14 : __GNUC__ >= 12)
#define KCLONES                                                               \
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
  kv3 b, rho, phi, dphi; /* ball joint, b - c, directions (29) */
  double l, il, th, ok;  /* length, 1 / l, theta (39), reachable (1/0) */
  double dl, dth, ddl, ddth; /* joint rates and accelerations */
  kv3 bdd;               /* ball-joint acceleration from those (invdyn.c) */
} klink;

/* link i from the platform frame (columns rx, ry) and centre c: (15)-(17),
   (5)-(7), (39) and (29), as rps3_ik_with */
KINLINE klink link_pos(const kconst *K, int i, kv3 rx, kv3 ry, kv3 c,
                       int full) {
  klink L;
  double radial, ct, st;
  kv3 v;
  L.b = kadd(c, kadd(kscale(K->body[i][0], rx), kscale(K->body[i][1], ry)));
  L.rho = ksub(L.b, c);
  v = kv(L.b.x - K->pin[i][0], L.b.y - K->pin[i][1], L.b.z);
  L.l = sqrt(kdot(v, v));
  radial = v.x * K->u[i][0] + v.y * K->u[i][1];
  L.ok = ((L.l > 0.0) & (v.z > 0.0)) ? 1.0 : 0.0;
  /* select, then divide: a division under a condition is a branch */
  L.il = 1.0 / (L.l > 0.0 ? L.l : 1.0);
  L.th = full > 0 ? katan2(v.z > 0.0 ? v.z : 1.0, -radial) : 0.0;
  ct = -radial * L.il;
  st = v.z * L.il;
  L.phi = kv(-ct * K->u[i][0], -ct * K->u[i][1], st);
  L.dphi = kv(st * K->u[i][0], st * K->u[i][1], ct);
  return L;
}

/* joint rates and accelerations of link L (rps3_velocity_with,
   rps3_acceleration_with), then b'' from them (lagrange_kinematics) */
KINLINE klink link_rates(klink L, kv3 w, kv3 vc, kv3 dw, kv3 ac) {
  kv3 bd = kadd(kcross(w, L.rho), vc);
  kv3 bb = kadd(kadd(kcross(dw, L.rho), kcross(w, kcross(w, L.rho))), ac);
  double s1, s2;
  L.dl = kdot(L.phi, bd);
  L.dth = kdot(L.dphi, bd) * L.il;
  L.ddl = kdot(L.phi, bb) + L.l * L.dth * L.dth;
  L.ddth = (kdot(L.dphi, bb) - 2.0 * L.dl * L.dth) * L.il;
  s1 = L.ddl - L.l * L.dth * L.dth;
  s2 = 2.0 * L.dl * L.dth + L.l * L.ddth;
  L.bdd = kadd(kscale(s1, L.phi), kscale(s2, L.dphi));
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
  r.lc = 2.0 * kdot(D, Lk.phi);
  r.le = -2.0 * kdot(D, Lj.phi);
  r.ta = 2.0 * Lk.l * kdot(D, Lk.dphi);
  r.tb = -2.0 * Lj.l * kdot(D, Lj.dphi);
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
  return kscale(-1.0, kadd(kadd(kscale(wt.x, r0), kscale(wt.y, r1)),
                           kscale(wt.z, r2)));
}

/* the transmission row of link e: the platform twist (vc, omega) for a
   unit rate of link e, theta' = x = -Jt^-1 Jl e_e; ball i moves
   [i == e] phi_i + l_i x_i dphi_i, and omega follows from the balls as in
   rps3_omega_from_balls (the vc part drops: sum rho_i = 0), with
   rho_i x dphi_i in Q_i and rho_i x phi_e in P; returns |vc|_1 + R
   |omega|_1 */
KINLINE double trans_row(const kconst *K, klink L0, klink L1, klink L2,
                         kv3 Q0, kv3 Q1, kv3 Q2, kv3 x, kv3 phi, kv3 P,
                         kv3 a) {
  double s0 = L0.l * x.x, s1 = L1.l * x.y, s2 = L2.l * x.z, sd;
  kv3 v = kadd(kadd(kadd(kscale(s0, L0.dphi), kscale(s1, L1.dphi)),
                    kscale(s2, L2.dphi)), phi);
  kv3 ws = kadd(kadd(kadd(kscale(s0, Q0), kscale(s1, Q1)), kscale(s2, Q2)),
                P);
  v = kscale(1.0 / 3.0, v);
  ws = kscale(K->w_scale, ws);
  sd = 0.5 * kdot(a, ws);
  return knorm1(v) + K->R * knorm1(ksub(ws, kscale(sd, a)));
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
KINLINE void kdata(rps3_data *d, kv3 rx, kv3 ry, kv3 rz, klink L0,
                   klink L1, klink L2, kv3 w, kv3 vc, kv3 dw, kv3 ac,
                   int rates) {
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

#endif /* RPS3_BATCH_KMECH_H */
