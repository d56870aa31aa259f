/*
 * fwddyn_plane.h - the forward dynamics' state in the links' planes
 * (src/fwddyn.c's header comment has the formulation): the constraint
 * Jacobians and their inverse, the rates, the bias accelerations and the
 * velocity maps, Mq and hq from them, formed by static inline steps that
 * compile into rps3_fwddyn_state's one evaluation.  Included by the
 * forward dynamics' files only (src/fwddyn*.c).
 */
#ifndef RPS3_FWDDYN_PLANE_H
#define RPS3_FWDDYN_PLANE_H

#include "fwddyn.h"
#include "loads.h"
#include "power.h"

/* omega from sum_i rho_i x u_i for the ball motions u_i = omega x rho_i
   ((26)-(28) in closed form, src/power.h's RPS3_OMEGA_OF_SUM, as
   rps3_omega_from_balls); wk = 2 / (3 r^2) */
static inline void omega_of_sum(double omega[3], const double w[3],
                                const double a[3], double wk) {
  RPS3_OMEGA_OF_SUM(RPS3_V3C, wk, w[0], w[1], w[2], a, omega);
}

/* the steps below are meant to compile into their callers' one
   evaluation (GCC otherwise keeps some out of line: a call, and its
   arguments through memory) */
#if defined(__GNUC__)
#define FD_INLINE static inline __attribute__((always_inline))
#else
#define FD_INLINE static inline
#endif

/* C99 does not convert double (*)[2] to const double (*)[2] implicitly */
#define M2C(A) ((const double(*)[2])(A))

/* the larger of a and b (fmax is a call at -O2).  A NaN in a is dropped:
   each use below is followed by a test that a NaN fails (the Newton
   step's sum of |f|, the finite start, det and the inverse's scale) */
static inline double max2(double a, double b) { return a > b ? a : b; }

/* the state in the links' planes: `plane`, in fwddyn.h */

/* the constraints f_k [m^2] at p's l, c, s and their derivatives in
   theta (at, bt), with A, B, E (rps3_closure_eval, in metres): one Newton
   iteration's evaluation, whose last is the state's (plane_jacobian reads
   it); the series step of theta's cosines and sines is rps3_trig_step
   (src/theta.h) */
FD_INLINE void plane_constraints(const rps3_model *m, plane *p, double f[3]) {
  p->q.R = m->R;
  p->q.r3 = 3.0 * m->r * m->r;
  rps3_closure_eval(&p->q, f);
}

/* det df/dtheta: column i of df/dtheta holds at[i] and bt[i - 1], a
   cyclic bidiagonal matrix */
static inline double plane_det(const plane *p) {
  const double *a = p->q.at, *b = p->q.bt;
  return a[0] * (a[1] * a[2]) + b[0] * (b[1] * b[2]);
}

/* X = (df/dtheta)^-1 by its adjugate, det its determinant (plane_det) */
static inline void plane_inverse(plane *p, double det) {
  const double *a = p->q.at, *b = p->q.bt, id = 1.0 / det;
  p->X[0][0] = a[1] * a[2] * id;
  p->X[0][1] = -b[0] * a[2] * id;
  p->X[0][2] = b[0] * b[1] * id;
  p->X[1][0] = b[1] * b[2] * id;
  p->X[1][1] = a[0] * a[2] * id;
  p->X[1][2] = -a[0] * b[1] * id;
  p->X[2][0] = -a[1] * b[2] * id;
  p->X[2][1] = b[0] * b[2] * id;
  p->X[2][2] = a[0] * a[1] * id;
}

/* the 1-norm condition number of df/dtheta, from its entries and its
   inverse X */
static inline double plane_cond1(const plane *p) {
  double n1 = 0.0, ni = 0.0;
  int i;
  for (i = 0; i < 3; i++) {
    n1 = max2(n1, fabs(p->q.at[i]) + fabs(p->q.bt[(i + 2) % 3]));
    ni = max2(ni, fabs(p->X[0][i]) + fabs(p->X[1][i]) + fabs(p->X[2][i]));
  }
  return n1 * ni;
}

/* the constraint Jacobians (df/dtheta from plane_constraints at the
   state's root), the mode (sign of det(df/dtheta), grouped as
   rps3_mode_of_jac groups it), (df/dtheta)^-1 and its 1-norm condition
   number (RPS3_ESING past opt.cond_max); column i of df/dtheta holds
   at[i] and bt[i - 1] */
static inline int plane_jacobian(const rps3_model *m, rps3_data *d, plane *p) {
  double det, cond;
  int q;
  for (q = 0; q < 3; q++) {
    const int j = (q + 1) % 3;
    rps3_plane_pair pq;
    pq.A = p->q.A[q];
    pq.B = p->q.B[q];
    pq.E = p->q.E[q];
    rps3_plane_pair_dl(&pq, p->q.c[q], p->q.s[q], p->q.c[j], p->q.s[j],
                       &p->al[q], &p->bl[q]);
  }
  det = plane_det(p);
  d->mode = (det > 0.0) - (det < 0.0);
  if (!(fabs(det) > 0.0) || !(fabs(det) < HUGE_VAL))
    return rps3_sing_decide(m, d, RPS3_SING_JT, HUGE_VAL);
  plane_inverse(p, det);
  cond = plane_cond1(p);
  return rps3_sing_check(m, d, RPS3_SING_JT, cond);
}

/* G = -X df/dl (column j of df/dl holds al[j] and bl[j - 1]); the rates
   theta' = G l' and the balls' in-plane rates (28); the bias theta''
   from the second derivative of (8)-(10), (df/dtheta) theta'' = x with
   x_k = -(2 |b_i' - b_j'|^2 + A h_i''0 + B h_j''0 + E (Z_i''0 - Z_j''0))
   (rps3_constraint_acc_rhs in the links' planes; ''0: without theta''),
   and the balls' and the centre's accelerations at l'' = 0; Jc, column j
   the centre's velocity (25) for l_j' = 1 */
static inline void plane_rates(plane *p, const double u[3][2]) {
  const double third = 1.0 / 3.0; /* a product: divisions are slow */
  double x[3];
  int i, j, q;
  for (j = 0; j < 3; j++) {
    const int k = (j + 2) % 3;
    for (i = 0; i < 3; i++)
      p->G[i][j] = -(p->X[i][j] * p->al[j] + p->X[i][k] * p->bl[k]);
  }
  for (i = 0; i < 3; i++)
    p->dth[i] =
        p->G[i][0] * p->dl[0] + p->G[i][1] * p->dl[1] + p->G[i][2] * p->dl[2];
  rps3_closure_bias(&p->q, p->dl, p->dth, x, p->hd, p->Zd, p->hdd, p->Zdd);
  for (i = 0; i < 3; i++) {
    p->ddb[i] = p->X[i][0] * x[0] + p->X[i][1] * x[1] + p->X[i][2] * x[2];
    p->hdd[i] += p->q.l[i] * p->q.s[i] * p->ddb[i];
    p->Zdd[i] += p->q.l[i] * p->q.c[i] * p->ddb[i];
  }
  for (q = 0; q < 2; q++)
    p->acb[q] =
        (p->hdd[0] * u[0][q] + p->hdd[1] * u[1][q] + p->hdd[2] * u[2][q]) *
        third;
  p->acb[2] = (p->Zdd[0] + p->Zdd[1] + p->Zdd[2]) * third;
  for (j = 0; j < 3; j++) {
    /* dh_i/dl_j' = l_i sin_i G_ij - cos_j [i = j], dZ_i/dl_j' = l_i cos_i
       G_ij + sin_j [i = j] */
    double sh0 = -p->q.c[j] * u[j][0], sh1 = -p->q.c[j] * u[j][1],
           sz = p->q.s[j];
    for (i = 0; i < 3; i++) {
      const double gh = p->q.l[i] * p->q.s[i] * p->G[i][j];
      sh0 += gh * u[i][0];
      sh1 += gh * u[i][1];
      sz += p->q.l[i] * p->q.c[i] * p->G[i][j];
    }
    p->Jc[0][j] = sh0 * third;
    p->Jc[1][j] = sh1 * third;
    p->Jc[2][j] = sz * third;
  }
}

/* the platform's motion from its ball joints, (25)-(28): Jw, column j
   omega for l_j' = 1, into k, from rho_i x u_i and rho_i x e_z (rho_i =
   b_i - c) formed once; with `motion` also vc, omega from sum_i rho_i x
   b_i' and the angular bias acceleration from sum_i rho_i x (b_i'' -
   omega x (omega x rho_i)) (the inverse dynamics' limits read Jw alone).
   The ball joints b_i = h_i u_i + Z_i e_z, the centre (11) and the
   platform's normal a = n x o ((18)-(20): n = rho_1 / r, o = (b_2 - b_3)
   / (sqrt(3) r)) from the plane, so that a state without positions (a
   lean one) has them too */
static inline void platform_motion(const rps3_model *m, const plane *p,
                                   const double u[3][2], int motion,
                                   rps3_fd_state *k, double vc[3],
                                   double om[3]) {
  const double wk = 2.0 / (3.0 * m->r * m->r), third = 1.0 / 3.0;
  const double ak = 1.0 / (RPS3_SQRT3 * m->r * m->r);
  double P[3][3], Q[3][3], rho[3][3], b[3][3], cen[3], e[3], a[3], w[3];
  int i, j, q;
  for (i = 0; i < 3; i++) {
    const double h = m->R - p->q.l[i] * p->q.c[i];
    b[i][0] = h * u[i][0];
    b[i][1] = h * u[i][1];
    b[i][2] = p->q.l[i] * p->q.s[i];
  }
  for (q = 0; q < 3; q++) {
    cen[q] = (b[0][q] + b[1][q] + b[2][q]) * third;
    e[q] = b[1][q] - b[2][q];
  }
  for (i = 0; i < 3; i++)
    for (q = 0; q < 3; q++) rho[i][q] = b[i][q] - cen[q];
  v3_cross(a, rho[0], e);
  for (q = 0; q < 3; q++) a[q] *= ak;
  for (i = 0; i < 3; i++) {
    P[i][0] = -rho[i][2] * u[i][1];
    P[i][1] = rho[i][2] * u[i][0];
    P[i][2] = rho[i][0] * u[i][1] - rho[i][1] * u[i][0];
    Q[i][0] = rho[i][1];
    Q[i][1] = -rho[i][0];
    Q[i][2] = 0.0;
  }
  for (j = 0; j < 3; j++) {
    double wj[3] = {0.0, 0.0, 0.0}, oj[3];
    for (i = 0; i < 3; i++) {
      const double gh =
          p->q.l[i] * p->q.s[i] * p->G[i][j] - (i == j ? p->q.c[i] : 0.0);
      const double gz =
          p->q.l[i] * p->q.c[i] * p->G[i][j] + (i == j ? p->q.s[i] : 0.0);
      for (q = 0; q < 3; q++) wj[q] += gh * P[i][q] + gz * Q[i][q];
    }
    omega_of_sum(oj, wj, a, wk);
    for (q = 0; q < 3; q++) k->Jw[q][j] = oj[q];
  }
  if (!motion) return;
  for (q = 0; q < 2; q++)
    vc[q] =
        (p->hd[0] * u[0][q] + p->hd[1] * u[1][q] + p->hd[2] * u[2][q]) * third;
  vc[2] = (p->Zd[0] + p->Zd[1] + p->Zd[2]) * third;
  w[0] = w[1] = w[2] = 0.0;
  for (i = 0; i < 3; i++)
    for (q = 0; q < 3; q++) w[q] += p->hd[i] * P[i][q] + p->Zd[i] * Q[i][q];
  omega_of_sum(om, w, a, wk);
  w[0] = w[1] = w[2] = 0.0;
  for (i = 0; i < 3; i++) {
    double t[3], wr = v3_dot(om, rho[i]);
    v3_cross(t, rho[i], om);
    for (q = 0; q < 3; q++)
      w[q] += p->hdd[i] * P[i][q] + p->Zdd[i] * Q[i][q] - wr * t[q];
  }
  omega_of_sum(k->dw_b, w, a, wk);
}

/* what rps3_invdyn reports of the configuration, and its limits: the
   lambda system (df/dtheta)^T's condition number (its 1-norm, the
   infinity norm of df/dtheta: rows hold at[q], bt[q]) and the force
   transmission, max over l_j' = 1 of |vc|_1 + R |omega|_1 (the rows of
   dF/d(f, n) by virtual power, rps3_invdyn's transmission()): the
   twist of column q is (Jc, Jw)'s, which the dynamics forms anyway, its
   omega by omega_of_sum; the measure and the largest row src/power.h's */
static inline int invdyn_limits(const rps3_model *m, rps3_data *d,
                                const plane *p, const rps3_fd_state *k) {
  double nr = 0.0, nx = 0.0, T = 0.0;
  int q, st;
  for (q = 0; q < 3; q++) {
/* component c of column q of a 3 x 3 map */
#define FD_COLC(M, c) ((M)[c][q])
    const double sj = RPS3_TRANS_MEASURE(FD_COLC, m->R, p->Jc, k->Jw);
#undef FD_COLC
    nr = max2(nr, fabs(p->q.at[q]) + fabs(p->q.bt[q]));
    nx = max2(nx, fabs(p->X[q][0]) + fabs(p->X[q][1]) + fabs(p->X[q][2]));
    RPS3_TRANS_MAX(T, sj);
  }
  d->cond = nr * nx;
  d->transmission = T;
  st = rps3_sing_check(m, d, RPS3_SING_LAMBDA, d->cond);
  if (st != RPS3_OK) return st;
  return rps3_sing_check(m, d, RPS3_SING_TRANS, T);
}

/* fwddyn_body.c: world inertia rot diag(I) rot^T; a rigid body's terms
   of Mq and hq (mass mb, centre of mass offset s from the platform centre
   and inertia Iw about it, world axes; g = 0 leaves its weight out) */
void rps3_fd_inertia_world(double Iw[3][3], const double rot[3][3],
                           const double I[3]);
void rps3_fd_add_body(const rps3_fd_state *k, const rps3_data *d, double mb,
                      const double s[3], const double Iw[3][3], double g,
                      double Mq[3][3], double hq[3]);

/* the coefficients of the loads (src/loads.h) with the selection of
   their effects folded in, as the batch kernel folds it: an effect left
   out is a zero coefficient; friction and the payload are branches */
typedef struct {
  double m6;  /* RPS3_DISC_BALL_MASS, platform inertia */
  double W;   /* RPS3_PLATFORM_BALL_WEIGHT, platform gravity */
  double Jl;  /* Jlink, link inertia */
  double mgd; /* RPS3_LINK_WEIGHT_MOMENT, link gravity */
} fd_coef;

FD_INLINE fd_coef fd_coef_of(const rps3_model *m) {
  const int eff = m->opt.effects;
  fd_coef K;
  K.m6 = (eff & RPS3_EFF_PLATFORM_INERTIA) ? RPS3_DISC_BALL_MASS(m->M) : 0.0;
  K.W = (eff & RPS3_EFF_PLATFORM_GRAVITY)
            ? RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g)
            : 0.0;
  K.Jl = (eff & RPS3_EFF_LINK_INERTIA) ? m->Jlink : 0.0;
  K.mgd = (eff & RPS3_EFF_LINK_GRAVITY)
              ? RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d)
              : 0.0;
  return K;
}

/* a vector in link i's frame (u_i, e_z x u_i, e_z), the world turned
   about e_z onto the pin's radial unit vector u_i, as the loads read it:
   h along u_i, z vertical.  phi_i = (-cos_i, 0, sin_i) and dphi_i =
   (sin_i, 0, cos_i) lie in the link's plane, so the loads phi_i . f and
   l_i dphi_i . f of a ball force f do not see its component along e_z x
   u_i: the C of src/loads.h over this type has that component 0 */
typedef struct {
  double h, z;
} fd_pv;
#define FD_PC(v, k) FD_PC_##k(v)
#define FD_PC_0(v) ((v).h)
#define FD_PC_1(v) 0.0
#define FD_PC_2(v) ((v).z)

/* the platform's inertia load on link i (src/loads.h) at the centre's
   acceleration c'' = (cx, cy, cz), world axes, and the ball's
   acceleration bdd in the link's frame */
FD_INLINE void platform_load(const rps3_model *m, const plane *p,
                             const fd_coef *K, int i, double cx, double cy,
                             double cz, fd_pv bdd, double *wl, double *wt) {
  fd_pv phi, dphi, cdd;
  phi.h = -p->q.c[i];
  phi.z = p->q.s[i];
  dphi.h = p->q.s[i];
  dphi.z = p->q.c[i];
  cdd.h = cx * m->radial[i][0] + cy * m->radial[i][1];
  cdd.z = cz;
  RPS3_LOAD_PLATFORM_INERTIA(FD_PC, K->m6, cdd, bdd, phi, dphi, p->q.l[i], *wl,
                             *wt);
}

/* the generalized force F = wl + G^T wt of the loads (wl, wt) on the
   links' (l_i, theta_i), the inverse dynamics' (34): F = wl + (df/dl)^T
   lambda with (df/dtheta)^T lambda = -wt */
FD_INLINE void fd_force(const plane *p, const double wl[3], const double wt[3],
                        double F[3]) {
  int j;
  for (j = 0; j < 3; j++)
    F[j] = wl[j] + p->G[0][j] * wt[0] + p->G[1][j] * wt[1] + p->G[2][j] * wt[2];
}

/* hq: the generalized force of the selected effects' loads at the bias
   accelerations (l'' = 0): c'' = ac_bias, b_i'' = (h_i'', Z_i'') of
   plane_rates, theta'' = theta''_bias; as the inverse dynamics' (34), F =
   wl + (df/dl)^T lambda with (df/dtheta)^T lambda = -wt, F = wl + G^T wt */
FD_INLINE void bias_force(const rps3_model *m, const plane *p, const fd_coef *K,
                          double hq[3]) {
  const int fric = (m->opt.effects & RPS3_EFF_PIN_FRICTION) != 0;
  const int pfric = (m->opt.effects & RPS3_EFF_PRISMATIC_FRICTION) != 0;
  double wl[3], wt[3];
  int i;
  for (i = 0; i < 3; i++) {
    double w, v;
    fd_pv bdd;
    bdd.h = p->hdd[i];
    bdd.z = p->Zdd[i];
    platform_load(m, p, K, i, p->acb[0], p->acb[1], p->acb[2], bdd, &wl[i],
                  &wt[i]);
    RPS3_LOAD_PLATFORM_GRAVITY(K->W, p->q.s[i], p->q.c[i], p->q.l[i], w, v);
    wl[i] += w;
    wt[i] += v;
    RPS3_LOAD_LINK_GRAVITY(K->mgd, p->q.c[i], w);
    wt[i] += w;
    RPS3_LOAD_LINK_INERTIA(K->Jl, p->ddb[i], w);
    wt[i] += w;
    if (fric) {
      RPS3_LOAD_PIN_FRICTION(rps3_friction_torque(m, i, p->dth[i]), w);
      wt[i] += w;
    }
    /* the prismatic joint's friction, on l_i alone (invdyn.c) */
    if (pfric) wl[i] += rps3_friction_law(&m->leg[i].prismatic, p->dl[i]);
  }
  fd_force(p, wl, wt, hq);
}

/* Mq's upper triangle, column j the generalized force of the inertia
   loads at the unit acceleration l'' = e_j with the rates zero (c'' = Jc
   e_j, b_i'' = [i = j] phi_i + l_i G_ij dphi_i, theta'' = G e_j), in its
   Gram form: with phi.phi = dphi.dphi = 1, phi.dphi = 0 and the centre's
   M/2 reaching each link as M/6 (src/loads.h), Mq = (M/6) I + G^T
   diag(Jlink + (M/6) l_i^2) G + (M/2) Jc^T Jc.  The loads' columns
   themselves cost twice its flops (docs/library.md, "The formulation");
   tests/test_fd_loads.c holds it to them */
FD_INLINE void mass_gram(const plane *p, const fd_coef *K, double Mq[3][3]) {
  const double mc = 3.0 * K->m6; /* M / 2 at the centre */
  double Jp[3];
  int i, j, q;
  for (i = 0; i < 3; i++) Jp[i] = K->m6 * p->q.l[i] * p->q.l[i] + K->Jl;
  for (j = 0; j < 3; j++)
    for (q = j; q < 3; q++)
      Mq[j][q] = (q == j ? K->m6 : 0.0) + Jp[0] * p->G[0][j] * p->G[0][q] +
                 Jp[1] * p->G[1][j] * p->G[1][q] +
                 Jp[2] * p->G[2][j] * p->G[2][q] +
                 mc * (p->Jc[0][j] * p->Jc[0][q] + p->Jc[1][j] * p->Jc[1][q] +
                       p->Jc[2][j] * p->Jc[2][q]);
}

/* fwddyn_general.c: Mq (symmetric, both triangles) and hq of the general
   bodies, the payload aside, from the inverse dynamics' loads' columns */
void rps3_fd_general(const rps3_model *m, const plane *p, double Mq[3][3],
                     double hq[3]);

/* Mq and hq of the selected effects (src/fwddyn.c's header): hq the
   generalized force of the inverse dynamics' loads (src/loads.h) at the
   bias accelerations, Mq the Gram form of their columns (the general
   bodies': the columns themselves, rps3_fd_general), a payload as a
   rigid body; Mq symmetric to the bit (its upper triangle) */
FD_INLINE void assemble(const rps3_model *m, rps3_data *d,
                        const rps3_fd_state *k, const plane *p) {
  double Mq[3][3], hq[3];
  int j, q;
  if (m->bodies == RPS3_BODIES_GENERAL) {
    rps3_fd_general(m, p, Mq, hq);
  } else {
    const fd_coef K = fd_coef_of(m);
    bias_force(m, p, &K, hq);
    mass_gram(p, &K, Mq);
  }
  if (m->opt.effects & RPS3_EFF_PAYLOAD) {
    double sp[3], Iw[3][3];
    for (j = 0; j < 3; j++)
      for (q = 0; q < j; q++) Mq[j][q] = Mq[q][j];
    m3_mulv(sp, M3C(d->rot), m->payload.com);
    rps3_fd_inertia_world(Iw, M3C(d->rot), m->payload.inertia);
    rps3_fd_add_body(k, d, m->payload.mass, sp, M3C(Iw), m->g, Mq, hq);
  }
  for (j = 0; j < 3; j++) {
    for (q = 0; q < 3; q++) d->Mq[j][q] = (q >= j) ? Mq[j][q] : Mq[q][j];
    d->hq[j] = hq[j];
  }
}

/* a root in another assembly mode than opt.mode asks for is refused, as
   rps3_theta_solve refuses it (the fall-back rps3_fk did already) */
static inline int mode_refused(const rps3_model *m, rps3_data *d,
                               rps3_fd_state *k) {
  if (m->opt.mode == RPS3_MODE_ANY || d->mode == m->opt.mode) return RPS3_OK;
  d->have_theta = 0;
  k->have_trig = 0;
  RPS3_ERROR(d, RPS3_EMODE,
             "root theta = (%.6g, %.6g, %.6g) is in assembly mode %d (sign of "
             "det df/dtheta; +1 the level platform's), opt.mode asks for %d",
             d->theta[0], d->theta[1], d->theta[2], d->mode, m->opt.mode);
}

/* a failure leaves no acceleration that could be read as one */
static inline void poison(rps3_data *d) {
  d->ddl[0] = d->ddl[1] = d->ddl[2] = (double)NAN;
  d->stage &= RPS3_STAGE_POS | RPS3_STAGE_VEL;
}

/* fwddyn_theta.c: theta from d->l by the theta solve's warm Newton path
   (rps3_theta_newton) from d->theta (its cosines and sines in p->q when
   have_trig, else taken there), to a root rps3_theta_solve would accept;
   0 with the root's cosines and sines and the pair terms in p->q, and
   the positions (when `positions`, else NaN when `unset`) and pose (when
   `pose`, else NaN when `unset`) written, -1 for the caller to fall back
   to rps3_fk */
int rps3_fd_theta_newton(const rps3_model *m, rps3_data *d, plane *p,
                         int have_trig, int positions, int pose, int unset);

#endif /* RPS3_FWDDYN_PLANE_H */
