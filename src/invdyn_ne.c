/*
 * invdyn_ne.c - the inverse dynamics by Newton-Euler (opt.method
 * RPS3_NEWTON_EULER), the formulation independent of the Lagrange route
 * of invdyn.c: each link's and the platform's force and moment balance,
 * a 6x6 system in the actuator forces F_i and the pin torques tau_i.
 */
#include "internal.h"
#include "linalg.h"

/* world inertia tensor rot diag(I) rot^T applied to v */
void rps3_inertia_apply(double res[3], const double rot[3][3],
                        const double I[3], const double v[3]) {
  double t[3];
  m3_mulvt(t, M3C(rot), v);
  t[0] *= I[0];
  t[1] *= I[1];
  t[2] *= I[2];
  m3_mulv(res, M3C(rot), t);
}

/* Euler: I w' + w x I w, world axes */
static void euler_moment(double res[3], const double rot[3][3],
                         const double I[3], const double w[3],
                         const double dw[3]) {
  double Iw[3], t[3];
  rps3_inertia_apply(res, rot, I, dw);
  rps3_inertia_apply(Iw, rot, I, w);
  v3_cross(t, w, Iw);
  v3_axpy(res, res, 1.0, t);
}

/* payload centre of mass offset (world) and its acceleration */
void rps3_payload_kin(const rps3_model *m, const rps3_data *d, double rg[3],
                      double vg[3], double ag[3]) {
  double t[3];
  m3_mulv(rg, M3C(d->rot), m->payload.com);
  v3_cross(t, d->omega, rg);
  v3_axpy(vg, d->vc, 1.0, t);
  v3_cross(ag, d->domega, rg);
  v3_axpy(ag, ag, 1.0, d->ac);
  v3_cross(t, d->omega, rg);
  v3_cross(t, d->omega, t);
  v3_axpy(ag, ag, 1.0, t);
}

/* a general platform's wrench about its centre (bodies.c), its weight
   alone or its inertia alone */
static void platform_wrench(const rps3_model *m, const rps3_data *d,
                            int inertia, double wf[3], double wm[3]) {
  const double zero[3] = {0.0, 0.0, 0.0};
  double e[3][3], a[3];
  int k;
  for (k = 0; k < 3; k++) {
    e[0][k] = d->rot[k][0];
    e[1][k] = d->rot[k][1];
    e[2][k] = d->rot[k][2];
  }
  if (inertia) v3_copy(a, d->ac);
  else
    a[0] = a[1] = 0.0, a[2] = m->g;
  rps3_body_wrench(m->std[0], M3C(e), inertia ? d->omega : zero,
                   inertia ? d->domega : zero, a, wf, wm);
}

/* the general legs' loads (bodies.c), each ball joint's acceleration
   from the platform's motion: the actuator's direct share p_i (its
   piston along the link) and the ball force's component s_i along dphi_i
   that the leg's moment balance about its pin fixes, l s = -wt */
static void legs_ne(const rps3_model *m, const rps3_data *d, int inertia,
                    double p[3], double s[3]) {
  double rho[3], bdd[3], t[3], wt;
  int i;
  for (i = 0; i < 3; i++) {
    v3_sub(rho, d->b[i], d->c);
    /* b'' = ac + omega' x rho + omega x (omega x rho) */
    v3_cross(bdd, d->domega, rho);
    v3_axpy(bdd, bdd, 1.0, d->ac);
    v3_cross(t, d->omega, rho);
    v3_cross(t, d->omega, t);
    v3_axpy(bdd, bdd, 1.0, t);
    rps3_leg_loads(m, i, d->phi[i], d->dphi[i], d->l[i],
                   inertia ? d->dtheta[i] : 0.0, inertia ? d->ddtheta[i] : 0.0,
                   inertia ? bdd : NULL, inertia ? 0.0 : m->g, &p[i], &wt);
    s[i] = -wt / d->l[i];
  }
}

/*
 * Newton-Euler loads of effect e: the wrench (force wf, moment wm about the
 * centre) the links must apply to the platform, the component s_i of
 * each ball force along dphi_i fixed by link i's moment balance about its
 * pin:  Jlink theta'' = -l s - m g d cos(theta) + T_fric, and the share p_i
 * of actuator i that does not reach the ball (a piston's load along the
 * link, the prismatic joint's friction): F_i = phi_i . f_i + p_i.
 */
static void ne_effect(const rps3_model *m, const rps3_data *d, int e,
                      double wf[3], double wm[3], double s[3], double p[3]) {
  double rg[3], vg[3], ag[3];
  int i;
  for (i = 0; i < 3; i++) wf[i] = wm[i] = s[i] = p[i] = 0.0;
  if (m->bodies == RPS3_BODIES_GENERAL) switch (1 << e) {
    case RPS3_EFF_PLATFORM_GRAVITY:
    case RPS3_EFF_PLATFORM_INERTIA:
      platform_wrench(m, d, (1 << e) == RPS3_EFF_PLATFORM_INERTIA, wf, wm);
      return;
    case RPS3_EFF_LINK_GRAVITY:
    case RPS3_EFF_LINK_INERTIA:
      legs_ne(m, d, (1 << e) == RPS3_EFF_LINK_INERTIA, p, s);
      return;
    default: break;
    }
  switch (1 << e) {
  case RPS3_EFF_PLATFORM_GRAVITY: wf[2] = m->M * m->g; break;
  case RPS3_EFF_PLATFORM_INERTIA:
    v3_scale(wf, m->M, d->ac);
    euler_moment(wm, M3C(d->rot), m->Ip, d->omega, d->domega);
    break;
  case RPS3_EFF_PAYLOAD:
    rps3_payload_kin(m, d, rg, vg, ag);
    v3_scale(wf, m->payload.mass, ag);
    wf[2] += m->payload.mass * m->g;
    v3_cross(wm, rg, wf);
    {
      double t[3];
      euler_moment(t, M3C(d->rot), m->payload.inertia, d->omega, d->domega);
      v3_axpy(wm, wm, 1.0, t);
    }
    break;
  case RPS3_EFF_LINK_GRAVITY:
    for (i = 0; i < 3; i++)
      s[i] = -m->m * m->g * m->d * d->dphi[i][2] / d->l[i]; /* cos(theta) */
    break;
  case RPS3_EFF_LINK_INERTIA:
    for (i = 0; i < 3; i++) s[i] = -m->Jlink * d->ddtheta[i] / d->l[i];
    break;
  case RPS3_EFF_PIN_FRICTION:
    for (i = 0; i < 3; i++)
      s[i] = rps3_friction_torque(m, i, d->dtheta[i]) / d->l[i];
    break;
  case RPS3_EFF_PRISMATIC_FRICTION:
    for (i = 0; i < 3; i++)
      p[i] = rps3_friction_law(&m->leg[i].prismatic, d->dl[i]);
    break;
  default: break;
  }
}

/* the Newton-Euler system, factored into LU, perm: unknowns x = (F_1,
   F_2, F_3, tau_1, tau_2, tau_3), f_i = F_i phi_i + s_i dphi_i + tau_i
   axis_i; rows: force (3), moment about c (3); rho_i = b_i - c.
   Returns 0, or -1 for a singular system */
int rps3_ne_system(const rps3_model *m, const rps3_data *d, double LU[36],
                   int perm[6], double rho[3][3]) {
  double t[3];
  int i, r;
  for (i = 0; i < 3; i++) {
    v3_sub(rho[i], d->b[i], d->c);
    for (r = 0; r < 3; r++) {
      LU[6 * r + i] = d->phi[i][r];
      LU[6 * r + 3 + i] = m->axis[i][r];
    }
    v3_cross(t, rho[i], d->phi[i]);
    for (r = 0; r < 3; r++) LU[6 * (3 + r) + i] = t[r];
    v3_cross(t, rho[i], m->axis[i]);
    for (r = 0; r < 3; r++) LU[6 * (3 + r) + 3 + i] = t[r];
  }
  return rps3_lu_factor(6, LU, perm);
}

/* the right-hand side x of the Newton-Euler system for effect e: the
   wrench of ne_effect less the ball forces' known parts k_i = s_i dphi_i
   - p_i phi_i (f_i = (F_i - p_i) phi_i + s_i dphi_i + tau_i axis_i) */
static void ne_rhs_of(const rps3_data *d, const double rho[3][3],
                      double wf[3], double wm[3], const double s[3],
                      const double p[3], double x[6]) {
  double t[3];
  int i, r;
  for (i = 0; i < 3; i++) {
    v3_axpy(wf, wf, -s[i], d->dphi[i]);
    v3_cross(t, rho[i], d->dphi[i]);
    v3_axpy(wm, wm, -s[i], t);
    if (p[i] == 0.0) continue;
    v3_axpy(wf, wf, p[i], d->phi[i]);
    v3_cross(t, rho[i], d->phi[i]);
    v3_axpy(wm, wm, p[i], t);
  }
  for (r = 0; r < 3; r++) {
    x[r] = wf[r];
    x[3 + r] = wm[r];
  }
}

void rps3_ne_rhs(const rps3_model *m, const rps3_data *d,
                 const double rho[3][3], int e, double x[6]) {
  double wf[3], wm[3], s[3], p[3];
  ne_effect(m, d, e, wf, wm, s, p);
  ne_rhs_of(d, rho, wf, wm, s, p, x);
}

void rps3_ne_rhs_legs(const rps3_data *d, const double rho[3][3],
                      const double w[6], double x[6]) {
  double wf[3] = {0.0, 0.0, 0.0}, wm[3] = {0.0, 0.0, 0.0}, s[3], p[3];
  int i;
  for (i = 0; i < 3; i++) {
    p[i] = w[i];
    s[i] = -w[3 + i] / d->l[i];
  }
  ne_rhs_of(d, rho, wf, wm, s, p, x);
}

int rps3_newton_euler(const rps3_model *m, rps3_data *d) {
  double LU[36], rho[3][3], xsum[6] = {0, 0, 0, 0, 0, 0};
  int perm[6], i, e, r;
  int eff = m->opt.effects;
  if (rps3_ne_system(m, d, LU, perm, rho) != 0)
    RPS3_ERROR(d, RPS3_ESING, "Newton-Euler system is singular");
  for (e = 0; e < RPS3_NEFFECT; e++) {
    double x[6];
    if (!(eff & (1 << e))) continue;
    rps3_ne_rhs(m, d, M3C(rho), e, x);
    if (!(m->opt.outputs & RPS3_OUT_EFFECTS)) {
      /* the sum of the wrenches, solved once below: no shares */
      for (r = 0; r < 6; r++) xsum[r] += x[r];
      continue;
    }
    rps3_lu_solve(6, LU, perm, x);
    for (i = 0; i < 3; i++) {
      d->F_effect[e][i] = x[i];
      d->F[i] += x[i];
    }
  }
  if (!(m->opt.outputs & RPS3_OUT_EFFECTS)) {
    rps3_lu_solve(6, LU, perm, xsum);
    for (i = 0; i < 3; i++) d->F[i] = xsum[i];
  }
  d->has_lambda = 0;
  return RPS3_OK;
}
