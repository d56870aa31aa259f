/*
 * fwddyn.c - forward dynamics in the link lengths l, the paper's independent
 * coordinates: Mq(l) l'' + hq(l, l') = F, and the energy of a state.
 *
 * Mq and hq are assembled by virtual power (Kane's method), not from the
 * Lagrange multipliers of rps3_invdyn.  Every velocity of the mechanism is
 * linear in l':
 *   theta' = G l',  G = -(df/dtheta)^-1 (df/dl)        (from (8)-(10))
 *   b_i'   = l_i' phi_i + l_i theta_i' dphi_i          ((12)-(14), (28))
 *   vc     = Jc l' = (b_1' + b_2' + b_3') / 3          ((11), (25))
 *   omega  = Jw l'  from the ball joints               ((26)-(28))
 * and every acceleration is that map applied to l'' plus its value at
 * l'' = 0 (the velocity-product "bias", rps3_joint_acceleration with ddl =
 * 0).  A rigid body of mass mb, centre of mass offset s and world inertia
 * Iw about it contributes, with Jg = Jc - [s]x Jw its centre of mass's map,
 *   Mq += mb Jg^T Jg + Jw^T Iw Jw,
 *   hq += Jg^T mb (a_g,bias + g e_z) + Jw^T (Iw dw_bias + w x Iw w);
 * a link (pinned, swinging about its pin axis) contributes
 *   Mq += Jlink G^T G,  hq += G^T (Jlink theta''_bias + m g d cos theta
 *   - T_friction).
 * The platform is the uniform disc of (21) as a rigid body (not the point
 * masses rps3_invdyn's Lagrange route uses), so the two routes share no
 * inertia formula.
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

/*
 * Rates and the maps from one inverse of df/dtheta: the mode (sign of its
 * determinant), its condition (rps3_jt_factor's test and messages), then
 *   G = -(df/dtheta)^-1 (df/dl)
 *   Jc e_j = (phi_j + sum_i l_i G_ij dphi_i) / 3            (25), (28)
 *   Jw e_j = W (rho_j x phi_j + sum_i l_i G_ij rho_i x dphi_i)  (26)-(28)
 * where W inverts sum_i rho_i x u_i for the balls (rps3_omega_from_balls;
 * the centre's own motion drops out, sum_i rho_i = 0 by (11)).  The
 * velocities are the maps applied to l' (theta' = G l', vc = Jc l', omega
 * = Jw l'), and the accelerations at l'' = 0 (the bias) come from the
 * second derivative of (8)-(10), D.D'' + |D'|^2 = 0 with D = b_i - b_j,
 * solved with the same inverse.  The stage functions would factor
 * df/dtheta once per rate and apply W five times.
 */
static int rates_and_maps(const rps3_model *m, rps3_data *d,
                          rps3_fd_state *k, int dpose) {
  const double wk = 2.0 / (3.0 * m->r * m->r);
  double Jl[3][3], Jt[3][3], A[9], LU[9], X[9], cond, rho[3][3], P[3][3],
      Q[3][3], a[3], kn[3][3], x[3], w[3];
  int perm[3], i, j, q;
  rps3_constraint_jacobian(d, Jl, Jt);
  d->mode = rps3_mode_of_jac(M3C(Jt));
  for (i = 0; i < 3; i++)
    for (q = 0; q < 3; q++) A[3 * i + q] = LU[3 * i + q] = Jt[i][q];
  if (rps3_lu_factor(3, LU, perm) != 0)
    RPS3_ERROR(d, RPS3_ESING, "constraint Jacobian df/dtheta is singular");
  cond = rps3_lu3_inverse_cond1(A, LU, perm, X);
  if (!(cond <= m->opt.cond_max))
    RPS3_ERROR(d, RPS3_ESING,
               "constraint Jacobian df/dtheta: condition number %.3g exceeds "
               "cond_max %.3g", cond, m->opt.cond_max);
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++)
      k->G[i][j] = -(X[3 * i] * Jl[0][j] + X[3 * i + 1] * Jl[1][j] +
                     X[3 * i + 2] * Jl[2][j]);

  /* the maps, column j the motion for l' = e_j */
  for (i = 0; i < 3; i++) {
    v3_sub(rho[i], d->b[i], d->c);
    v3_cross(P[i], rho[i], d->phi[i]);
    v3_cross(Q[i], rho[i], d->dphi[i]);
    a[i] = d->rot[i][2];
  }
  for (j = 0; j < 3; j++) {
    double vc[3], om[3];
    v3_copy(vc, d->phi[j]);
    v3_copy(w, P[j]);
    for (i = 0; i < 3; i++) {
      double s = d->l[i] * k->G[i][j];
      v3_axpy(vc, vc, s, d->dphi[i]);
      v3_axpy(w, w, s, Q[i]);
    }
    omega_of_sum(om, w, a, wk);
    for (q = 0; q < 3; q++) {
      k->Jc[q][j] = vc[q] / 3.0;
      k->Jw[q][j] = om[q];
    }
  }

  /* velocities */
  m3_mulv(d->dtheta, M3C(k->G), d->dl);
  m3_mulv(d->vc, M3C(k->Jc), d->dl);
  m3_mulv(d->omega, M3C(k->Jw), d->dl);
  /* one test, and the named checks only when it fails */
  if (!(rps3_all_finite(d->dtheta, 3) & rps3_all_finite(d->vc, 3) &
        rps3_all_finite(d->omega, 3))) {
    RPS3_CHECK_FINITE(d, d->dtheta, 3, "dtheta");
    RPS3_CHECK_FINITE(d, d->vc, 3, "vc");
    RPS3_CHECK_FINITE(d, d->omega, 3, "omega");
  }
  if (dpose) {
    rps3_pose_rates(d);
    RPS3_CHECK_FINITE(d, d->dpose, 3, "dpose");
  } else {
    d->dpose[0] = d->dpose[1] = d->dpose[2] = (double)NAN;
  }
  d->stage |= RPS3_STAGE_VEL;

  /* the bias: b_i'' = (l_i'' - l_i th_i'^2) phi_i + (2 l_i' th_i' + l_i
     th_i'') dphi_i at l'' = 0, without its theta'' part (kn) first */
  d->ddl[0] = d->ddl[1] = d->ddl[2] = 0.0;
  rps3_joint_acc_rhs(d, kn, x);
  for (i = 0; i < 3; i++)
    k->ddth_b[i] = X[3 * i] * x[0] + X[3 * i + 1] * x[1] + X[3 * i + 2] * x[2];
  /* ac = mean b_i''; domega from sum_i rho_i x (b_i'' - omega x (omega x
     rho_i)), the last term (omega . rho_i) rho_i x omega */
  k->ac_b[0] = k->ac_b[1] = k->ac_b[2] = 0.0;
  w[0] = w[1] = w[2] = 0.0;
  for (i = 0; i < 3; i++) {
    double bdd[3], t[3];
    v3_axpy(bdd, kn[i], d->l[i] * k->ddth_b[i], d->dphi[i]);
    v3_axpy(k->ac_b, k->ac_b, 1.0 / 3.0, bdd);
    v3_cross(t, rho[i], bdd);
    v3_axpy(w, w, 1.0, t);
    v3_cross(t, rho[i], d->omega);
    v3_axpy(w, w, -v3_dot(d->omega, rho[i]), t);
  }
  omega_of_sum(k->dw_b, w, a, wk);
  v3_copy(d->ddtheta, k->ddth_b);
  v3_copy(d->ac, k->ac_b);
  v3_copy(d->domega, k->dw_b);
  if (!(rps3_all_finite(d->ddtheta, 3) & rps3_all_finite(d->ac, 3) &
        rps3_all_finite(d->domega, 3))) {
    RPS3_CHECK_FINITE(d, d->ddtheta, 3, "ddtheta");
    RPS3_CHECK_FINITE(d, d->ac, 3, "ac");
    RPS3_CHECK_FINITE(d, d->domega, 3, "domega");
  }
  return RPS3_OK;
}

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

/* Mq and hq of the selected effects at the state of d */
static void assemble(const rps3_model *m, const rps3_data *d,
                     const rps3_fd_state *k, double Mo[3][3], double ho[3]) {
  const int eff = m->opt.effects;
  /* sums in locals: the compiler cannot tell Mo from k's members */
  double Mq[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, hq[3] = {0, 0, 0};
  double Iw[3][3], tl[3] = {0, 0, 0}, Jl[3] = {0, 0, 0}, s[3];
  int i, j, q;
  /* platform: the disc of (21), Ip about its centre, a principal
     inertia in the platform's axes: with Wb = rot^T Jw and wb, dwb the
     angular velocity and bias acceleration in those axes,
       Mq += M Jc^T Jc + Wb^T Ip Wb,
       hq += M Jc^T ac_bias + Wb^T (Ip dwb + wb x Ip wb)  (add_body's) */
  if (eff & RPS3_EFF_PLATFORM_INERTIA) {
    double Wb[3][3], wb[3], dwb[3], Iwb[3], t[3];
    m3_mulvt(wb, M3C(d->rot), d->omega);
    m3_mulvt(dwb, M3C(d->rot), k->dw_b);
    for (q = 0; q < 3; q++) {
      double wq[3] = {k->Jw[0][q], k->Jw[1][q], k->Jw[2][q]};
      m3_mulvt(t, M3C(d->rot), wq);
      for (i = 0; i < 3; i++) Wb[i][q] = t[i];
      Iwb[q] = m->Ip[q] * wb[q];
    }
    v3_cross(t, wb, Iwb);
    for (i = 0; i < 3; i++) t[i] += m->Ip[i] * dwb[i];
    for (j = 0; j < 3; j++) {
      for (q = j; q < 3; q++) {
        double mjq = 0.0;
        for (i = 0; i < 3; i++)
          mjq += m->M * k->Jc[i][j] * k->Jc[i][q] +
                 m->Ip[i] * Wb[i][j] * Wb[i][q];
        Mq[j][q] += mjq;
      }
      for (i = 0; i < 3; i++)
        hq[j] += m->M * k->Jc[i][j] * k->ac_b[i] + Wb[i][j] * t[i];
    }
  }
  /* (22): M g z_c, z_c' = Jc[2] l' */
  if (eff & RPS3_EFF_PLATFORM_GRAVITY)
    for (j = 0; j < 3; j++) hq[j] += m->M * m->g * k->Jc[2][j];
  /* payload: weight and inertia together */
  if (eff & RPS3_EFF_PAYLOAD) {
    m3_mulv(s, M3C(d->rot), m->payload.com);
    inertia_world(Iw, M3C(d->rot), m->payload.inertia);
    add_body(k, d, m->payload.mass, s, M3C(Iw), m->g, Mq, hq);
  }
  /* links: generalized loads on theta_i, mapped to l by G^T */
  for (i = 0; i < 3; i++) {
    if (eff & RPS3_EFF_LINK_INERTIA) {
      Jl[i] = m->Jlink;
      tl[i] += m->Jlink * k->ddth_b[i];
    }
    /* (22): d/dtheta of m g d sin(theta); cos theta is dphi_i's Z */
    if (eff & RPS3_EFF_LINK_GRAVITY) tl[i] += m->m * m->g * m->d * d->dphi[i][2];
    if (eff & RPS3_EFF_PIN_FRICTION)
      tl[i] -= rps3_friction_torque(m, d->dtheta[i]);
  }
  for (j = 0; j < 3; j++) {
    for (q = j; q < 3; q++)
      for (i = 0; i < 3; i++) Mq[j][q] += Jl[i] * k->G[i][j] * k->G[i][q];
    for (i = 0; i < 3; i++) hq[j] += k->G[i][j] * tl[i];
  }
  /* the upper triangle is Mq: symmetric to the bit */
  for (j = 0; j < 3; j++) {
    for (q = 0; q < 3; q++) Mo[j][q] = (q >= j) ? Mq[j][q] : Mq[q][j];
    ho[j] = hq[j];
  }
}

/* Cholesky factor Mq = L L^T: positive definiteness is the test, the
   solve its use; returns 0 or -1 (a pivot not > 0) */
static int chol3_factor(const double A[3][3], double L[3][3]) {
  int i, j, k;
  memset(L, 0, 9 * sizeof(double));
  for (j = 0; j < 3; j++) {
    double s = A[j][j];
    for (k = 0; k < j; k++) s -= L[j][k] * L[j][k];
    if (!(s > 0.0)) return -1;
    L[j][j] = sqrt(s);
    for (i = j + 1; i < 3; i++) {
      double t = A[i][j];
      for (k = 0; k < j; k++) t -= L[i][k] * L[j][k];
      L[i][j] = t / L[j][j];
    }
  }
  return 0;
}

/* Mq^-1 = L^-T L^-1 from the Cholesky factor (L^-1 by forward
   substitution), symmetric to the bit, and the 1-norm condition number
   of Mq with it.  The accelerations are Mq^-1 (F - hq): one product per
   force, where a solve would divide six times. */
static double chol3_inverse_cond1(const double A[3][3], const double L[3][3],
                                  double Ai[3][3]) {
  double Li[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, anorm = 0.0,
         inorm = 0.0;
  int i, j, k;
  for (i = 0; i < 3; i++) {
    Li[i][i] = 1.0 / L[i][i];
    for (j = 0; j < i; j++) {
      double t = 0.0;
      for (k = j; k < i; k++) t += L[i][k] * Li[k][j];
      Li[i][j] = -t * Li[i][i];
    }
  }
  for (i = 0; i < 3; i++)
    for (j = i; j < 3; j++) {
      double t = 0.0;
      for (k = j; k < 3; k++) t += Li[k][i] * Li[k][j];
      Ai[i][j] = Ai[j][i] = t;
    }
  for (j = 0; j < 3; j++) {
    double sa = 0.0, si = 0.0;
    for (i = 0; i < 3; i++) {
      sa += fabs(A[i][j]);
      si += fabs(Ai[i][j]);
    }
    anorm = fmax(anorm, sa);
    inorm = fmax(inorm, si);
  }
  return anorm * inorm;
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
 * answer, and one or two Newton steps converge where GSL's hybridsj
 * costs its set-up on every call.  The same convergence test as
 * rps3_theta_solve (max |f_k| / R^2 <= opt.tol).  The cosines and sines of
 * the last evaluation, at the root, serve its positions.  Returns 0 when
 * it converged to a root that rps3_theta_solve would accept (0 < theta <
 * pi, not the spun platform); otherwise the caller falls back to rps3_fk,
 * which decides and reports.
 */
#define NEWTON_MAX 8
/* largest predicted change of a theta_i [rad]: ~0.6 degree, many steps of
   any run that keeps its accuracy */
#define PREDICT_MAX 1e-2
static int theta_newton(const rps3_model *m, rps3_data *d, int pose) {
  double L[3], c[3], sn[3];
  int it, i, k, fold = 0;
  if (!(m->opt.warm_start && d->have_theta && v3_finite(d->theta)) ||
      !v3_finite(d->l) || !(d->l[0] > 0 && d->l[1] > 0 && d->l[2] > 0))
    return -1;
  for (i = 0; i < 3; i++) L[i] = d->l[i] / m->R;
  for (it = 0; it <= NEWTON_MAX; it++) {
    /* (8)-(10) in units of R, as the GSL solve sees them */
    double f[3], J[3][3], LU[9], resid = 0.0;
    int perm[3];
    for (i = 0; i < 3; i++) {
      double t = d->theta[i]; /* one sincos */
      c[i] = cos(t);
      sn[i] = sin(t);
    }
    rps3_theta_constraints_trig(L, m->rho, c, sn, f, J);
    for (k = 0; k < 3; k++) resid = fmax(resid, fabs(f[k]));
    if (!(resid < HUGE_VAL)) return -1;
    if (resid <= m->opt.tol) {
      d->solve_niter = it;
      d->solve_resid = resid;
      break;
    }
    if (it == NEWTON_MAX) return -1;
    for (i = 0; i < 3; i++)
      for (k = 0; k < 3; k++) LU[3 * i + k] = J[i][k];
    if (rps3_lu_factor(3, LU, perm) != 0) return -1;
    rps3_lu_solve(3, LU, perm, f);
    for (i = 0; i < 3; i++) d->theta[i] -= f[i];
  }
  for (i = 0; i < 3; i++) {
    if (d->theta[i] > 0.0 && d->theta[i] < RPS3_PI) continue;
    d->theta[i] = remainder(d->theta[i], 2.0 * RPS3_PI);
    fold = 1;
    if (!(d->theta[i] > 0.0 && d->theta[i] < RPS3_PI)) return -1;
  }
  if (fold)
    rps3_links_from_joints(m, d);
  else
    rps3_links_from_trig(m, d, c, sn);
  rps3_frame_from_balls(m, d);
  if (d->rot[0][0] + d->rot[1][1] < 0.0) return -1; /* spun platform */
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
  double dl[3], L[3][3];
  int status, i, pd;
  if (!v3_finite(d->dl)) {
    poison(d);
    RPS3_ERROR(d, RPS3_EINVAL, "dl (%g, %g, %g) m/s is not finite", d->dl[0],
               d->dl[1], d->dl[2]);
  }
  if (!has_mass(m)) {
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
    double th0[3], dth[3] = {0, 0, 0}, dlen[3];
    v3_copy(th0, d->theta);
    d->stage = 0;
    d->warn = 0;
    /* the start moved along the last state's tangent, theta + G (l -
       l_last): within O(|l - l_last|^2) of the root, one Newton step
       instead of two.  A step of more than PREDICT_MAX (near a singular
       configuration, where G grows) is not taken: the start stays where
       the last root was, as does the fall-back */
    if ((flags & RPS3_FD_PREDICT) && m->opt.warm_start && d->have_theta) {
      double big = 0.0;
      v3_sub(dlen, d->l, k->l);
      m3_mulv(dth, M3C(k->G), dlen);
      for (i = 0; i < 3; i++) big = fmax(big, fabs(dth[i]));
      if (big <= PREDICT_MAX)
        v3_axpy(d->theta, d->theta, 1.0, dth);
    }
    if (theta_newton(m, d, !(flags & RPS3_FD_LEAN)) == 0) {
      d->have_theta = 1;
      d->stage = RPS3_STAGE_POS;
    } else {
      v3_copy(d->theta, th0);
      status = rps3_fk(m, d);
      if (status != RPS3_OK) {
        poison(d);
        return status;
      }
    }
  }
  v3_copy(k->l, d->l);
  /* rates, the accelerations at l'' = 0 (the bias) and the maps */
  v3_copy(d->dl, dl);
  status = rates_and_maps(m, d, k, !(flags & RPS3_FD_LEAN));
  if (status != RPS3_OK) {
    poison(d);
    return status;
  }
  poison(d); /* no acceleration before rps3_fwddyn_accel */

  /* Mq symmetric positive definite and conditioned: its factor, and the
     condition number from it (by LU when it does not exist) */
  assemble(m, d, k, d->Mq, d->hq);
  pd = (chol3_factor(M3C(d->Mq), L) == 0);
  d->Mcond = pd ? chol3_inverse_cond1(M3C(d->Mq), M3C(L), k->Minv)
                : mass_cond(M3C(d->Mq));
  if (!pd || !(d->Mcond <= m->opt.cond_max))
    RPS3_ERROR(d, RPS3_ESING,
               "mass matrix not positive definite or condition number %.3g "
               "above cond_max %.3g", d->Mcond, m->opt.cond_max);
  RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
  RPS3_CHECK_FINITE(d, d->Mq, 9, "Mq");
  return RPS3_OK;
}

int rps3_fwddyn_accel(const rps3_model *m, rps3_data *d,
                      const rps3_fd_state *k) {
  double x[3];
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
  /* every acceleration is its map applied to l'' plus its bias */
  for (i = 0; i < 3; i++) {
    d->ddtheta[i] = k->ddth_b[i] + v3_dot(k->G[i], x);
    d->ac[i] = k->ac_b[i] + v3_dot(k->Jc[i], x);
    d->domega[i] = k->dw_b[i] + v3_dot(k->Jw[i], x);
  }
  if (!(rps3_all_finite(d->ddtheta, 3) & rps3_all_finite(d->ac, 3) &
        rps3_all_finite(d->domega, 3))) {
    RPS3_CHECK_FINITE(d, d->ddtheta, 3, "ddtheta");
    RPS3_CHECK_FINITE(d, d->ac, 3, "ac");
    RPS3_CHECK_FINITE(d, d->domega, 3, "domega");
  }
  d->stage |= RPS3_STAGE_ACC;
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
