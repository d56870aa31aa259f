/*
 * fwddyn_body.c - rigid bodies in the forward dynamics and the energy of a
 * state: a payload's terms of Mq and hq (from the platform's maps Jc, Jw,
 * the bias accelerations and its inertia in world axes), and rps3_energy,
 * the kinetic and potential energy from the disc's inertia tensor and the
 * payload's, or from the general bodies' standard parameters, which shares
 * nothing with Mq (src/fwddyn.c's header).
 */
#include "fwddyn_plane.h"

/* world inertia rot diag(I) rot^T */
void rps3_fd_inertia_world(double Iw[3][3], const double rot[3][3],
                           const double I[3]) {
  int p, q, k;
  for (p = 0; p < 3; p++)
    for (q = 0; q < 3; q++) {
      double s = 0.0;
      for (k = 0; k < 3; k++) s += rot[p][k] * I[k] * rot[q][k];
      Iw[p][q] = s;
    }
}

/* add a rigid body: mass mb, centre of mass offset s from the platform
   centre and inertia Iw about it (world axes); g = 0 leaves its weight out */
void rps3_fd_add_body(const rps3_fd_state *k, const rps3_data *d, double mb,
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
 * The kinetic and potential energy of a general body from its standard
 * parameters p (mass m, first moment h, inertia I about its frame's
 * origin O, body axes e: e[k] axis k in the base frame), O moving at vO
 * at height zO, the body turning at omega: with h_w = E h and omega_b =
 * E^T omega,
 *   T = (1/2) m |vO|^2 + vO . (omega x h_w) + (1/2) omega_b . I omega_b,
 *   P = g (m zO + h_w,z),
 * the integrals of (1/2) |v|^2 dm and g z dm over x = O + E s.  Mq and hq
 * come from the bodies' wrenches (rps3_body_wrench through the loads); this
 * shares nothing with them.
 */
static void body_energy(const double p[10], const double e[3][3],
                        const double vO[3], const double om[3], double zO,
                        double g, double *T, double *P) {
  double ob[3], hw[3], t[3];
  int k;
  for (k = 0; k < 3; k++) {
    ob[k] = v3_dot(e[k], om);
    hw[k] = e[0][k] * p[1] + e[1][k] * p[2] + e[2][k] * p[3];
  }
  v3_cross(t, om, hw);
  *T = 0.5 * p[0] * v3_dot(vO, vO) + v3_dot(vO, t) +
       0.5 * (p[4] * ob[0] * ob[0] + p[7] * ob[1] * ob[1] +
              p[9] * ob[2] * ob[2]) +
       p[5] * ob[0] * ob[1] + p[6] * ob[0] * ob[2] + p[8] * ob[1] * ob[2];
  *P = g * (p[0] * zO + hw[2]);
}

/* the general bodies' T and P of the selected effects (the platform about
   its centre with its axes, rot's columns; each leg's cylinder about its
   pin, at rest, and piston about its ball joint, which moves with the
   platform, b' = vc + omega x (b - c), both with the axes phi_i, the pin
   axis and their cross product, turning at theta_i' about the pin axis) */
static void general_energy(const rps3_model *m, const rps3_data *d, double *t,
                           double *p) {
  const int eff = m->opt.effects;
  const int in[2] = {(eff & RPS3_EFF_PLATFORM_INERTIA) != 0,
                     (eff & RPS3_EFF_LINK_INERTIA) != 0};
  const int gr[2] = {(eff & RPS3_EFF_PLATFORM_GRAVITY) != 0,
                     (eff & RPS3_EFF_LINK_GRAVITY) != 0};
  const double zero[3] = {0.0, 0.0, 0.0};
  double e[3][3], om[3], rho[3], vb[3], bt, bp;
  int i, k;
  for (k = 0; k < 3; k++)
    for (i = 0; i < 3; i++) e[k][i] = d->rot[i][k];
  body_energy(m->std[0], M3C(e), d->vc, d->omega, d->c[2], m->g, &bt, &bp);
  *t += in[0] ? bt : 0.0;
  *p += gr[0] ? bp : 0.0;
  if (!in[1] && !gr[1]) return;
  for (i = 0; i < 3; i++) {
    v3_copy(e[0], d->phi[i]);
    v3_copy(e[1], m->axis[i]);
    v3_cross(e[2], d->phi[i], m->axis[i]);
    v3_scale(om, d->dtheta[i], m->axis[i]);
    body_energy(m->std[1 + 2 * i], M3C(e), zero, om, m->pin[i][2], m->g, &bt,
                &bp);
    *t += in[1] ? bt : 0.0;
    *p += gr[1] ? bp : 0.0;
    v3_sub(rho, d->b[i], d->c);
    v3_cross(vb, d->omega, rho);
    v3_axpy(vb, vb, 1.0, d->vc);
    body_energy(m->std[2 + 2 * i], M3C(e), vb, om, d->b[i][2], m->g, &bt, &bp);
    *t += in[1] ? bt : 0.0;
    *p += gr[1] ? bp : 0.0;
  }
}

int rps3_energy(const rps3_model *m, const rps3_data *d, double *T, double *P,
                double *fric) {
  const int eff = (m != NULL) ? m->opt.effects : 0;
  const int paper = m != NULL && m->bodies != RPS3_BODIES_GENERAL;
  double t = 0.0, p = 0.0, f = 0.0, Iw[3][3], w[3], s[3], v[3];
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if ((d->stage & (RPS3_STAGE_POS | RPS3_STAGE_VEL)) !=
      (RPS3_STAGE_POS | RPS3_STAGE_VEL))
    return RPS3_ESTATE;
  if (!paper) general_energy(m, d, &t, &p);
  if (paper && (eff & RPS3_EFF_PLATFORM_INERTIA)) {
    rps3_fd_inertia_world(Iw, M3C(d->rot), m->Ip);
    m3_mulv(w, M3C(Iw), d->omega);
    t += 0.5 * m->M * v3_dot(d->vc, d->vc) + 0.5 * v3_dot(d->omega, w);
  }
  if (paper && (eff & RPS3_EFF_PLATFORM_GRAVITY)) p += m->M * m->g * d->c[2];
  if (eff & RPS3_EFF_PAYLOAD) {
    m3_mulv(s, M3C(d->rot), m->payload.com);
    v3_cross(v, d->omega, s);
    v3_axpy(v, v, 1.0, d->vc);
    rps3_fd_inertia_world(Iw, M3C(d->rot), m->payload.inertia);
    m3_mulv(w, M3C(Iw), d->omega);
    t += 0.5 * m->payload.mass * v3_dot(v, v) + 0.5 * v3_dot(d->omega, w);
    p += m->payload.mass * m->g * (d->c[2] + s[2]);
  }
  for (i = 0; i < 3; i++) {
    if (paper && (eff & RPS3_EFF_LINK_INERTIA))
      t += 0.5 * m->Jlink * d->dtheta[i] * d->dtheta[i];
    /* sin theta_i is phi_i's Z component (29) */
    if (paper && (eff & RPS3_EFF_LINK_GRAVITY))
      p += m->m * m->g * m->d * d->phi[i][2];
    if (eff & RPS3_EFF_PIN_FRICTION)
      f += rps3_friction_torque(m, i, d->dtheta[i]) * d->dtheta[i];
    if (eff & RPS3_EFF_PRISMATIC_FRICTION)
      f -= rps3_friction_law(&m->leg[i].prismatic, d->dl[i]) * d->dl[i];
  }
  if (T != NULL) *T = t;
  if (P != NULL) *P = p;
  if (fric != NULL) *fric = f;
  /* d is read-only here: the status alone says an energy overflowed */
  if (!(isfinite(t) && isfinite(p) && isfinite(f))) return RPS3_ERANGE;
  return RPS3_OK;
}
