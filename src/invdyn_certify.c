/*
 * invdyn_certify.c - the energy-rate certificate of the inverse dynamics
 * (rps3_invdyn, RPS3_OUT_CERTIFY): the power the actuators and the
 * friction put in against d(T + P)/dt, each written from the motion, not
 * from the forces it checks.
 */
#include "internal.h"
#include "linalg.h"
#include "power.h"

#define friction_torque rps3_friction_torque

/*
 * Energy-rate certificate: sum F_i l_i' + sum T_i theta_i' = d(T + P)/dt,
 * with T and P of the selected effects written from the Cartesian motion
 * (vc, omega, their derivatives) and the link rates, independently of the
 * force computation.  Each effect's term and its share of the scale are
 * the macros of src/power.h, which the batch kernel compiles too.
 */
/* the general bodies' terms of the certificate (bodies.c): the platform
   about its centre, each leg's cylinder about its pin and piston about
   its ball joint, whose motion is the platform's (b' = vc + omega x rho) */
static void certify_general(const rps3_model *m, const rps3_data *d,
                            double *dT, double *dP, double *scale) {
  const int eff = m->opt.effects;
  const int sel[2] = {(eff & RPS3_EFF_PLATFORM_INERTIA) != 0,
                      (eff & RPS3_EFF_LINK_INERTIA) != 0};
  const int gsel[2] = {(eff & RPS3_EFF_PLATFORM_GRAVITY) != 0,
                       (eff & RPS3_EFF_LINK_GRAVITY) != 0};
  const double zero[3] = {0.0, 0.0, 0.0};
  double e[3][3], pT, pP, s, rho[3], vb[3], ab[3], om[3], dom[3], t[3];
  int i, k;
  for (k = 0; k < 3; k++)
    for (i = 0; i < 3; i++) e[k][i] = d->rot[i][k];
  rps3_body_power(m->std[0], M3C(e), d->vc, d->ac, d->omega, d->domega, m->g,
                  &pT, &pP, &s);
  *dT += sel[0] ? pT : 0.0;
  *dP += gsel[0] ? pP : 0.0;
  *scale += (sel[0] || gsel[0]) ? s : 0.0;
  if (!sel[1] && !gsel[1]) return;
  for (i = 0; i < 3; i++) {
    v3_copy(e[0], d->phi[i]);
    v3_copy(e[1], m->axis[i]);
    v3_cross(e[2], d->phi[i], m->axis[i]);
    v3_scale(om, d->dtheta[i], m->axis[i]);
    v3_scale(dom, d->ddtheta[i], m->axis[i]);
    rps3_body_power(m->std[1 + 2 * i], M3C(e), zero, zero, om, dom, m->g, &pT,
                    &pP, &s);
    *dT += sel[1] ? pT : 0.0;
    *dP += gsel[1] ? pP : 0.0;
    *scale += s;
    v3_sub(rho, d->b[i], d->c);
    v3_cross(t, d->omega, rho);
    v3_axpy(vb, d->vc, 1.0, t);
    v3_cross(ab, d->domega, rho);
    v3_axpy(ab, ab, 1.0, d->ac);
    v3_cross(t, d->omega, t);
    v3_axpy(ab, ab, 1.0, t);
    rps3_body_power(m->std[2 + 2 * i], M3C(e), vb, ab, om, dom, m->g, &pT, &pP,
                    &s);
    *dT += sel[1] ? pT : 0.0;
    *dP += gsel[1] ? pP : 0.0;
    *scale += s;
  }
}

void rps3_certify(const rps3_model *m, rps3_data *d) {
  const int eff = m->opt.effects;
  double dT = 0.0, dP = 0.0, fp = 0.0, pw, scale, p, s, ax[3][3], cz[3];
  int i, k;
  /* the platform's axes r_k (the columns of rot) and cos theta_i */
  for (i = 0; i < 3; i++) {
    for (k = 0; k < 3; k++) ax[k][i] = d->rot[i][k];
    cz[i] = d->dphi[i][2];
  }
  RPS3_POWER_ACTUATORS(RPS3_V3C, d->F, d->dl, pw, scale);
  if (m->bodies == RPS3_BODIES_GENERAL)
    certify_general(m, d, &dT, &dP, &scale);
  if (m->bodies == RPS3_BODIES_PAPER && (eff & RPS3_EFF_PLATFORM_GRAVITY)) {
    RPS3_POWER_BODY_GRAVITY(m->M * m->g, d->vc[2], p, s);
    dP += p;
    scale += s;
  }
  if (m->bodies == RPS3_BODIES_PAPER && (eff & RPS3_EFF_PLATFORM_INERTIA)) {
    RPS3_POWER_BODY_INERTIA(RPS3_V3C, m->M, 1.0, m->Ip, ax[0], ax[1], ax[2],
                            d->vc, d->ac, d->omega, d->domega, p, s);
    dT += p;
    scale += s;
  }
  if (eff & RPS3_EFF_PAYLOAD) {
    double rg[3], vg[3], ag[3];
    rps3_payload_kin(m, d, rg, vg, ag);
    RPS3_POWER_BODY_INERTIA(RPS3_V3C, m->payload.mass, 1.0, m->payload.inertia,
                            ax[0], ax[1], ax[2], vg, ag, d->omega, d->domega, p,
                            s);
    dT += p;
    scale += s;
    RPS3_POWER_BODY_GRAVITY(m->payload.mass * m->g, vg[2], p, s);
    dP += p;
    scale += s;
  }
  if (m->bodies == RPS3_BODIES_PAPER && (eff & RPS3_EFF_LINK_GRAVITY)) {
    RPS3_POWER_LINK_GRAVITY(RPS3_V3C, RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d),
                            cz, d->dtheta, p, s);
    dP += p;
    scale += s;
  }
  if (m->bodies == RPS3_BODIES_PAPER && (eff & RPS3_EFF_LINK_INERTIA)) {
    RPS3_POWER_LINK_INERTIA(RPS3_V3C, m->Jlink, d->dtheta, d->ddtheta, p, s);
    dT += p;
    scale += s;
  }
  if (eff & RPS3_EFF_PIN_FRICTION) {
    double Tf[3];
    for (i = 0; i < 3; i++) Tf[i] = friction_torque(m, i, d->dtheta[i]);
    RPS3_POWER_PIN_FRICTION(RPS3_V3C, Tf, d->dtheta, fp, s);
    scale += s;
  }
  if (eff & RPS3_EFF_PRISMATIC_FRICTION)
    /* the force the actuators overcome: power they put in and lose */
    for (i = 0; i < 3; i++) {
      p = -rps3_friction_law(&m->leg[i].prismatic, d->dl[i]) * d->dl[i];
      fp += p;
      scale += fabs(p);
    }
  d->power = pw;
  d->dTdt = dT;
  d->dPdt = dP;
  d->friction_power = fp;
  d->energy_residual = RPS3_POWER_RESIDUAL(pw + fp, dT, dP);
  d->energy_scale = scale;
}

