/*
 * fd_gram_oracle.h - the forward dynamics' Mq and hq in Kane's form
 * written by hand in the links' planes,
 *   Mq = (M/6) I + G^T diag(Jlink + (M/6) l_i^2) G + (M/2) Jc^T Jc,
 *   hq = sigma + G^T tau + (M/2) Jc^T ac_bias + M g Jc^T e_z,
 *   sigma_i = -(M/6) l_i theta_i'^2,
 *   tau_i   = (Jlink + (M/6) l_i^2) theta_i''_bias + 2 (M/6) l_i l_i'
 *             theta_i' + m g d cos(theta_i) - T_friction,i,
 * with phi.phi = dphi.dphi = 1 and phi.dphi = 0 used by hand, the
 * coefficients and the pin torques from src/loads.h.  A
 * hand-written implementation as a test oracle (tests/test_fd_loads.c): the
 * library's Mq is this Gram form (bit for bit), its hq the loads'.
 */
#ifndef RPS3_FD_GRAM_ORACLE_H
#define RPS3_FD_GRAM_ORACLE_H

#include "fwddyn_plane.h"

static void fd_gram_oracle(const rps3_model *m, const rps3_data *d,
                           const rps3_fd_state *k, const plane *p,
                           double Mq_out[3][3], double hq_out[3]) {
  const int eff = m->opt.effects;
  const double mb =
      (eff & RPS3_EFF_PLATFORM_INERTIA) ? RPS3_DISC_BALL_MASS(m->M) : 0.0;
  const double mc = 3.0 * mb; /* M / 2 at the centre */
  const double gz = (eff & RPS3_EFF_PLATFORM_GRAVITY) ? m->M * m->g : 0.0;
  double Jp[3], tau[3], sig[3], Mq[3][3], hq[3];
  int i, j, q;
  for (i = 0; i < 3; i++) {
    const double mbl = mb * p->q.l[i];
    Jp[i] = mbl * p->q.l[i];
    tau[i] = 2.0 * mbl * p->dl[i] * p->dth[i];
    sig[i] = -mbl * p->dth[i] * p->dth[i];
    if (eff & RPS3_EFF_LINK_INERTIA) Jp[i] += m->Jlink;
    tau[i] += Jp[i] * p->ddb[i];
    /* the pin torques, loads of src/loads.h as the inverse dynamics':
       (22), d/dtheta of m g d sin(theta), and friction */
    if (eff & RPS3_EFF_LINK_GRAVITY) {
      double w;
      RPS3_LOAD_LINK_GRAVITY(RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d),
                             p->q.c[i], w);
      tau[i] += w;
    }
    if (eff & RPS3_EFF_PIN_FRICTION) {
      double w;
      RPS3_LOAD_PIN_FRICTION(rps3_friction_torque(m, i, p->dth[i]), w);
      tau[i] += w;
    }
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
    m3_mulv(sp, (const double(*)[3])d->rot, m->payload.com);
    rps3_fd_inertia_world(Iw, (const double(*)[3])d->rot, m->payload.inertia);
    rps3_fd_add_body(k, d, m->payload.mass, sp, (const double(*)[3])Iw, m->g,
                     Mq, hq);
  }
  for (j = 0; j < 3; j++) {
    for (q = 0; q < 3; q++) Mq_out[j][q] = (q >= j) ? Mq[j][q] : Mq[q][j];
    hq_out[j] = hq[j];
  }
}

#endif /* RPS3_FD_GRAM_ORACLE_H */
