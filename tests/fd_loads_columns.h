/*
 * fd_loads_columns.h - the forward dynamics' Mq and hq formed from the
 * loads of src/loads.h, the inverse dynamics' own pieces, by virtual
 * power: a test oracle for assemble (src/fwddyn_plane.h), which forms the
 * same numbers in its Gram form (src/fwddyn.c's header).
 *
 * In the links' planes, phi_i = (-cos_i u_i, sin_i) and dphi_i = (sin_i
 * u_i, cos_i) (29).  The inverse dynamics' (34) is F = wl + (df/dl)^T
 * lambda with (df/dtheta)^T lambda = -wt, that is F = wl + G^T wt (G =
 * -(df/dtheta)^-1 df/dl), for the loads (wl, wt) of every selected
 * effect at the state's accelerations.  F = Mq l'' + hq is linear in l'',
 * so
 *   hq = the loads at the bias accelerations (l'' = 0): c'' = ac_bias,
 *        theta'' = theta''_bias, b_i'' = -l_i theta_i'^2 phi_i + (2 l_i'
 *        theta_i' + l_i theta_i''_bias) dphi_i ((12)-(14));
 *   Mq e_j = the inertia loads at l'' = e_j with the rates zero: c'' =
 *        Jc e_j, theta'' = G e_j, b_i'' = [i = j] phi_i + l_i G_ij dphi_i.
 * With phi.phi = dphi.dphi = 1 and phi.dphi = 0 these columns are the
 * Gram form's (M/6) I + G^T diag(Jlink + (M/6) l^2) G + (M/2) Jc^T Jc and
 * its bias; this form costs about twice the Gram form's flops (docs/
 * library.md, "The formulation"), which is why the library keeps the
 * latter and the tests hold it to this one (test_fd_loads.c).
 *
 * The payload's terms are rps3_fd_add_body's in both (src/fwddyn_body.c).
 * Each entry also gets the sum of the absolute values of its terms, the
 * scale its rounding is measured against.
 */
#ifndef RPS3_FD_LOADS_COLUMNS_H
#define RPS3_FD_LOADS_COLUMNS_H

#include "fwddyn_plane.h" /* plane, rps3_fd_add_body */
#include "loads.h"

/* the links' directions (29) in world axes from the plane */
static void fdl_dirs(const rps3_model *m, const plane *p, double phi[3][3],
                     double dphi[3][3]) {
  int i;
  for (i = 0; i < 3; i++) {
    const double c = p->q.c[i], s = p->q.s[i];
    phi[i][0] = -c * m->radial[i][0];
    phi[i][1] = -c * m->radial[i][1];
    phi[i][2] = s;
    dphi[i][0] = s * m->radial[i][0];
    dphi[i][1] = s * m->radial[i][1];
    dphi[i][2] = c;
  }
}

/* F = wl + G^T wt for the loads (wl, wt) of the links, and its scale */
static void fdl_force(const plane *p, const double wl[3], const double wt[3],
                      double F[3], double scale[3]) {
  int i, j;
  for (j = 0; j < 3; j++) {
    F[j] = wl[j];
    scale[j] = fabs(wl[j]);
    for (i = 0; i < 3; i++) {
      F[j] += p->G[i][j] * wt[i];
      scale[j] += fabs(p->G[i][j] * wt[i]);
    }
  }
}

/* the loads of link i of the selected effects at the accelerations cdd
   (centre), bdd (ball joint), ddth (theta_i''); with `rates` the
   velocity-dependent ones too (the pin friction at theta_i'), gravity
   with `gravity` */
static void fdl_link(const rps3_model *m, const plane *p, int i,
                     const double phi[3], const double dphi[3],
                     const double cdd[3], const double bdd[3], double ddth,
                     int gravity, double *wl, double *wt) {
  const int eff = m->opt.effects;
  const double l = p->q.l[i];
  double a = 0.0, b = 0.0, w;
  if (eff & RPS3_EFF_PLATFORM_INERTIA)
    RPS3_LOAD_PLATFORM_INERTIA(RPS3_V3C, RPS3_DISC_BALL_MASS(m->M), cdd, bdd,
                               phi, dphi, l, a, b);
  if (eff & RPS3_EFF_LINK_INERTIA) {
    RPS3_LOAD_LINK_INERTIA(m->Jlink, ddth, w);
    b += w;
  }
  if (gravity && (eff & RPS3_EFF_PLATFORM_GRAVITY)) {
    double v;
    RPS3_LOAD_PLATFORM_GRAVITY(RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g), phi[2],
                               dphi[2], l, w, v);
    a += w;
    b += v;
  }
  if (gravity && (eff & RPS3_EFF_LINK_GRAVITY)) {
    RPS3_LOAD_LINK_GRAVITY(RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d), dphi[2],
                           w);
    b += w;
  }
  if (gravity && (eff & RPS3_EFF_PIN_FRICTION)) {
    RPS3_LOAD_PIN_FRICTION(rps3_friction_torque(m, i, p->dth[i]), w);
    b += w;
  }
  *wl = a;
  *wt = b;
}

/* Mq and hq of m's selected effects at the plane p (a state's kept
   kinematics, rps3_fd_state.kin) with k's maps for a payload and d's
   rot, omega; sM and sh their scales (a payload's terms not in them) */
static void fd_loads_columns(const rps3_model *m, const rps3_data *d,
                             const rps3_fd_state *k, const plane *p,
                             double Mq[3][3], double hq[3], double sM[3][3],
                             double sh[3]) {
  double phi[3][3], dphi[3][3], wl[3], wt[3], col[3], sc[3];
  int i, j, q;
  fdl_dirs(m, p, phi, dphi);
  for (i = 0; i < 3; i++) {
    const double l = p->q.l[i], th = p->dth[i];
    const double a = -l * th * th, b = 2.0 * p->dl[i] * th + l * p->ddb[i];
    double bdd[3];
    for (q = 0; q < 3; q++) bdd[q] = a * phi[i][q] + b * dphi[i][q];
    fdl_link(m, p, i, phi[i], dphi[i], p->acb, bdd, p->ddb[i], 1, &wl[i],
             &wt[i]);
  }
  fdl_force(p, wl, wt, hq, sh);
  for (j = 0; j < 3; j++) {
    const double cdd[3] = {p->Jc[0][j], p->Jc[1][j], p->Jc[2][j]};
    for (i = 0; i < 3; i++) {
      double bdd[3];
      for (q = 0; q < 3; q++)
        bdd[q] =
            (i == j ? phi[i][q] : 0.0) + p->q.l[i] * p->G[i][j] * dphi[i][q];
      fdl_link(m, p, i, phi[i], dphi[i], cdd, bdd, p->G[i][j], 0, &wl[i],
               &wt[i]);
    }
    fdl_force(p, wl, wt, col, sc);
    for (q = 0; q < 3; q++) {
      Mq[q][j] = col[q];
      sM[q][j] = sc[q];
    }
  }
  if (m->opt.effects & RPS3_EFF_PAYLOAD) {
    double sp[3], Iw[3][3];
    for (q = 0; q < 3; q++)
      sp[q] = d->rot[q][0] * m->payload.com[0] +
              d->rot[q][1] * m->payload.com[1] +
              d->rot[q][2] * m->payload.com[2];
    rps3_fd_inertia_world(Iw, (const double(*)[3])d->rot, m->payload.inertia);
    rps3_fd_add_body(k, d, m->payload.mass, sp, (const double(*)[3])Iw, m->g,
                     Mq, hq);
  }
}

#endif /* RPS3_FD_LOADS_COLUMNS_H */
