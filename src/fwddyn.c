/*
 * fwddyn.c - forward dynamics in the link lengths l, the paper's independent
 * coordinates: Mq(l) l'' + hq(l, l') = F, and the energy of a state.
 *
 * Mq and hq are assembled by virtual power (Kane's method), not from the
 * Lagrange multipliers of rps3_invdyn.  Link i moves in the vertical plane
 * of pin i: its ball joint is b_i = h_i u_i + Z_i e_z with h_i = R - l_i
 * cos(theta_i), Z_i = l_i sin(theta_i) ((12)-(14)), u_i the pin's radial
 * unit vector, so the constraints (8)-(10), their Jacobians and the ball
 * joints' motion are written with these two numbers a link.  Every
 * velocity of the mechanism is linear in l':
 *   theta' = G l',  G = -(df/dtheta)^-1 (df/dl)        (from (8)-(10))
 *   b_i'   = l_i' phi_i + l_i theta_i' dphi_i          ((12)-(14), (28))
 *   vc     = Jc l' = (b_1' + b_2' + b_3') / 3          ((11), (25))
 *   omega  = Jw l'  from the ball joints               ((26)-(28))
 * and every acceleration is that map applied to l'' plus its value at
 * l'' = 0 (the velocity-product "bias").  The platform, the uniform disc
 * of (21), has the mass, centroid and inertia tensor of M/2 at its centre
 * and M/6 at each ball joint, so its kinetic energy is that of these
 * points; a ball joint's speed is |b_i'|^2 = l_i'^2 + l_i^2 theta_i'^2.
 * With the links' inertia Jlink about their pins:
 *   Mq = (M/6) I + G^T diag(Jlink + (M/6) l_i^2) G + (M/2) Jc^T Jc,
 *   hq = sigma + G^T tau + (M/2) Jc^T ac_bias + M g Jc^T e_z,
 *   sigma_i = -(M/6) l_i theta_i'^2,
 *   tau_i   = (Jlink + (M/6) l_i^2) theta_i''_bias + 2 (M/6) l_i l_i'
 *             theta_i' + m g d cos(theta_i) - T_friction,i.
 * A payload, a rigid body of mass mb, centre of mass offset s and world
 * inertia Iw about it, with Jg = Jc - [s]x Jw its centre of mass's map:
 *   Mq += mb Jg^T Jg + Jw^T Iw Jw,
 *   hq += Jg^T mb (a_g,bias + g e_z) + Jw^T (Iw dw_bias + w x Iw w).
 * rps3_invdyn's Lagrange route writes the platform as the same points;
 * its Newton-Euler route (a rigid body and six ball-joint forces) and the
 * kinetic energy of rps3_energy (the disc's inertia tensor) share nothing
 * with this file, and the tests hold it to both.
 */
#include <string.h>

#include "fwddyn.h"
#include "linalg.h"

/* a selected inertia effect with a non-zero mass: without one Mq = 0 */
static int has_mass(const rps3_model *m) {
  const int eff = m->opt.effects;
  return ((eff & RPS3_EFF_PLATFORM_INERTIA) && m->M > 0.0) ||
         ((eff & RPS3_EFF_LINK_INERTIA) && m->Jlink > 0.0) ||
         ((eff & RPS3_EFF_PAYLOAD) && m->payload.mass > 0.0);
}

/* world inertia rot diag(I) rot^T */
static void inertia_world(double Iw[3][3], const double rot[3][3],
                          const double I[3]) {
  int p, q, k;
  for (p = 0; p < 3; p++)
    for (q = 0; q < 3; q++) {
      double s = 0.0;
      for (k = 0; k < 3; k++) s += rot[p][k] * I[k] * rot[q][k];
      Iw[p][q] = s;
    }
}

/* omega from sum_i rho_i x u_i for the ball motions u_i = omega x rho_i
   (rps3_omega_from_balls: (26)-(28) in closed form); wk = 2 / (3 r^2) */
static void omega_of_sum(double omega[3], const double w[3], const double a[3],
                         double wk) {
  double s = 0.5 * wk * v3_dot(a, w);
  int q;
  for (q = 0; q < 3; q++) omega[q] = wk * w[q] - s * a[q];
}

/* C99 does not convert double (*)[2] to const double (*)[2] implicitly */
#define M2C(A) ((const double(*)[2])(A))

/* the larger of a and b (fmax is a call at -O2).  A NaN in a is dropped:
   each use below is followed by a test that a NaN fails (the Newton
   step's sum of |f|, the finite start, det and the inverse's scale) */
static inline double max2(double a, double b) { return a > b ? a : b; }
/* add a rigid body: mass mb, centre of mass offset s from the platform
   centre and inertia Iw about it (world axes); g = 0 leaves its weight out */
static void add_body(const rps3_fd_state *k, const rps3_data *d, double mb,
                     const double s[3], const double Iw[3][3], double g,
                     double Mq[3][3], double hq[3]) {
  double Jg[3][3], ag[3], mom[3], t[3], Iwj[3][3];
  int j, q;
  /* the centre of mass moves with vc + omega x s */
  for (j = 0; j < 3; j++) {
    double wj[3] = {k->Jw[0][j], k->Jw[1][j], k->Jw[2][j]};
    v3_cross(t, wj, s);
    for (q = 0; q < 3; q++) Jg[j][q] = k->Jc[q][j] + t[q];
    m3_mulv(Iwj[j], Iw, wj);
  }
  /* bias: a_g = ac + dw x s + w x (w x s) + g e_z; moment Iw dw + w x Iw w */
  v3_cross(ag, k->dw_b, s);
  v3_axpy(ag, ag, 1.0, k->ac_b);
  v3_cross(t, d->omega, s);
  v3_cross(t, d->omega, t);
  v3_axpy(ag, ag, 1.0, t);
  ag[2] += g;
  m3_mulv(mom, Iw, k->dw_b);
  m3_mulv(t, Iw, d->omega);
  v3_cross(t, d->omega, t);
  v3_axpy(mom, mom, 1.0, t);
  for (j = 0; j < 3; j++) {
    double wj[3] = {k->Jw[0][j], k->Jw[1][j], k->Jw[2][j]};
    for (q = 0; q < 3; q++) {
      double wq[3] = {k->Jw[0][q], k->Jw[1][q], k->Jw[2][q]};
      Mq[j][q] += mb * v3_dot(Jg[j], Jg[q]) + v3_dot(wq, Iwj[j]);
    }
    hq[j] += mb * v3_dot(Jg[j], ag) + v3_dot(wj, mom);
  }
}

/*
 * A state in the links' planes.  Link i moves in the vertical plane of pin
 * i, its ball joint at b_i = h_i u_i + Z_i e_z, h_i = R - l_i cos_i, Z_i =
 * l_i sin_i ((12)-(14)).  The pair k = (i, j), j = i + 1 (mod 3), of
 * (8)-(10) is f_k = |b_i - b_j|^2 - 3 r^2 = h_i^2 + h_j^2 + h_i h_j + (Z_i
 * - Z_j)^2 - 3 r^2 (u_i . u_j = -1/2), so with A = 2 h_i + h_j, B = 2 h_j +
 * h_i, E = 2 (Z_i - Z_j) its derivatives are
 *   df_k/dtheta_i = l_i (A sin_i + E cos_i),  df_k/dtheta_j = l_j (B sin_j
 *   - E cos_j), df_k/dl_i = E sin_i - A cos_i,  df_k/dl_j = -B cos_j - E
 *   sin_j,
 * rps3_constraint_jacobian's entries, two a row: df/dtheta is cyclic
 * bidiagonal, det = a0 a1 a2 + b0 b1 b2, and its inverse is its adjugate
 * over det, nine products.  Everything is formed in this local structure
 * and stored into d and k once: stores through them could alias the
 * inputs as far as the compiler knows.
 */
typedef struct {
  double l[3], dl[3], c[3], s[3]; /* lengths, rates, cos and sin theta */
  double A[3], B[3], E[3];        /* of pair k, above */
  double at[3], bt[3];            /* df_k/dtheta_k, df_k/dtheta_(k+1) */
  double al[3], bl[3];            /* df_k/dl_k, df_k/dl_(k+1) */
  double X[3][3];                 /* (df/dtheta)^-1 */
  double G[3][3];                 /* dtheta'/dl' = -X df/dl */
  double Jc[3][3];                /* dvc/dl' */
  double dth[3], ddb[3];          /* theta', theta'' at l'' = 0 */
  double hd[3], Zd[3];            /* h_i', Z_i' */
  double hdd[3], Zdd[3];          /* h_i'', Z_i'' at l'' = 0 */
  double acb[3];                  /* centre acceleration at l'' = 0 */
} plane;

/* the constraint Jacobians, the mode (sign of det(df/dtheta), grouped as
   rps3_mode_of_jac groups it), (df/dtheta)^-1 and its 1-norm condition
   number (RPS3_ESING past opt.cond_max); column i of df/dtheta holds
   at[i] and bt[i - 1] */
static int plane_jacobian(const rps3_model *m, rps3_data *d, plane *p) {
  double h[3], Z[3], det, id, n1 = 0.0, ni = 0.0, cond;
  int i, q;
  for (i = 0; i < 3; i++) {
    h[i] = m->R - p->l[i] * p->c[i];
    Z[i] = p->l[i] * p->s[i];
  }
  for (q = 0; q < 3; q++) {
    const int j = (q + 1) % 3;
    i = q;
    p->A[q] = 2.0 * h[i] + h[j];
    p->B[q] = 2.0 * h[j] + h[i];
    p->E[q] = 2.0 * (Z[i] - Z[j]);
    p->at[q] = p->l[i] * (p->A[q] * p->s[i] + p->E[q] * p->c[i]);
    p->bt[q] = p->l[j] * (p->B[q] * p->s[j] - p->E[q] * p->c[j]);
    p->al[q] = p->E[q] * p->s[i] - p->A[q] * p->c[i];
    p->bl[q] = -p->B[q] * p->c[j] - p->E[q] * p->s[j];
  }
  det = p->at[0] * (p->at[1] * p->at[2]) + p->bt[0] * (p->bt[1] * p->bt[2]);
  d->mode = (det > 0.0) - (det < 0.0);
  if (!(fabs(det) > 0.0) || !(fabs(det) < HUGE_VAL))
    RPS3_ERROR(d, RPS3_ESING, "constraint Jacobian df/dtheta is singular");
  id = 1.0 / det;
  p->X[0][0] = p->at[1] * p->at[2] * id;
  p->X[0][1] = -p->bt[0] * p->at[2] * id;
  p->X[0][2] = p->bt[0] * p->bt[1] * id;
  p->X[1][0] = p->bt[1] * p->bt[2] * id;
  p->X[1][1] = p->at[0] * p->at[2] * id;
  p->X[1][2] = -p->at[0] * p->bt[1] * id;
  p->X[2][0] = -p->at[1] * p->bt[2] * id;
  p->X[2][1] = p->bt[0] * p->bt[2] * id;
  p->X[2][2] = p->at[0] * p->at[1] * id;
  for (i = 0; i < 3; i++) {
    n1 = max2(n1, fabs(p->at[i]) + fabs(p->bt[(i + 2) % 3]));
    ni = max2(ni, fabs(p->X[0][i]) + fabs(p->X[1][i]) + fabs(p->X[2][i]));
  }
  cond = n1 * ni;
  if (!(cond <= m->opt.cond_max))
    RPS3_ERROR(d, RPS3_ESING,
               "constraint Jacobian df/dtheta: condition number %.3g exceeds "
               "cond_max %.3g", cond, m->opt.cond_max);
  return RPS3_OK;
}

/* G = -X df/dl (column j of df/dl holds al[j] and bl[j - 1]); the rates
   theta' = G l' and the balls' in-plane rates (28); the bias theta''
   from the second derivative of (8)-(10), (df/dtheta) theta'' = x with
   x_k = -(2 |b_i' - b_j'|^2 + A h_i''0 + B h_j''0 + E (Z_i''0 - Z_j''0))
   (rps3_constraint_acc_rhs in the links' planes; ''0: without theta''),
   and the balls' and the centre's accelerations at l'' = 0; Jc, column j
   the centre's velocity (25) for l_j' = 1 */
static void plane_rates(plane *p, const double u[3][2]) {
  const double third = 1.0 / 3.0; /* a product: divisions are slow */
  double x[3];
  int i, j, q;
  for (j = 0; j < 3; j++) {
    const int k = (j + 2) % 3;
    for (i = 0; i < 3; i++)
      p->G[i][j] = -(p->X[i][j] * p->al[j] + p->X[i][k] * p->bl[k]);
  }
  for (i = 0; i < 3; i++) {
    const double th = p->G[i][0] * p->dl[0] + p->G[i][1] * p->dl[1] +
                      p->G[i][2] * p->dl[2];
    const double lth = p->l[i] * th, v = 2.0 * p->dl[i] * th;
    p->dth[i] = th;
    p->hd[i] = p->s[i] * lth - p->c[i] * p->dl[i];
    p->Zd[i] = p->s[i] * p->dl[i] + p->c[i] * lth;
    p->hdd[i] = p->s[i] * v + p->c[i] * lth * th;
    p->Zdd[i] = p->c[i] * v - p->s[i] * lth * th;
  }
  for (q = 0; q < 3; q++) {
    const int j2 = (q + 1) % 3;
    const double dz = p->Zd[q] - p->Zd[j2];
    x[q] = -(2.0 * (p->hd[q] * p->hd[q] + p->hd[j2] * p->hd[j2] +
                    p->hd[q] * p->hd[j2] + dz * dz) +
             p->A[q] * p->hdd[q] + p->B[q] * p->hdd[j2] +
             p->E[q] * (p->Zdd[q] - p->Zdd[j2]));
  }
  for (i = 0; i < 3; i++) {
    p->ddb[i] = p->X[i][0] * x[0] + p->X[i][1] * x[1] + p->X[i][2] * x[2];
    p->hdd[i] += p->l[i] * p->s[i] * p->ddb[i];
    p->Zdd[i] += p->l[i] * p->c[i] * p->ddb[i];
  }
  for (q = 0; q < 2; q++)
    p->acb[q] = (p->hdd[0] * u[0][q] + p->hdd[1] * u[1][q] +
                 p->hdd[2] * u[2][q]) * third;
  p->acb[2] = (p->Zdd[0] + p->Zdd[1] + p->Zdd[2]) * third;
  for (j = 0; j < 3; j++) {
    /* dh_i/dl_j' = l_i sin_i G_ij - cos_j [i = j], dZ_i/dl_j' = l_i cos_i
       G_ij + sin_j [i = j] */
    double sh0 = -p->c[j] * u[j][0], sh1 = -p->c[j] * u[j][1], sz = p->s[j];
    for (i = 0; i < 3; i++) {
      const double gh = p->l[i] * p->s[i] * p->G[i][j];
      sh0 += gh * u[i][0];
      sh1 += gh * u[i][1];
      sz += p->l[i] * p->c[i] * p->G[i][j];
    }
    p->Jc[0][j] = sh0 * third;
    p->Jc[1][j] = sh1 * third;
    p->Jc[2][j] = sz * third;
  }
}

/* the platform's motion from its ball joints, (25)-(28): vc, omega from
   sum_i rho_i x b_i' (rho_i = b_i - c, with rho_i x u_i and rho_i x e_z
   formed once), and, with `bias`, the angular bias acceleration from sum_i
   rho_i x (b_i'' - omega x (omega x rho_i)); Jw, column j omega for l_j'
   = 1, into k */
static void platform_motion(const rps3_model *m, const rps3_data *d,
                            const plane *p, const double u[3][2], int bias,
                            rps3_fd_state *k, double vc[3], double om[3]) {
  const double wk = 2.0 / (3.0 * m->r * m->r), third = 1.0 / 3.0;
  double P[3][3], Q[3][3], rho[3][3], a[3], w[3];
  int i, j, q;
  for (i = 0; i < 3; i++) {
    a[i] = d->rot[i][2];
    for (q = 0; q < 3; q++) rho[i][q] = d->b[i][q] - d->c[q];
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
          p->l[i] * p->s[i] * p->G[i][j] - (i == j ? p->c[i] : 0.0);
      const double gz =
          p->l[i] * p->c[i] * p->G[i][j] + (i == j ? p->s[i] : 0.0);
      for (q = 0; q < 3; q++) wj[q] += gh * P[i][q] + gz * Q[i][q];
    }
    omega_of_sum(oj, wj, a, wk);
    for (q = 0; q < 3; q++) k->Jw[q][j] = oj[q];
  }
  for (q = 0; q < 2; q++)
    vc[q] = (p->hd[0] * u[0][q] + p->hd[1] * u[1][q] + p->hd[2] * u[2][q]) *
            third;
  vc[2] = (p->Zd[0] + p->Zd[1] + p->Zd[2]) * third;
  w[0] = w[1] = w[2] = 0.0;
  for (i = 0; i < 3; i++)
    for (q = 0; q < 3; q++) w[q] += p->hd[i] * P[i][q] + p->Zd[i] * Q[i][q];
  omega_of_sum(om, w, a, wk);
  if (!bias) return;
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
   dF/d(f, n) by virtual power, rps3_invdyn's transmission()) */
static int invdyn_limits(const rps3_model *m, rps3_data *d, const plane *p,
                         const rps3_fd_state *k) {
  double nr = 0.0, nx = 0.0, T = 0.0;
  int q;
  for (q = 0; q < 3; q++) {
    const double sj =
        fabs(p->Jc[0][q]) + fabs(p->Jc[1][q]) + fabs(p->Jc[2][q]) +
        m->R * (fabs(k->Jw[0][q]) + fabs(k->Jw[1][q]) + fabs(k->Jw[2][q]));
    nr = max2(nr, fabs(p->at[q]) + fabs(p->bt[q]));
    nx = max2(nx, fabs(p->X[q][0]) + fabs(p->X[q][1]) + fabs(p->X[q][2]));
    if (sj > T || !isfinite(sj)) T = sj;
  }
  d->cond = nr * nx;
  d->transmission = T;
  if (!(d->cond <= m->opt.cond_max))
    RPS3_ERROR(d, RPS3_ESING,
               "lambda system condition number %.3g exceeds cond_max %.3g",
               d->cond, m->opt.cond_max);
  if (d->cond > m->opt.cond_warn) d->warn |= RPS3_WARN_ILLCOND;
  if (!(T >= 0.0 && T <= m->opt.trans_max))
    RPS3_ERROR(d, RPS3_ESING,
               "force transmission %.3g exceeds trans_max %.3g: an actuator "
               "would carry that many times the load on the platform",
               T, m->opt.trans_max);
  if (T > m->opt.trans_warn) d->warn |= RPS3_WARN_TRANS;
  return RPS3_OK;
}

/* Mq and hq of the selected effects (the file's header): the links and
   the platform's ball-joint masses as generalized loads on theta (tau)
   and on l (sigma), the centre's mass through Jc, a payload as a rigid
   body; the upper triangle is Mq, symmetric to the bit */
static void assemble(const rps3_model *m, rps3_data *d,
                     const rps3_fd_state *k, const plane *p) {
  const int eff = m->opt.effects;
  const double mb = (eff & RPS3_EFF_PLATFORM_INERTIA) ? m->M / 6.0 : 0.0;
  const double mc = 3.0 * mb; /* M / 2 at the centre */
  const double gz = (eff & RPS3_EFF_PLATFORM_GRAVITY) ? m->M * m->g : 0.0;
  double Jp[3], tau[3], sig[3], Mq[3][3], hq[3];
  int i, j, q;
  for (i = 0; i < 3; i++) {
    const double mbl = mb * p->l[i];
    Jp[i] = mbl * p->l[i];
    tau[i] = 2.0 * mbl * p->dl[i] * p->dth[i];
    sig[i] = -mbl * p->dth[i] * p->dth[i];
    if (eff & RPS3_EFF_LINK_INERTIA) Jp[i] += m->Jlink;
    tau[i] += Jp[i] * p->ddb[i];
    /* (22): d/dtheta of m g d sin(theta) */
    if (eff & RPS3_EFF_LINK_GRAVITY) tau[i] += m->m * m->g * m->d * p->c[i];
    if (eff & RPS3_EFF_PIN_FRICTION)
      tau[i] -= rps3_friction_torque(m, p->dth[i]);
  }
  for (j = 0; j < 3; j++) {
    for (q = j; q < 3; q++)
      Mq[j][q] = (q == j ? mb : 0.0) + Jp[0] * p->G[0][j] * p->G[0][q] +
                 Jp[1] * p->G[1][j] * p->G[1][q] +
                 Jp[2] * p->G[2][j] * p->G[2][q] +
                 mc * (p->Jc[0][j] * p->Jc[0][q] + p->Jc[1][j] * p->Jc[1][q] +
                       p->Jc[2][j] * p->Jc[2][q]);
    hq[j] = sig[j] + p->G[0][j] * tau[0] + p->G[1][j] * tau[1] +
            p->G[2][j] * tau[2] +
            mc * (p->Jc[0][j] * p->acb[0] + p->Jc[1][j] * p->acb[1] +
                  p->Jc[2][j] * p->acb[2]) +
            gz * p->Jc[2][j];
  }
  if (eff & RPS3_EFF_PAYLOAD) {
    double sp[3], Iw[3][3];
    for (j = 0; j < 3; j++)
      for (q = 0; q < j; q++) Mq[j][q] = Mq[q][j];
    m3_mulv(sp, M3C(d->rot), m->payload.com);
    inertia_world(Iw, M3C(d->rot), m->payload.inertia);
    add_body(k, d, m->payload.mass, sp, M3C(Iw), m->g, Mq, hq);
  }
  for (j = 0; j < 3; j++) {
    for (q = 0; q < 3; q++) d->Mq[j][q] = (q >= j) ? Mq[j][q] : Mq[q][j];
    d->hq[j] = hq[j];
  }
}

/*
 * Rates, maps, Mq and hq at the positions d holds (d->l; theta's cosines
 * and sines cth, sth) and the rates d->dl, for the selected effects.  The
 * platform's motion (vc, omega, Jw and the angular bias acceleration),
 * which only the full report and a payload read, is left out of a lean
 * state (NaN); RPS3_FD_NOFACTOR adds Jw and what rps3_invdyn reports of
 * the configuration, its checks included.
 */
static int state_eval(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags, const double cth[3], const double sth[3]) {
  const int invdyn = (flags & RPS3_FD_NOFACTOR) != 0;
  const int with_w =
      !(flags & RPS3_FD_LEAN) || (m->opt.effects & RPS3_EFF_PAYLOAD);
  plane p;
  double u[3][2], vc[3], om[3], chk = 0.0;
  int i, q, st;
  for (i = 0; i < 3; i++) {
    p.l[i] = d->l[i];
    p.dl[i] = d->dl[i];
    p.c[i] = cth[i];
    p.s[i] = sth[i];
    u[i][0] = m->radial[i][0];
    u[i][1] = m->radial[i][1];
  }
  st = plane_jacobian(m, d, &p);
  if (st != RPS3_OK) return st;
  plane_rates(&p, M2C(u));
  k->have_w = with_w;
  if (with_w || invdyn) {
    platform_motion(m, d, &p, M2C(u), with_w, k, vc, om);
  }
  if (!with_w)
    for (q = 0; q < 3; q++) vc[q] = om[q] = (double)NAN; /* as positions */
  for (q = 0; q < 3; q++) {
    chk += fabs(p.dth[q]) + fabs(p.ddb[q]) + fabs(p.acb[q]);
    if (with_w) chk += fabs(vc[q]) + fabs(om[q]) + fabs(k->dw_b[q]);
    d->dtheta[q] = p.dth[q];
    d->vc[q] = vc[q];
    d->omega[q] = om[q];
    k->ddth_b[q] = p.ddb[q];
    k->ac_b[q] = p.acb[q];
  }
  memcpy(k->G, p.G, sizeof(p.G));
  memcpy(k->Jc, p.Jc, sizeof(p.Jc));
  /* one test of the rates and the bias; the named checks when it fails */
  if (!(chk <= DBL_MAX)) {
    RPS3_CHECK_FINITE(d, d->dtheta, 3, "dtheta");
    if (with_w) {
      RPS3_CHECK_FINITE(d, d->vc, 3, "vc");
      RPS3_CHECK_FINITE(d, d->omega, 3, "omega");
    }
    RPS3_CHECK_FINITE(d, k->ddth_b, 3, "ddtheta");
    RPS3_CHECK_FINITE(d, k->ac_b, 3, "ac");
    if (with_w) RPS3_CHECK_FINITE(d, k->dw_b, 3, "domega");
  }
  if (invdyn) {
    st = invdyn_limits(m, d, &p, k);
    if (st != RPS3_OK) return st;
  }
  assemble(m, d, k, &p);
  return RPS3_OK;
}

/*
 * Mq^-1 and the 1-norm condition number of Mq, when Mq is positive definite
 * (Sylvester: its leading minors M00, M00 M11 - M01^2 and det are > 0;
 * returns -1 otherwise).  The inverse is the adjugate over the
 * determinant, symmetric to the bit: one division, where a Cholesky factor
 * chains three square roots and three divisions on the evaluation's
 * critical path.  The accelerations are Mq^-1 (F - hq): one product per
 * force.
 */
static int mass_inverse(const double A[3][3], double Ai[3][3], double *cond) {
  const double c00 = A[1][1] * A[2][2] - A[1][2] * A[1][2];
  const double c01 = A[0][2] * A[1][2] - A[0][1] * A[2][2];
  const double c02 = A[0][1] * A[1][2] - A[0][2] * A[1][1];
  const double c11 = A[0][0] * A[2][2] - A[0][2] * A[0][2];
  const double c12 = A[0][1] * A[0][2] - A[0][0] * A[1][2];
  const double c22 = A[0][0] * A[1][1] - A[0][1] * A[0][1];
  const double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
  double id, anorm = 0.0, inorm = 0.0;
  int i, j;
  if (!(A[0][0] > 0.0 && c22 > 0.0 && det > 0.0 && det < HUGE_VAL))
    return -1;
  id = 1.0 / det;
  if (!(id < HUGE_VAL)) return -1; /* a subnormal det: no inverse */
  Ai[0][0] = c00 * id;
  Ai[0][1] = Ai[1][0] = c01 * id;
  Ai[0][2] = Ai[2][0] = c02 * id;
  Ai[1][1] = c11 * id;
  Ai[1][2] = Ai[2][1] = c12 * id;
  Ai[2][2] = c22 * id;
  for (j = 0; j < 3; j++) {
    double sa = 0.0, si = 0.0;
    for (i = 0; i < 3; i++) {
      sa += fabs(A[i][j]);
      si += fabs(Ai[i][j]);
    }
    anorm = max2(anorm, sa);
    inorm = max2(inorm, si);
  }
  *cond = anorm * inorm;
  return 0;
}

static double mass_cond(const double Mq[3][3]) {
  double A[9], LU[9];
  int perm[3], i, j;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) A[3 * i + j] = LU[3 * i + j] = Mq[i][j];
  if (rps3_lu_factor(3, LU, perm) != 0) return HUGE_VAL;
  return rps3_lu_cond1(3, A, LU, perm);
}


/*
 * Positions from l by Newton's method on (8)-(10) from the warm start: in a
 * simulation the previous evaluation's theta is within a step of the
 * answer, and one Newton step converges where GSL's hybridsj costs its
 * set-up on every call.  The same convergence test as rps3_theta_solve
 * (max |f_k| / R^2 <= opt.tol), f_k in units of R as state_eval writes it.
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
#define PREDICT_MAX RPS3_FD_PREDICT_MAX
/* evaluations whose start trigonometry trig_step moves before one takes
   sincos again: the phase's rounding, an ulp a step at most, stays below
   1e-13 rad (the solve's tolerance is 1e-12); the plant's full state at
   the end of every control period takes sincos anyway */
#define TRIG_RESYNC 256
/* largest Newton correction [rad] that moves cos and sin by trig_step's
   series (exact to the rounding up to PREDICT_MAX); a larger one, far
   from any root a warm start gives, takes sincos */
#define TAYLOR_MAX PREDICT_MAX

/* c, sn of theta - e for |e| <= PREDICT_MAX: the series of cos e to e^6 /
   720 and of sin e to e^7 / 5040 (the next terms, e^8 / 40320 and e^9 /
   362880, are below 2.5e-21), or, for |e| <= 1e-5 (a Newton correction,
   or a predicted step of a slow motion), to e^2 / 2 and e^3 / 6 (the
   next, e^4 / 24 and e^5 / 120, below 4.2e-22); then back onto the unit
   circle to first order, (3 - |.|^2) / 2, so that the rounding of many
   steps does not build up in the magnitude (rps3_fwddyn_state bounds the
   steps between two sincos: TRIG_RESYNC) */
static void trig_step(double c[3], double sn[3], const double e[3]) {
  const int small = max2(max2(fabs(e[0]), fabs(e[1])), fabs(e[2])) <= 1e-5;
  int i;
  for (i = 0; i < 3; i++) {
    const double x = e[i], x2 = x * x;
    double ce, se, cn, snn, g;
    if (small) {
      ce = 1.0 - 0.5 * x2;
      se = x - x * x2 * (1.0 / 6.0);
    } else {
      ce = 1.0 - x2 * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0)));
      se = x * (1.0 - x2 * (1.0 / 6.0 -
                            x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0))));
    }
    cn = c[i] * ce + sn[i] * se;
    snn = sn[i] * ce - c[i] * se;
    g = 1.5 - 0.5 * (cn * cn + snn * snn);
    c[i] = cn * g;
    sn[i] = snn * g;
  }
}

/* a lean stage's positions: none (NaN), so that no earlier state's can be
   read as this one's */
static void positions_unset(rps3_data *d) {
  const double nan = (double)NAN;
  int i, q;
  for (i = 0; i < 3; i++) {
    d->c[i] = nan;
    for (q = 0; q < 3; q++)
      d->b[i][q] = d->phi[i][q] = d->dphi[i][q] = d->rot[i][q] = nan;
  }
}

static int theta_newton(const rps3_model *m, rps3_data *d, double c[3],
                        double sn[3], int have_trig, int positions,
                        int pose) {
  const double q3 = 3.0 * m->rho * m->rho; /* 3 r^2 / R^2 */
  const double iR = 1.0 / m->R;
  double L[3], th[3], resid;
  int it, i, fold = 0;
  if (!(m->opt.warm_start && d->have_theta && v3_finite(d->theta)) ||
      !v3_finite(d->l) || !(d->l[0] > 0 && d->l[1] > 0 && d->l[2] > 0))
    return -1;
  for (i = 0; i < 3; i++) {
    L[i] = d->l[i] * iR;
    th[i] = d->theta[i];
  }
  if (!have_trig)
    for (i = 0; i < 3; i++) {
      const double t = th[i]; /* one sincos */
      c[i] = cos(t);
      sn[i] = sin(t);
    }
  for (it = 0;; it++) {
    double H[3], Y[3], f[3], a[3], b[3], x[3], det, id, big;
    int k;
    for (i = 0; i < 3; i++) {
      H[i] = 1.0 - L[i] * c[i];
      Y[i] = L[i] * sn[i];
    }
    for (k = 0; k < 3; k++) {
      const int j = (k + 1) % 3;
      const double E = 2.0 * (Y[k] - Y[j]);
      f[k] = H[k] * H[k] + H[j] * H[j] + H[k] * H[j] + 0.25 * E * E - q3;
      a[k] = L[k] * ((2.0 * H[k] + H[j]) * sn[k] + E * c[k]);
      b[k] = L[j] * ((2.0 * H[j] + H[k]) * sn[j] - E * c[j]);
    }
    resid = max2(max2(fabs(f[0]), fabs(f[1])), fabs(f[2]));
    if (!(fabs(f[0]) + fabs(f[1]) + fabs(f[2]) < HUGE_VAL)) return -1;
    if (resid <= m->opt.tol) break;
    if (it == NEWTON_MAX) return -1;
    /* J x = f, J[k][k] = a_k, J[k][k+1] = b_k: the adjugate (state_eval) */
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
      trig_step(c, sn, x); /* cos and sin of theta - x */
    } else {
      for (i = 0; i < 3; i++) {
        const double t = th[i];
        c[i] = cos(t);
        sn[i] = sin(t);
      }
    }
  }
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
  if (positions || fold) {
    rps3_links_from_trig(m, d, c, sn);
    rps3_frame_from_balls(m, d);
    if (d->rot[0][0] + d->rot[1][1] < 0.0) return -1; /* spun platform */
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
    positions_unset(d);
  }
  if (pose)
    rps3_pose_from_frame(d);
  else
    d->pose[0] = d->pose[1] = d->pose[2] = (double)NAN;
  return 0;
}

/* a failure leaves no acceleration that could be read as one */
static void poison(rps3_data *d) {
  d->ddl[0] = d->ddl[1] = d->ddl[2] = (double)NAN;
  d->stage &= RPS3_STAGE_POS | RPS3_STAGE_VEL;
}

int rps3_fwddyn_state(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags) {
  const int lean = (flags & RPS3_FD_LEAN) != 0;
  const int payload = (m->opt.effects & RPS3_EFF_PAYLOAD) != 0;
  /* the positions (ball joints, link directions, frame): not in a lean
     stage, which reads theta alone, unless a payload or the inverse
     dynamics' checks need them */
  const int positions = !lean || payload || (flags & RPS3_FD_NOFACTOR);
  double dl[3], c[3], sn[3];
  int status, pd, trig = 0;
  if (!v3_finite(d->dl)) {
    poison(d);
    RPS3_ERROR(d, RPS3_EINVAL, "dl (%g, %g, %g) m/s is not finite", d->dl[0],
               d->dl[1], d->dl[2]);
  }
  if (!(flags & RPS3_FD_NOFACTOR) && !has_mass(m)) {
    poison(d);
    RPS3_ERROR(d, RPS3_EINVAL,
               "forward dynamics needs inertia: select platform_inertia, "
               "link_inertia or payload, with a non-zero mass");
  }
  /* the rates survive the stages, which reset what they write */
  v3_copy(dl, d->dl);

  /* positions: theta from l, warm-started on the tracked assembly mode;
     Newton from the warm start, else the full solve (which reports) */
  {
    double th0[3];
    v3_copy(th0, d->theta);
    d->stage = 0;
    d->warn = 0;
    /* the start moved along the last state's tangent, theta + G (l -
       l_last): within O(|l - l_last|^2) of the root, one Newton step
       instead of two.  A step of more than PREDICT_MAX (near a singular
       configuration, where G grows) is not taken: the start stays where
       the last root was, as does the fall-back */
    if ((flags & RPS3_FD_PREDICT) && m->opt.warm_start && d->have_theta) {
      double dlen[3], dth[3];
      v3_sub(dlen, d->l, k->l);
      m3_mulv(dth, M3C(k->G), dlen);
      if (max2(max2(fabs(dth[0]), fabs(dth[1])), fabs(dth[2])) <= PREDICT_MAX)
        v3_axpy(d->theta, d->theta, 1.0, dth);
    }
    /* a lean state started near the last root moves that root's cosines
       and sines by the change of theta (exact: the two are within a
       factor of two); a full state, and every TRIG_RESYNC-th lean one,
       takes sincos, so that the series' rounding never builds up */
    if ((flags & RPS3_FD_TRIG) && lean && k->have_trig && d->have_theta &&
        k->nrot < TRIG_RESYNC) {
      double e[3];
      v3_sub(e, k->th, d->theta);
      if (max2(max2(fabs(e[0]), fabs(e[1])), fabs(e[2])) <= PREDICT_MAX) {
        v3_copy(c, k->c);
        v3_copy(sn, k->s);
        trig_step(c, sn, e);
        trig = 1;
      }
    }
    k->have_trig = 0;
    if (theta_newton(m, d, c, sn, trig, positions, !lean) == 0) {
      d->have_theta = 1;
      d->stage = positions ? RPS3_STAGE_POS : 0;
    } else {
      int i;
      v3_copy(d->theta, th0);
      status = rps3_fk(m, d);
      if (status != RPS3_OK) {
        poison(d);
        return status;
      }
      for (i = 0; i < 3; i++) {
        c[i] = d->dphi[i][2]; /* cos theta_i (29) */
        sn[i] = d->phi[i][2]; /* sin theta_i */
      }
      trig = 0;
    }
  }
  v3_copy(k->l, d->l);
  v3_copy(k->th, d->theta);
  v3_copy(k->c, c);
  v3_copy(k->s, sn);
  k->have_trig = 1;
  k->nrot = trig ? k->nrot + 1 : 0;
  v3_copy(d->dl, dl);
  /* rates, the accelerations at l'' = 0 (the bias), the maps, Mq, hq */
  status = state_eval(m, d, k, flags, c, sn);
  if (status != RPS3_OK) {
    poison(d);
    return status;
  }
  /* a root in another assembly mode than opt.mode asks for is refused, as
     rps3_theta_solve refuses it (the fall-back rps3_fk did already) */
  if (m->opt.mode != RPS3_MODE_ANY && d->mode != m->opt.mode) {
    d->have_theta = 0;
    k->have_trig = 0;
    poison(d);
    RPS3_ERROR(d, RPS3_EMODE,
               "root theta = (%.6g, %.6g, %.6g) is in assembly mode %d "
               "(sign of det df/dtheta; +1 the level platform's), opt.mode "
               "asks for %d", d->theta[0], d->theta[1], d->theta[2], d->mode,
               m->opt.mode);
  }
  if (lean) {
    d->dpose[0] = d->dpose[1] = d->dpose[2] = (double)NAN;
  } else {
    rps3_pose_rates(d);
    RPS3_CHECK_FINITE(d, d->dpose, 3, "dpose");
  }
  /* the stage bits say what is there: a lean stage has theta and its
     rates, not the positions nor the platform's motion */
  if (k->have_w) d->stage |= RPS3_STAGE_VEL;
  poison(d); /* no acceleration before rps3_fwddyn_accel */
  if (flags & RPS3_FD_NOFACTOR) {
    RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
    RPS3_CHECK_FINITE(d, d->Mq, 9, "Mq");
    k->mode = d->mode;
    return RPS3_OK;
  }

  /* Mq symmetric positive definite and conditioned: its inverse, and the
     condition number from it (by LU when it is not positive definite) */
  pd = (mass_inverse(M3C(d->Mq), k->Minv, &d->Mcond) == 0);
  if (!pd) d->Mcond = mass_cond(M3C(d->Mq));
  if (!pd || !(d->Mcond <= m->opt.cond_max))
    RPS3_ERROR(d, RPS3_ESING,
               "mass matrix not positive definite or condition number %.3g "
               "above cond_max %.3g", d->Mcond, m->opt.cond_max);
  RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
  RPS3_CHECK_FINITE(d, d->Mq, 9, "Mq");
  k->mode = d->mode;
  return RPS3_OK;
}

int rps3_fwddyn_accel(const rps3_model *m, rps3_data *d,
                      const rps3_fd_state *k) {
  double x[3], chk = 0.0;
  int i;
  (void)m;
  if (!v3_finite(d->F)) {
    poison(d);
    RPS3_ERROR(d, RPS3_EINVAL, "F (%g, %g, %g) N is not finite", d->F[0],
               d->F[1], d->F[2]);
  }
  /* Mq l'' = F - hq */
  v3_sub(x, d->F, d->hq);
  m3_mulv(x, M3C(k->Minv), x);
  if (!v3_finite(x)) {
    poison(d);
    RPS3_ERROR(d, RPS3_ESING, "acceleration is not finite");
  }
  v3_copy(d->ddl, x);
  /* every acceleration is its map applied to l'' plus its bias; the
     angular one where the state formed its map */
  for (i = 0; i < 3; i++) {
    d->ddtheta[i] = k->ddth_b[i] + v3_dot(k->G[i], x);
    d->ac[i] = k->ac_b[i] + v3_dot(k->Jc[i], x);
    d->domega[i] = k->have_w ? k->dw_b[i] + v3_dot(k->Jw[i], x) : (double)NAN;
    chk += fabs(d->ddtheta[i]) + fabs(d->ac[i]);
    if (k->have_w) chk += fabs(d->domega[i]);
  }
  if (!(chk <= DBL_MAX)) {
    RPS3_CHECK_FINITE(d, d->ddtheta, 3, "ddtheta");
    RPS3_CHECK_FINITE(d, d->ac, 3, "ac");
    if (k->have_w) RPS3_CHECK_FINITE(d, d->domega, 3, "domega");
  }
  if (k->have_w) d->stage |= RPS3_STAGE_ACC;
  return RPS3_OK;
}

int rps3_fwddyn(const rps3_model *m, rps3_data *d) {
  rps3_fd_state k;
  double F[3];
  int status;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!v3_finite(d->dl) || !v3_finite(d->F)) {
    poison(d);
    RPS3_ERROR(d, RPS3_EINVAL,
               "dl (%g, %g, %g) m/s or F (%g, %g, %g) N is not finite",
               d->dl[0], d->dl[1], d->dl[2], d->F[0], d->F[1], d->F[2]);
  }
  /* the force survives the stages, which reset what they write */
  v3_copy(F, d->F);
  status = rps3_fwddyn_state(m, d, &k, 0);
  v3_copy(d->F, F);
  if (status != RPS3_OK) return status;
  return rps3_fwddyn_accel(m, d, &k);
}

int rps3_energy(const rps3_model *m, const rps3_data *d, double *T,
                double *P, double *fric) {
  const int eff = (m != NULL) ? m->opt.effects : 0;
  double t = 0.0, p = 0.0, f = 0.0, Iw[3][3], w[3], s[3], v[3];
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if ((d->stage & (RPS3_STAGE_POS | RPS3_STAGE_VEL)) !=
      (RPS3_STAGE_POS | RPS3_STAGE_VEL))
    return RPS3_ESTATE;
  if (eff & RPS3_EFF_PLATFORM_INERTIA) {
    inertia_world(Iw, M3C(d->rot), m->Ip);
    m3_mulv(w, M3C(Iw), d->omega);
    t += 0.5 * m->M * v3_dot(d->vc, d->vc) + 0.5 * v3_dot(d->omega, w);
  }
  if (eff & RPS3_EFF_PLATFORM_GRAVITY) p += m->M * m->g * d->c[2];
  if (eff & RPS3_EFF_PAYLOAD) {
    m3_mulv(s, M3C(d->rot), m->payload.com);
    v3_cross(v, d->omega, s);
    v3_axpy(v, v, 1.0, d->vc);
    inertia_world(Iw, M3C(d->rot), m->payload.inertia);
    m3_mulv(w, M3C(Iw), d->omega);
    t += 0.5 * m->payload.mass * v3_dot(v, v) + 0.5 * v3_dot(d->omega, w);
    p += m->payload.mass * m->g * (d->c[2] + s[2]);
  }
  for (i = 0; i < 3; i++) {
    if (eff & RPS3_EFF_LINK_INERTIA)
      t += 0.5 * m->Jlink * d->dtheta[i] * d->dtheta[i];
    /* sin theta_i is phi_i's Z component (29) */
    if (eff & RPS3_EFF_LINK_GRAVITY) p += m->m * m->g * m->d * d->phi[i][2];
    if (eff & RPS3_EFF_PIN_FRICTION)
      f += rps3_friction_torque(m, d->dtheta[i]) * d->dtheta[i];
  }
  if (T != NULL) *T = t;
  if (P != NULL) *P = p;
  if (fric != NULL) *fric = f;
  /* d is read-only here: the status alone says an energy overflowed */
  if (!(isfinite(t) && isfinite(p) && isfinite(f))) return RPS3_ERANGE;
  return RPS3_OK;
}
