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
 * l'' = 0 (the velocity-product "bias").  The inverse dynamics' forces
 * are F = wl + G^T wt for the loads (wl, wt) of src/loads.h on each
 * link's l_i and theta_i ((23), (34): (df/dtheta)^T lambda = -wt), and F
 * is linear in l'', so
 *   hq = F at the bias accelerations: the loads of every selected effect
 *        at c'' = ac_bias, b_i'' = (h_i'', Z_i'')_bias, theta'' =
 *        theta''_bias, the links' rates (friction) and weights,
 *   Mq e_j = F of the inertia loads at l'' = e_j, rates zero: c'' = Jc
 *        e_j, b_i'' = [i = j] phi_i + l_i G_ij dphi_i, theta'' = G e_j.
 * hq instantiates the loads of src/loads.h themselves (bias_force, in each
 * link's frame); Mq is their columns in Gram form: the platform, the
 * uniform disc of (21), is M/2 at its centre and M/6 at each ball joint,
 * and with phi.phi = dphi.dphi = 1, phi.dphi = 0
 *   Mq = (M/6) I + G^T diag(Jlink + (M/6) l_i^2) G + (M/2) Jc^T Jc,
 * half the flops of the columns themselves (tests/test_fd_loads.c holds
 * it to them, docs/library.md says why).
 * A payload, a rigid body of mass mb, centre of mass offset s and world
 * inertia Iw about it, with Jg = Jc - [s]x Jw its centre of mass's map:
 *   Mq += mb Jg^T Jg + Jw^T Iw Jw,
 *   hq += Jg^T mb (a_g,bias + g e_z) + Jw^T (Iw dw_bias + w x Iw w),
 * in its own form (rps3_fd_add_body), not the inverse dynamics' body_load
 * (a load through the frame's second derivatives, several times dearer:
 * docs/library.md, "The formulation").
 * The general bodies (RPS3_BODIES_GENERAL) have no such Gram form: their
 * Mq and hq are the loads' columns themselves, src/fwddyn_general.c.
 * rps3_invdyn's Lagrange route writes the platform as the same points,
 * with the same loads; its Newton-Euler route (a rigid body and six
 * ball-joint forces) and the kinetic energy of rps3_energy
 * (src/fwddyn_body.c, the disc's inertia tensor) share nothing with Mq
 * and hq, and the tests hold them to both.  The
 * steps of a state are in src/fwddyn_plane.h, its theta solve in
 * src/fwddyn_theta.c, another model's state at a kept one in
 * src/fwddyn_shared.c, the test of a failed solve at the singular surface
 * in src/fwddyn_singular.c.
 */
#include <string.h>

#include "fwddyn_plane.h"
#include "linalg.h"

/* general body b has a mass, or an inertia about its frame's origin */
static int body_has_mass(const rps3_model *m, int b) {
  const double *p = m->std[b];
  return p[0] > 0.0 || p[4] + p[7] + p[9] > 0.0;
}

/* a selected inertia effect with a non-zero mass: without one Mq = 0 */
static int has_mass(const rps3_model *m) {
  const int eff = m->opt.effects;
  int b, legs = 0;
  if ((eff & RPS3_EFF_PAYLOAD) && m->payload.mass > 0.0) return 1;
  if (m->bodies != RPS3_BODIES_GENERAL)
    return ((eff & RPS3_EFF_PLATFORM_INERTIA) && m->M > 0.0) ||
           ((eff & RPS3_EFF_LINK_INERTIA) && m->Jlink > 0.0);
  for (b = 1; b < RPS3_NBODY; b++) legs |= body_has_mass(m, b);
  return ((eff & RPS3_EFF_PLATFORM_INERTIA) && body_has_mass(m, 0)) ||
         ((eff & RPS3_EFF_LINK_INERTIA) && legs);
}

/* the rates and the bias accelerations a state gave, by name */
static int rates_finite(rps3_data *d, const rps3_fd_state *k) {
  RPS3_CHECK_FINITE(d, d->dtheta, 3, "dtheta");
  RPS3_CHECK_FINITE(d, k->ddth_b, 3, "ddtheta");
  RPS3_CHECK_FINITE(d, k->ac_b, 3, "ac");
  return RPS3_OK;
}

/*
 * Rates, maps, Mq and hq at the positions p holds (l, theta's cosines and
 * sines, and the constraint terms there: plane_constraints) and the rates
 * d->dl, for the selected effects.  The
 * platform's motion (vc, omega, Jw and the angular bias acceleration),
 * which only the full report and a payload read, is left out of a lean
 * state (NaN); RPS3_FD_NOFACTOR adds Jw and what rps3_invdyn reports of
 * the configuration, its checks included.
 */
static int state_eval(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags, plane *p) {
  const int invdyn = (flags & RPS3_FD_NOFACTOR) != 0;
  const int with_w =
      !(flags & RPS3_FD_LEAN) || (m->opt.effects & RPS3_EFF_PAYLOAD);
  double u[3][2], vc[3], om[3], chk = 0.0;
  int i, q, st;
  for (i = 0; i < 3; i++) {
    p->dl[i] = d->dl[i];
    u[i][0] = m->radial[i][0];
    u[i][1] = m->radial[i][1];
  }
  st = plane_jacobian(m, d, p);
  if (st != RPS3_OK) return st;
  plane_rates(p, M2C(u));
  k->have_w = with_w;
  if (with_w || invdyn || (flags & RPS3_FD_KEEP))
    platform_motion(m, p, M2C(u), with_w, k, vc, om);
  for (q = 0; q < 3; q++) {
    d->dtheta[q] = p->dth[q];
    k->ddth_b[q] = p->ddb[q];
    k->ac_b[q] = p->acb[q];
  }
  /* a scratch state's rates and bias are tested through what they give,
     Mq^-1 and l'' (rates_finite on the failure path names them) */
  if (!(flags & RPS3_FD_SCRATCH) || with_w)
    for (q = 0; q < 3; q++)
      chk += fabs(p->dth[q]) + fabs(p->ddb[q]) + fabs(p->acb[q]);
  if (with_w) {
    for (q = 0; q < 3; q++) {
      chk += fabs(vc[q]) + fabs(om[q]) + fabs(k->dw_b[q]);
      d->vc[q] = vc[q];
      d->omega[q] = om[q];
    }
  } else if (!(flags & RPS3_FD_SCRATCH)) {
    for (q = 0; q < 3; q++)
      d->vc[q] = d->omega[q] = (double)NAN; /* as positions */
  }
  memcpy(k->G, p->G, sizeof(p->G));
  memcpy(k->Jc, p->Jc, sizeof(p->Jc));
  /* one test of the rates and the bias; the named checks when it fails */
  if (!(chk <= DBL_MAX)) {
    st = rates_finite(d, k);
    if (st != RPS3_OK) return st;
    if (with_w) {
      RPS3_CHECK_FINITE(d, d->vc, 3, "vc");
      RPS3_CHECK_FINITE(d, d->omega, 3, "omega");
      RPS3_CHECK_FINITE(d, k->dw_b, 3, "domega");
    }
  }
  if (invdyn) {
    st = invdyn_limits(m, d, p, k);
    if (st != RPS3_OK) return st;
  }
  assemble(m, d, k, p);
  return RPS3_OK;
}

/*
 * Mq^-1 by the adjugate over the determinant, symmetric to the bit: one
 * division, where a Cholesky factor chains three square roots and three
 * divisions on the evaluation's critical path.  The determinant cancels
 * terms of order A00 A11 A22 (products of three entries, each at most
 * sqrt(A_ii A_jj) in a positive definite A) down to det: it serves when
 * Mq is positive definite by Sylvester's criterion (M00, M00 M11 - M01^2
 * and det > 0) with det at least MASS_ADJ_DET A00 A11 A22 (the
 * diagonally scaled matrix's determinant, which bounds its smallest
 * eigenvalue from below by MASS_ADJ_DET / 9 and its condition number by
 * 2.7e5), and returns -1 otherwise, for mass_decide's Cholesky factor to
 * decide.  The accelerations are Mq^-1 (F - hq): one product per force.
 */
#define MASS_ADJ_DET 1e-4
static int mass_inverse(const double A[3][3], double Ai[3][3]) {
  const double c00 = A[1][1] * A[2][2] - A[1][2] * A[1][2];
  const double c01 = A[0][2] * A[1][2] - A[0][1] * A[2][2];
  const double c02 = A[0][1] * A[1][2] - A[0][2] * A[1][1];
  const double c11 = A[0][0] * A[2][2] - A[0][2] * A[0][2];
  const double c12 = A[0][1] * A[0][2] - A[0][0] * A[1][2];
  const double c22 = A[0][0] * A[1][1] - A[0][1] * A[0][1];
  const double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
  double id;
  /* det(D^-1/2 A D^-1/2), D = diag(A), at least MASS_ADJ_DET: the
     determinant's rounding, a few eps A00 A11 A22, is then negligible */
  if (!(A[0][0] > 0.0 && c22 > 0.0 &&
        det > MASS_ADJ_DET * (A[0][0] * A[1][1] * A[2][2]) && det < HUGE_VAL))
    return -1;
  id = 1.0 / det;
  if (!(id < HUGE_VAL)) return -1; /* a subnormal det: no inverse */
  Ai[0][0] = c00 * id;
  Ai[0][1] = Ai[1][0] = c01 * id;
  Ai[0][2] = Ai[2][0] = c02 * id;
  Ai[1][1] = c11 * id;
  Ai[1][2] = Ai[2][1] = c12 * id;
  Ai[2][2] = c22 * id;
  return 0;
}

/* the 1-norm condition number of A from A and its inverse (3 x 3, rows
   in order) */
static double cond1_of(const double *A, const double *Ai) {
  double anorm = 0.0, inorm = 0.0;
  int i, j;
  for (j = 0; j < 3; j++) {
    double sa = 0.0, si = 0.0;
    for (i = 0; i < 3; i++) {
      sa += fabs(A[3 * i + j]);
      si += fabs(Ai[3 * i + j]);
    }
    anorm = max2(anorm, sa);
    inorm = max2(inorm, si);
  }
  return anorm * inorm;
}

/*
 * Mq^-1 by its Cholesky factor Mq = L D L^T, on the failure path of
 * mass_inverse: the adjugate's determinant cancels terms of order
 * |Mq|^3 down to |Mq| lambda_min^2, and its sign is rounding from
 * cond(Mq) ~ 1e8 on, while a Cholesky pivot d_k is at least lambda_min
 * against a rounding of a few eps A_kk, so that it decides up to cond ~
 * 1e15 (cond_max <= 1e13 by default).  A pivot at or below MASS_PIVOT_TOL
 * times its diagonal entry is not positive: returns its index (1..3) and
 * *piv its ratio d_k / A_kk; 0 with the inverse otherwise.
 */
#define MASS_PIVOT_TOL (8.0 * DBL_EPSILON)

static int mass_chol_inverse(const double A[3][3], double Ai[3][3],
                             double *piv) {
  double D[3], L10, L20, L21, a11, a12, a22, Li[3][3], x;
  int i, j, k;
  D[0] = A[0][0];
  *piv = D[0] / A[0][0];
  if (!(D[0] > 0.0 && D[0] < HUGE_VAL)) return 1;
  L10 = A[0][1] / D[0];
  L20 = A[0][2] / D[0];
  a11 = A[1][1] - L10 * A[0][1];
  a12 = A[1][2] - L10 * A[0][2];
  a22 = A[2][2] - L20 * A[0][2];
  D[1] = a11;
  *piv = D[1] / A[1][1];
  if (!(D[1] > MASS_PIVOT_TOL * A[1][1])) return 2;
  L21 = a12 / D[1];
  D[2] = a22 - L21 * a12;
  *piv = D[2] / A[2][2];
  if (!(D[2] > MASS_PIVOT_TOL * A[2][2])) return 3;
  /* L^-1 (unit lower triangular), then A^-1 = L^-T D^-1 L^-1 */
  Li[0][0] = Li[1][1] = Li[2][2] = 1.0;
  Li[0][1] = Li[0][2] = Li[1][2] = 0.0;
  Li[1][0] = -L10;
  Li[2][1] = -L21;
  Li[2][0] = L10 * L21 - L20;
  for (i = 0; i < 3; i++)
    for (j = i; j < 3; j++) {
      x = 0.0;
      for (k = j; k < 3; k++) x += Li[k][i] * Li[k][j] / D[k];
      Ai[i][j] = Ai[j][i] = x;
    }
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

/* the failure path of the adjugate's test: Mq decided by its Cholesky
   factor (mass_chol_inverse: the adjugate's determinant fails by rounding
   far below cond_max), and its inverse from that factor when it passes */
static int mass_decide(const rps3_model *m, rps3_data *d, rps3_fd_state *k) {
  double A[3][3], Ai[3][3], piv;
  int bad, st;
  memcpy(A, d->Mq, sizeof(A));
  bad = mass_chol_inverse(M3C(A), Ai, &piv);
  if (bad) {
    d->Mcond = mass_cond(M3C(A));
    return rps3_sing_mass_indefinite(d, bad, piv, d->Mcond);
  }
  d->Mcond = cond1_of(&A[0][0], &Ai[0][0]);
  st = rps3_sing_check(m, d, RPS3_SING_MQ, d->Mcond);
  if (st != RPS3_OK) return st;
  memcpy(k->Minv, Ai, sizeof(Ai));
  return RPS3_OK;
}

/* evaluations whose start trigonometry rps3_trig_step moves before one
   takes sincos again: the phase's rounding, an ulp a step at most, stays
   below 1e-13 rad (the solve's tolerance is 1e-12) */
#define TRIG_RESYNC 256

int rps3_fwddyn_state(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags) {
  const int lean = (flags & RPS3_FD_LEAN) != 0;
  const int payload = (m->opt.effects & RPS3_EFF_PAYLOAD) != 0;
  /* the positions (ball joints, link directions, frame): not in a lean
     stage, which reads theta alone, unless a payload needs them */
  const int positions = !lean || payload;
  plane p;
  double dl[3], *c = p.q.c, *sn = p.q.s, bound;
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
  k->have_kin = 0;

  /* positions: theta from l, warm-started on the tracked assembly mode;
     Newton from the warm start, else the full solve (which reports) */
  {
    double th0[3];
    v3_copy(th0, d->theta);
    d->stage = 0;
    d->warn = 0;
    /* the start predicted from the last root along the change of the
       lengths, to second order along the last state's rates, whose bias
       theta'' is formed already (rps3_theta_predict): an integrator's
       next stage lies along them (RK4's second and fourth stages to
       O(h^3)), the start is within O(h^3) of the root, most often within
       the tolerance, and no Newton step is taken.  A step of more than
       RPS3_FD_PREDICT_MAX (near a singular configuration, where G grows)
       is not taken: the start stays where the last root was, as does the
       fall-back */
    if ((flags & RPS3_FD_PREDICT) && m->opt.warm_start && d->have_theta) {
      double dlen[3];
      v3_sub(dlen, d->l, k->l);
      rps3_theta_predict(d->theta, d->l, k->l, d->theta, M3C(k->G), k->ddth_b,
                         v3_dot(dlen, k->dl) * k->idl2, RPS3_FD_PREDICT_MAX);
    }
    /* a state started near the last root moves that root's cosines and
       sines by the change of theta (exact: the two are within a factor of
       two); every TRIG_RESYNC-th takes sincos, so that the series'
       rounding never builds up */
    if ((flags & RPS3_FD_TRIG) && k->have_trig && d->have_theta &&
        k->nrot < TRIG_RESYNC) {
      double e[3];
      v3_sub(e, k->th, d->theta);
      if (max2(max2(fabs(e[0]), fabs(e[1])), fabs(e[2])) <=
          RPS3_FD_PREDICT_MAX) {
        v3_copy(c, k->c);
        v3_copy(sn, k->s);
        rps3_trig_step(c, sn, e);
        trig = 1;
      }
    }
    k->have_trig = 0;
    if (rps3_fd_theta_newton(m, d, &p, trig, positions, !lean,
                             !(flags & RPS3_FD_SCRATCH)) == 0) {
      d->have_theta = 1;
      d->stage = positions ? RPS3_STAGE_POS : 0;
    } else {
      double f[3];
      int i;
      const int warm = m->opt.warm_start && d->have_theta;
      const int mode0 = d->mode; /* the last root's */
      v3_copy(d->theta, th0);
      status = rps3_fk(m, d);
      if (status != RPS3_OK) {
        /* a failure at the singular surface says so, with its measure */
        if (warm && (status == RPS3_ENOCONV || status == RPS3_EBRANCH)) {
          const rps3_error err = d->err;
          if (rps3_fd_solve_failed_singular(m, d, th0, mode0) == RPS3_OK)
            d->err = err;
          else
            status = RPS3_ESING;
        }
        poison(d);
        return status;
      }
      for (i = 0; i < 3; i++) {
        p.q.l[i] = d->l[i];
        p.q.th[i] = d->theta[i];
        c[i] = d->dphi[i][2]; /* cos theta_i (29) */
        sn[i] = d->phi[i][2]; /* sin theta_i */
      }
      plane_constraints(m, &p, f);
      trig = 0;
    }
  }
  v3_copy(k->l, d->l);
  v3_copy(k->dl, dl);
  {
    /* for the next state's prediction, off its critical path */
    const double v2 = v3_dot(dl, dl);
    k->idl2 = v2 > 0.0 ? 1.0 / v2 : 0.0;
  }
  v3_copy(k->th, d->theta);
  v3_copy(k->c, c);
  v3_copy(k->s, sn);
  k->have_trig = 1;
  k->nrot = trig ? k->nrot + 1 : 0;
  v3_copy(d->dl, dl);
  /* rates, the accelerations at l'' = 0 (the bias), the maps, Mq, hq */
  status = state_eval(m, d, k, flags, &p);
  if (status != RPS3_OK) {
    poison(d);
    return status;
  }
  /* a scratch state refused for its mode names non-finite rates first,
     as the states that test them in state_eval do */
  if ((flags & RPS3_FD_SCRATCH) && lean && !k->have_w &&
      m->opt.mode != RPS3_MODE_ANY && d->mode != m->opt.mode) {
    status = rates_finite(d, k);
    if (status != RPS3_OK) {
      poison(d);
      return status;
    }
  }
  status = mode_refused(m, d, k);
  if (status != RPS3_OK) {
    poison(d);
    return status;
  }
  k->scratch = lean && (flags & RPS3_FD_SCRATCH) && !k->have_w;
  if (lean) {
    if (!(flags & RPS3_FD_SCRATCH))
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
     condition number from it; by the adjugate (mass_inverse) where its
     rounding is negligible, else Mq's Cholesky factor (mass_decide)
     decides and inverts, up to cond_max.  An integrator's stage
     (scratch) decides on a bound when it can: cond_1 <= 3 cond_2 <= 3
     tr(Mq) tr(Mq^-1) for a positive definite Mq (|A|_1 <= sqrt(3)
     |A|_2, lambda_max <= tr), with 1e-12 for its rounding (Mcond NaN:
     the number was not needed) */
  pd = (mass_inverse(M3C(d->Mq), k->Minv) == 0);
  bound = pd ? 3.0 * (1.0 + 1e-12) * (d->Mq[0][0] + d->Mq[1][1] + d->Mq[2][2]) *
                   (k->Minv[0][0] + k->Minv[1][1] + k->Minv[2][2])
             : HUGE_VAL;
  if (!pd) {
    d->Mcond = HUGE_VAL; /* mass_decide's */
  } else if (k->scratch && bound <= m->opt.cond_max) {
    d->Mcond = (double)NAN;
  } else {
    d->Mcond = cond1_of(&d->Mq[0][0], &k->Minv[0][0]);
  }
  if (!(d->Mcond <= m->opt.cond_max || isnan(d->Mcond))) {
    status = mass_decide(m, d, k);
    if (status != RPS3_OK) {
      /* a scratch state names non-finite rates first */
      if (k->scratch) {
        const int st2 = rates_finite(d, k);
        if (st2 != RPS3_OK) return st2;
      }
      return status;
    }
  }
  /* a scratch state's hq is tested by rps3_fwddyn_accel's result */
  if (!k->scratch) RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
  k->mode = d->mode;
  if (flags & RPS3_FD_KEEP) {
    k->kin = p;
    memcpy(k->Mq, d->Mq, sizeof(k->Mq));
    v3_copy(k->hq, d->hq);
    k->have_kin = 1;
  }
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
    if (k->scratch) { /* what a scratch state did not test */
      int st = rates_finite(d, k);
      if (st != RPS3_OK) return st;
      RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
    }
    RPS3_ERROR(d, RPS3_ESING,
               RPS3_SING_PREFIX
               "acceleration ddl = Mq^-1 (F - hq) not "
               "finite");
  }
  v3_copy(d->ddl, x);
  if (k->scratch) return RPS3_OK; /* an integrator's stage reads ddl alone */
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
