/*
 * invdyn.c - inverse dynamics, sections III and V, by two independent
 * formulations (the energy-rate certificate is invdyn_certify.c).
 *
 * Both formulations are linear in the loads of the effects, so each selected
 * effect is solved on its own right-hand side with one shared factorization;
 * the shares sum to the total force exactly up to rounding.
 *
 * Lagrange (the paper's form, (21)-(24), (34)).  Coordinates q = (l, theta),
 * constraints f_k = |b_i - b_j|^2 - 3 r^2 ((8)-(10) in metres).  A body
 * fixed to the platform (the payload) is a mass distribution x = c + E s,
 * with E = [n o a] the frame of (18)-(20) written through the ball joints
 * b_i(l_i, theta_i):
 * c = (b1+b2+b3)/3, n = (2 b1 - b2 - b3)/(3r), o = (b2 - b3)/(sqrt3 r),
 * a = n x o.  This extends T off the constraint manifold holonomically, so
 *   d/dt dT/dq' - dT/dq = integral (dx/dq) . x'' dm
 * exactly, and with first moment h and second moment S of the body in
 * platform axes
 *   Q_j = mB dc_j . c'' + dc_j . (E'' h) + (dE_j h) . c''
 *         + sum_ab S_ab dE_j,a . E''_b.
 * The platform itself, the uniform disc of (21), has the mass, centroid and
 * inertia tensor of M/2 at its centre plus M/6 at each ball joint (3 (M/6)
 * r^2 = M r^2 / 2 about z, M r^2 / 4 about x and y), so on the manifold its
 * T equals (M/4) |c'|^2 + (M/12) sum |b_i'|^2 for every rigid motion;
 * written through the ball joints this extension needs no frame partials:
 *   Q_l_i = (M/6) phi_i . (c'' + b_i''),  Q_theta_i = l_i dphi_i . (same).
 * F does not depend on how T is extended off the manifold (the difference
 * lies in the span of the constraint gradients and moves only lambda);
 * lambda does, and is reported for these extensions.  Links are point
 * masses at d from the pin (21), plus an optional centroidal moment.
 *
 * Newton-Euler.  The platform (and payload) is a free rigid body loaded by
 * the ball-joint forces f_i; each link balances moments about its pin axis,
 * which fixes the component of f_i along dphi_i; the actuator carries the
 * component along the link, F_i = phi_i . f_i (massless piston).  The six
 * remaining unknowns (F_i and the component along the pin axis) come from
 * the platform's six equations.  It uses the Cartesian velocities (vc,
 * omega) where the Lagrange route uses the joint rates (invdyn_ne.c).
 */
#include <string.h>

#include "internal.h"
#include "linalg.h"
#include "links.h"
#include "loads.h"
#include "power.h"

/* kinematic quantities of the Lagrange route, per point (on the stack;
   internal.h, the regressor's loads hold one too) */
typedef rps3_lag_kin lag_kin;

static const double WN[3] = {2.0, -1.0, -1.0}; /* n = sum WN_i b_i / (3r) */
static const double WO[3] = {0.0, 1.0, -1.0};  /* o = sum WO_i b_i/(sqrt3 r) */

/* need_frame: the frame's accelerations, for a general body (payload);
   need_acc: the accelerations of the ball joints (inertia effects) */
static void lagrange_kinematics(const rps3_model *m, const rps3_data *d,
                                lag_kin *k, int need_frame, int need_acc) {
  double nd[3] = {0, 0, 0}, od[3] = {0, 0, 0}, bd[3], t[3];
  const double cn = 1.0 / (3.0 * m->r), co = 1.0 / (RPS3_SQRT3 * m->r);
  int i;
  for (i = 0; i < 3; i++) {
    k->n[i] = d->rot[i][0];
    k->o[i] = d->rot[i][1];
    k->cdd[i] = k->ndd[i] = k->odd[i] = k->add[i] = 0.0;
  }
  /* a static scene reads no rates: they are not computed for it */
  if (!need_acc) return;
  for (i = 0; i < 3; i++) {
    double l = d->l[i], ld = d->dl[i], th = d->dtheta[i];
    /* b'' and b' from the joint rates, (12)-(14) (src/links.h) */
    RPS3_BALL_ACC_JOINTS(RPS3_V3C, d->phi[i], d->dphi[i], l, ld, th, d->ddl[i],
                         d->ddtheta[i], k->bdd[i]);
    v3_axpy(k->cdd, k->cdd, 1.0 / 3.0, k->bdd[i]);
    if (!need_frame) continue;
    RPS3_BALL_VEL_JOINTS(RPS3_V3C, d->phi[i], d->dphi[i], l, ld, th, bd);
    v3_axpy(k->ndd, k->ndd, WN[i] * cn, k->bdd[i]);
    v3_axpy(k->odd, k->odd, WO[i] * co, k->bdd[i]);
    v3_axpy(nd, nd, WN[i] * cn, bd);
    v3_axpy(od, od, WO[i] * co, bd);
  }
  if (need_frame) {
    /* a'' = n'' x o + 2 n' x o' + n x o'' */
    v3_cross(k->add, k->ndd, k->o);
    v3_cross(t, nd, od);
    v3_axpy(k->add, k->add, 2.0, t);
    v3_cross(t, k->n, k->odd);
    v3_axpy(k->add, k->add, 1.0, t);
  }
}

/*
 * Generalized inertial (and gravity) load of a body fixed to the platform:
 * mass mb, first moment h, second moment S (platform axes).  q_j = l_i or
 * theta_i moves only b_i, by delta = phi_i or l_i dphi_i, so that dc = delta
 * / 3, dn = WN_i cn delta, do = WO_i co delta and da = dn x o + n x do.
 * Every term of Q_j is then delta . (a vector): with V_p = sum_q S_pq E''_q
 * + h_p (c'' + g e_z), (delta x o) . V = delta . (o x V) and (n x delta) . V
 * = delta . (V x n), the load on link i is delta . G_i with
 *   G_i = C + WN_i cn (V_n + o x V_a) + WO_i co (V_o + V_a x n),
 *   C = (mb (c'' + g e_z) + E'' h) / 3.
 */
static void body_load(const rps3_model *m, const rps3_data *d, const lag_kin *k,
                      double mb, const double h[3], const double S[3][3],
                      double g, int inertia, double w[6]) {
  const double *E2[3] = {k->ndd, k->odd, k->add};
  const double cn = 1.0 / (3.0 * m->r), co = 1.0 / (RPS3_SQRT3 * m->r);
  double cg[3] = {0.0, 0.0, 0.0}, C[3], V[3][3], A[3], B[3], t[3];
  int i, p, q;
  /* c'' + g e_z: inertia and weight enter together (the weight alone
     without inertia: the accelerations read as zero) */
  if (inertia) v3_copy(cg, k->cdd);
  cg[2] += g;
  v3_scale(C, mb, cg);
  for (p = 0; p < 3; p++) {
    if (inertia) v3_axpy(C, C, h[p], E2[p]);
    v3_scale(V[p], h[p], cg);
    for (q = 0; q < 3; q++)
      if (inertia && S[p][q] != 0.0) v3_axpy(V[p], V[p], S[p][q], E2[q]);
  }
  v3_scale(C, 1.0 / 3.0, C);
  v3_cross(t, k->o, V[2]);
  v3_axpy(A, V[0], 1.0, t);
  v3_cross(t, V[2], k->n);
  v3_axpy(B, V[1], 1.0, t);
  for (i = 0; i < 3; i++) {
    double G[3];
    v3_axpy(G, C, WN[i] * cn, A);
    v3_axpy(G, G, WO[i] * co, B);
    w[i] = v3_dot(d->phi[i], G);
    w[3 + i] = d->l[i] * v3_dot(d->dphi[i], G);
  }
}

/* payload first and second moments about the platform centre, platform axes */
static void payload_moments(const rps3_model *m, double h[3], double S[3][3]) {
  const rps3_payload *p = &m->payload;
  double tr = 0.5 * (p->inertia[0] + p->inertia[1] + p->inertia[2]);
  int i, j;
  for (i = 0; i < 3; i++) {
    h[i] = p->mass * p->com[i];
    for (j = 0; j < 3; j++)
      S[i][j] =
          p->mass * p->com[i] * p->com[j] + (i == j ? tr - p->inertia[i] : 0.0);
  }
}

/* the general platform's first and second moments about its centre,
   platform axes, from its standard parameters: h = m c, S = tr(I)/2 1 - I
   (I about the centre) */
static void platform_moments(const rps3_model *m, double h[3],
                             double S[3][3]) {
  const double *p = m->std[0];
  const double I[3][3] = {
      {p[4], p[5], p[6]}, {p[5], p[7], p[8]}, {p[6], p[8], p[9]}};
  double tr = 0.5 * (p[4] + p[7] + p[9]);
  int i, j;
  for (i = 0; i < 3; i++) {
    h[i] = p[1 + i];
    for (j = 0; j < 3; j++) S[i][j] = (i == j ? tr : 0.0) - I[i][j];
  }
}

/* the general legs' loads (bodies.c): their weight, or their inertia at
   the ball joints' accelerations of k */
static void legs_load(const rps3_model *m, const rps3_data *d, const lag_kin *k,
                      int inertia, double w[6]) {
  int i;
  for (i = 0; i < 3; i++)
    rps3_leg_loads(m, i, d->phi[i], d->dphi[i], d->l[i],
                   inertia ? d->dtheta[i] : 0.0, inertia ? d->ddtheta[i] : 0.0,
                   inertia ? k->bdd[i] : NULL, inertia ? 0.0 : m->g, &w[i],
                   &w[3 + i]);
}

/* friction torque about pin axis i, opposing theta-dot (T_{i-3} of (23)):
   the law shared with the forward dynamics, internal.h */
#define friction_torque rps3_friction_torque

/*
 * The loads of effect e as the left-hand side of (23): w[0..2] on l_i,
 * w[3..5] on theta_i (generalized applied torques enter with a minus sign);
 * each link's load of src/loads.h, which the batch kernel compiles too.
 */
static void lagrange_effect(const rps3_model *m, const rps3_data *d,
                            const lag_kin *k, int e, double w[6]) {
  double S[3][3], h[3]; /* set by payload_moments, for the payload only */
  int i;
  memset(w, 0, 6 * sizeof(double));
  if (m->bodies == RPS3_BODIES_GENERAL) switch (1 << e) {
    case RPS3_EFF_PLATFORM_GRAVITY:
    case RPS3_EFF_PLATFORM_INERTIA:
      /* the platform, a general body (body_load) */
      platform_moments(m, h, S);
      body_load(m, d, k, m->std[0][0], h, M3C(S),
                (1 << e) == RPS3_EFF_PLATFORM_GRAVITY ? m->g : 0.0,
                (1 << e) == RPS3_EFF_PLATFORM_INERTIA, w);
      return;
    case RPS3_EFF_LINK_GRAVITY:
    case RPS3_EFF_LINK_INERTIA:
      legs_load(m, d, k, (1 << e) == RPS3_EFF_LINK_INERTIA, w);
      return;
    default: break;
    }
  switch (1 << e) {
  case RPS3_EFF_PLATFORM_GRAVITY:
    /* (22): M g z_c, with dc = db_i / 3 (src/loads.h) */
    for (i = 0; i < 3; i++)
      RPS3_LOAD_PLATFORM_GRAVITY(RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g),
                                 d->phi[i][2], d->dphi[i][2], d->l[i], w[i],
                                 w[3 + i]);
    break;
  case RPS3_EFF_PLATFORM_INERTIA:
    /* (21): the disc as M/2 at c and M/6 at each b_i (see the top) */
    for (i = 0; i < 3; i++)
      RPS3_LOAD_PLATFORM_INERTIA(RPS3_V3C, RPS3_DISC_BALL_MASS(m->M), k->cdd,
                                 k->bdd[i], d->phi[i], d->dphi[i], d->l[i],
                                 w[i], w[3 + i]);
    break;
  case RPS3_EFF_PAYLOAD:
    payload_moments(m, h, S);
    body_load(m, d, k, m->payload.mass, h, M3C(S), m->g, 1, w);
    break;
  case RPS3_EFF_LINK_GRAVITY:
    /* (22): m g d sin(theta_i); cos(theta_i) is dphi_i's Z component, set
       by the position stage (rps3_link_dirs) */
    for (i = 0; i < 3; i++)
      RPS3_LOAD_LINK_GRAVITY(RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d),
                             d->dphi[i][2], w[3 + i]);
    break;
  case RPS3_EFF_LINK_INERTIA:
    /* (21): (m d^2 + I_c) theta'' */
    for (i = 0; i < 3; i++)
      RPS3_LOAD_LINK_INERTIA(m->Jlink, d->ddtheta[i], w[3 + i]);
    break;
  case RPS3_EFF_PIN_FRICTION:
    for (i = 0; i < 3; i++)
      RPS3_LOAD_PIN_FRICTION(friction_torque(m, i, d->dtheta[i]), w[3 + i]);
    break;
  case RPS3_EFF_PRISMATIC_FRICTION:
    /* the force the actuator overcomes, on l_i alone */
    for (i = 0; i < 3; i++)
      w[i] = rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);
    break;
  default: break;
  }
}

/* what lagrange_kinematics must compute for m's effects: the frame's
   accelerations for a general body on the platform (the payload, a
   general platform's inertia), the balls' for any inertia at the balls */
static int need_frame(const rps3_model *m) {
  const int eff = m->opt.effects;
  return (eff & RPS3_EFF_PAYLOAD) ||
         (m->bodies == RPS3_BODIES_GENERAL &&
          (eff & RPS3_EFF_PLATFORM_INERTIA));
}

static int need_balls(const rps3_model *m) {
  const int eff = m->opt.effects;
  return (eff & (RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_PAYLOAD)) ||
         (m->bodies == RPS3_BODIES_GENERAL && (eff & RPS3_EFF_LINK_INERTIA));
}

/* the loads of the effects `effects` (bits, summed) at the point t as the
   Lagrange route forms them (lagrange_kinematics, lagrange_effect): the
   forward dynamics' Mq and hq of the general bodies are these at unit
   and bias accelerations (src/fwddyn_general.c) */
void rps3_lagrange_loads(const rps3_model *m, const rps3_data *t, int effects,
                         double w[6]) {
  lag_kin k;
  double we[6];
  int e, i;
  lagrange_kinematics(m, t, &k, need_frame(m), need_balls(m));
  memset(w, 0, 6 * sizeof(double));
  for (e = 0; e < RPS3_NEFFECT; e++) {
    if (!(effects & (1 << e))) continue;
    lagrange_effect(m, t, &k, e, we);
    for (i = 0; i < 6; i++) w[i] += we[i];
  }
}

static int lagrange(const rps3_model *m, rps3_data *d, const double Jl[3][3],
                    const double LU[9], const int perm[3]) {
  lag_kin k;
  double w[RPS3_NEFFECT][6], lam[3][RPS3_NEFFECT];
  int sel[RPS3_NEFFECT], ns = 0, n, e, i, q;
  int eff = m->opt.effects;
  lagrange_kinematics(m, d, &k, need_frame(m), need_balls(m));
  /* the loads of each selected effect; the theta rows of (23),
     (df/dtheta)^T lambda = -w_theta, one column per effect */
  for (e = 0; e < RPS3_NEFFECT; e++) {
    if (!(eff & (1 << e))) continue;
    lagrange_effect(m, d, &k, e, w[ns]);
    for (i = 0; i < 3; i++) lam[i][ns] = -w[ns][3 + i];
    sel[ns++] = e;
  }
  /* no shares asked for (RPS3_OUT_EFFECTS): the sum of the loads in one
     column */
  if (!(m->opt.outputs & RPS3_OUT_EFFECTS) && ns > 0) {
    for (n = 1; n < ns; n++)
      for (i = 0; i < 6; i++) w[0][i] += w[n][i];
    for (i = 0; i < 3; i++) lam[i][0] = -w[0][3 + i];
    ns = 1;
    sel[0] = -1;
  }
  rps3_lu3_solve_multi(LU, perm, &lam[0][0], RPS3_NEFFECT, ns);
  for (n = 0; n < ns; n++) {
    e = sel[n];
    /* l rows, (34): F_i = w_l,i + sum_k lambda_k df_k/dl_i */
    for (i = 0; i < 3; i++) {
      double f = w[n][i];
      for (q = 0; q < 3; q++) f += lam[q][n] * Jl[q][i];
      if (e >= 0) d->F_effect[e][i] = f;
      d->F[i] += f;
      d->lambda[i] += lam[i][n];
    }
  }
  d->has_lambda = 1;
  return RPS3_OK;
}

/*
 * Force transmission, dimensionless: the largest actuator force a unit
 * platform load calls for.  A wrench (force f, moment n about the centre)
 * applied to the platform is held by the ball-joint forces
 * F_i phi_i + tau_i axis_i (massless links, no link load).  With
 * B = dF/d(f, n) and the moment measured in units of R, the measure is
 *   T = max_i ( sum_{j<3} |B_ij| + R sum_{j>=3} |B_ij| ),
 * so that |F_i| <= T max(|f|_inf, |n|_inf / R) for every load: the holding
 * force of the platform's weight is at most T M g.  T is 2.41 for the
 * paper's level platform at z_c = R, grows like 1 / sin(theta) as the level
 * platform is lowered (where the condition number of df/dtheta stays at 3)
 * and without bound towards every singular configuration.
 *
 * Row i of B by virtual power: the pin-axis forces do no work on the
 * motions the links allow (a ball joint moves in its pin's plane), so
 * F . l' = f . vc + n . omega for every such motion, and row i is the
 * platform twist (vc, omega) for l' = e_i: theta' = G e_i with
 * G = -(df/dtheta)^-1 df/dl, the twist and its measure those of
 * src/power.h (RPS3_TRANS_TWIST, RPS3_TRANS_MEASURE), which the batch
 * kernel compiles too.  Rows of the inverse of the 6 x 6 ball-joint system
 * of the Newton-Euler formulation, from a 3 x 3 LU (test_trans.c holds it
 * to an oracle of its own).  (df/dtheta)^-1 is the transpose of the lambda
 * system's inverse, which its condition number computed (J factored, not
 * singular).
 */
static double transmission(const rps3_model *m, const rps3_data *d,
                           const rps3_cjac *J) {
  const double wk = 2.0 / (3.0 * m->r * m->r);
  double rho[3][3], Q[3][3], a[3], T = 0.0;
  int i, j, q;
  for (j = 0; j < 3; j++) {
    v3_sub(rho[j], d->b[j], d->c);
    v3_cross(Q[j], rho[j], d->dphi[j]);
    a[j] = d->rot[j][2];
  }
  for (i = 0; i < 3; i++) {
    double x[3], P[3], vc[3], w[3], s;
    /* x = G e_i = -(df/dtheta)^-1 df/dl e_i, (df/dtheta)^-1 = Ainv^T */
    for (q = 0; q < 3; q++)
      x[q] = -(J->Ainv[q] * J->Jl[0][i] + J->Ainv[3 + q] * J->Jl[1][i] +
               J->Ainv[6 + q] * J->Jl[2][i]);
    v3_cross(P, rho[i], d->phi[i]);
    RPS3_TRANS_TWIST(RPS3_V3C, wk, d->l[0] * x[0], d->l[1] * x[1],
                     d->l[2] * x[2], d->dphi[0], d->dphi[1], d->dphi[2], Q[0],
                     Q[1], Q[2], d->phi[i], P, a, vc, w);
    s = RPS3_TRANS_MEASURE(RPS3_V3C, m->R, vc, w);
    RPS3_TRANS_MAX(T, s);
  }
  return T;
}

/* the singularity checks of the inverse dynamics at d's positions, with
   their Jacobian J (not yet factored, or factored): writes cond,
   transmission and the warnings */
static int invdyn_checks(const rps3_model *m, rps3_data *d, rps3_cjac *J) {
  int status;
  d->warn &= ~(RPS3_WARN_ILLCOND | RPS3_WARN_TRANS);
  d->transmission = (double)NAN; /* not computed for a singular matrix */

  /* the lambda system (df/dtheta)^T: its conditioning flags singular
     configurations for both formulations.  rps3_inverse passes the one its
     position stage built (perhaps factored by the own-root check) */
  rps3_cjac_factor(J);
  d->cond = J->sing ? HUGE_VAL : J->cond;
  status = rps3_sing_check(m, d, RPS3_SING_LAMBDA, d->cond);
  if (status != RPS3_OK) return status;

  /* force transmission: the condition number measures lost digits, not
     how much force a load takes; both limits are the caller's */
  d->transmission = transmission(m, d, J);
  return rps3_sing_check(m, d, RPS3_SING_TRANS, d->transmission);
}

/* ------------------------------------------- loads of unit parameters */

int rps3_loads_prepare(const rps3_model *m, rps3_data *d, rps3_cjac *J,
                       rps3_loads *L) {
  int status = invdyn_checks(m, d, J);
  if (status != RPS3_OK) return status;
  L->method = m->opt.method;
  L->J = J;
  if (L->method == RPS3_LAGRANGE) {
    lagrange_kinematics(m, d, &L->k, need_frame(m), need_balls(m));
    return RPS3_OK;
  }
  if (rps3_ne_system(m, d, L->LU6, L->perm6, L->rho) != 0)
    RPS3_ERROR(d, RPS3_ESING, "Newton-Euler system is singular");
  return RPS3_OK;
}

void rps3_loads_effect(const rps3_model *u, const rps3_data *d,
                       const rps3_loads *L, int e, double rhs[6]) {
  if (L->method == RPS3_LAGRANGE)
    lagrange_effect(u, d, &L->k, e, rhs);
  else
    rps3_ne_rhs(u, d, M3C(L->rho), e, rhs);
}

void rps3_loads_column(const rps3_model *m, const rps3_model *u,
                       const rps3_data *d, const rps3_loads *L, int effects,
                       double rhs[6]) {
  double w[6];
  int e, r;
  memset(rhs, 0, 6 * sizeof(double));
  for (e = 0; e < RPS3_NEFFECT; e++) {
    if (!(effects & m->opt.effects & (1 << e))) continue;
    rps3_loads_effect(u, d, L, e, w);
    for (r = 0; r < 6; r++) rhs[r] += w[r];
  }
}

void rps3_loads_solve(const rps3_loads *L, int ncol, double (*rhs)[6],
                      double *F, int ldf) {
  int n, i, q;
  if (L->method == RPS3_LAGRANGE) {
    /* as lagrange(): (df/dtheta)^T lambda = -w_theta, all columns at
       once; F_i = w_l,i + sum_k lambda_k df_k/dl_i, (34) */
    double lam[3][RPS3_LOADS_MAXCOL];
    for (n = 0; n < ncol; n++)
      for (i = 0; i < 3; i++) lam[i][n] = -rhs[n][3 + i];
    rps3_lu3_solve_multi(L->J->LU, L->J->perm, &lam[0][0], RPS3_LOADS_MAXCOL,
                         ncol);
    for (n = 0; n < ncol; n++)
      for (i = 0; i < 3; i++) {
        double f = rhs[n][i];
        for (q = 0; q < 3; q++) f += lam[q][n] * L->J->Jl[q][i];
        F[i * ldf + n] = f;
      }
    return;
  }
  for (n = 0; n < ncol; n++) {
    rps3_lu_solve(6, L->LU6, L->perm6, rhs[n]);
    for (i = 0; i < 3; i++) F[i * ldf + n] = rhs[n][i];
  }
}

void rps3_loads_leg_basis(const rps3_data *d, const rps3_loads *L,
                          double Fb[3][6]) {
  double rhs[6][6];
  int j, r;
  for (j = 0; j < 6; j++) {
    double w[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    w[j] = 1.0;
    if (L->method == RPS3_LAGRANGE)
      for (r = 0; r < 6; r++) rhs[j][r] = w[r];
    else
      rps3_ne_rhs_legs(d, M3C(L->rho), w, rhs[j]);
  }
  rps3_loads_solve(L, 6, rhs, &Fb[0][0], 6);
}

int rps3_invdyn(const rps3_model *m, rps3_data *d) {
  return rps3_invdyn_with(m, d, NULL);
}

int rps3_invdyn_with(const rps3_model *m, rps3_data *d, rps3_cjac *J) {
  rps3_cjac own;
  int status, need_rates;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (!(d->stage & RPS3_STAGE_POS))
    RPS3_ERROR(d, RPS3_ESTATE, "inverse dynamics needs positions");
  need_rates = rps3_need_rates(m);
  if (need_rates && (d->stage & (RPS3_STAGE_VEL | RPS3_STAGE_ACC)) !=
                        (RPS3_STAGE_VEL | RPS3_STAGE_ACC))
    RPS3_ERROR(d, RPS3_ESTATE,
               "the selected effects (or the certificate, RPS3_OUT_CERTIFY) "
               "need velocities and accelerations");
  d->stage &= ~RPS3_STAGE_DYN;
  memset(d->F, 0, sizeof(d->F));
  memset(d->F_effect, 0, sizeof(d->F_effect));
  memset(d->lambda, 0, sizeof(d->lambda));
  if (J == NULL) {
    J = &own;
    rps3_cjac_eval(d, J);
  }
  status = invdyn_checks(m, d, J);
  if (status != RPS3_OK) return status;

  status = (m->opt.method == RPS3_LAGRANGE)
               ? lagrange(m, d, M3C(J->Jl), J->LU, J->perm)
               : rps3_newton_euler(m, d);
  if (status != RPS3_OK) return status;
  if (m->opt.outputs & RPS3_OUT_CERTIFY)
    rps3_certify(m, d);
  else
    d->power = d->dTdt = d->dPdt = d->friction_power = d->energy_residual =
        d->energy_scale = 0.0;
  /* finite inputs can still overflow here (M = 1e300, or rates of 1e150
     squared): never report a non-finite force as a result */
  RPS3_CHECK_FINITE(d, d->F_effect, 3 * RPS3_NEFFECT, "F_effect");
  RPS3_CHECK_FINITE(d, d->F, 3, "F");
  RPS3_CHECK_FINITE(d, d->lambda, 3, "lambda");
  RPS3_CHECK_FINITE(d, &d->power, 1, "power");
  RPS3_CHECK_FINITE(d, &d->dTdt, 1, "dTdt");
  RPS3_CHECK_FINITE(d, &d->dPdt, 1, "dPdt");
  RPS3_CHECK_FINITE(d, &d->friction_power, 1, "friction_power");
  RPS3_CHECK_FINITE(d, &d->energy_residual, 1, "energy_residual");
  RPS3_CHECK_FINITE(d, &d->energy_scale, 1, "energy_scale");
  rps3_outputs_clear(m, d);
  d->stage |= RPS3_STAGE_DYN;
  return RPS3_OK;
}

/* NaN into the results of the outputs left out (rps3.h, enum
   rps3_output), after their checks: none holds a value the caller did
   not ask for, or another point's */
void rps3_outputs_clear(const rps3_model *m, rps3_data *d) {
  const int out = m->opt.outputs;
  const double nan = (double)NAN;
  int i, k;
  if (!(out & RPS3_OUT_FORCES))
    for (i = 0; i < 3; i++) d->F[i] = nan;
  if (!(out & RPS3_OUT_EFFECTS))
    for (k = 0; k < RPS3_NEFFECT; k++)
      for (i = 0; i < 3; i++) d->F_effect[k][i] = nan;
  if (!(out & RPS3_OUT_LAMBDA) || !d->has_lambda) {
    for (i = 0; i < 3; i++) d->lambda[i] = nan;
    d->has_lambda = 0;
  }
  if (!(out & RPS3_OUT_TRANSMISSION)) d->transmission = nan;
  if (!(out & RPS3_OUT_CERTIFY))
    d->power = d->dTdt = d->dPdt = d->friction_power = d->energy_residual =
        d->energy_scale = nan;
}
