/*
 * ident_std.c - the regressor of the general model's standard parameters
 * (rps3.h, RPS3_NSTD): F = Y pi, ten per body and the friction of every
 * joint.
 *
 * As the paper model's (ident.c), a column is the load of one unit
 * parameter pushed through the formulation's own solve: a copy of the
 * model with the general bodies (RPS3_BODIES_GENERAL) whose standard
 * parameters are all zero but one, its loads computed by the selected
 * method (invdyn.c, invdyn_ne.c, bodies.c), every column solved with the
 * one factorization.  The bodies' loads are linear in their standard
 * parameters (bodies.c), so the columns are exact, not differences.
 */
#include <stdint.h>
#include <string.h>

#include "ident_int.h"
#include "internal.h"
#include "links.h"

static const char *const param_units[10] = {
    "kg",     "kg m",   "kg m",   "kg m",   "kg m^2",
    "kg m^2", "kg m^2", "kg m^2", "kg m^2", "kg m^2"};
/* the friction columns after the bodies': prismatic then pin, leg by
   leg, (viscous, Coulomb) */
#define NBODYCOL (10 * RPS3_NBODY)
static const char *const friction_names[RPS3_NSTD - NBODYCOL] = {
    "prismatic1.fv", "prismatic1.fc", "prismatic2.fv", "prismatic2.fc",
    "prismatic3.fv", "prismatic3.fc", "pin1.fv",       "pin1.fc",
    "pin2.fv",       "pin2.fc",       "pin3.fv",       "pin3.fc"};
static const char *const friction_units[2][2] = {{"N s/m", "N"},
                                                 {"N m s/rad", "N m"}};

/* the bodies' names, "platform.m", ..., "piston3.Izz" */
#define NAME_LEN 24
static const char std_names[NBODYCOL][NAME_LEN] = {
#define R(b)                                                          \
  b ".m", b ".mcx", b ".mcy", b ".mcz", b ".Ixx", b ".Ixy", b ".Ixz", \
      b ".Iyy", b ".Iyz", b ".Izz"
    R("platform"),  R("cylinder1"), R("piston1"), R("cylinder2"),
    R("piston2"),   R("cylinder3"), R("piston3")
#undef R
};

const char *rps3_std_name(int k) {
  if (k < 0 || k >= RPS3_NSTD) return NULL;
  return k < NBODYCOL ? std_names[k] : friction_names[k - NBODYCOL];
}

const char *rps3_std_unit(int k) {
  if (k < 0 || k >= RPS3_NSTD) return NULL;
  if (k < NBODYCOL) return param_units[k % 10];
  k -= NBODYCOL;
  return friction_units[k / 6][k % 2];
}

/* a body's ten from its mass, centre of mass and inertia about it
   (model.c) */
static void std_of(double mass, const double c[3], const double Ic[6],
                   double p[10]) {
  rps3_body b;
  b.mass = mass;
  memcpy(b.com, c, sizeof b.com);
  memcpy(b.inertia, Ic, sizeof b.inertia);
  rps3_body_std(&b, p);
}

int rps3_std_params(const rps3_model *m, double pi[RPS3_NSTD]) {
  int b, i, k;
  if (m == NULL || !m->valid || pi == NULL) return RPS3_EINVAL;
  if (m->bodies == RPS3_BODIES_GENERAL) {
    for (b = 0; b < RPS3_NBODY; b++)
      for (k = 0; k < 10; k++) pi[10 * b + k] = m->std[b][k];
  } else {
    /* the paper's: the disc (21), each link a point mass m at d on its
       axis e1 with link_Ic about the pin axis (and about e3, which does
       not act), massless pistons */
    const double zero[3] = {0.0, 0.0, 0.0}, cd[3] = {m->d, 0.0, 0.0};
    const double disc[6] = {m->Ip[0], 0.0, 0.0, m->Ip[1], 0.0, m->Ip[2]};
    const double link[6] = {0.0, 0.0, 0.0, m->link_Ic, 0.0, m->link_Ic};
    memset(pi, 0, NBODYCOL * sizeof(double));
    std_of(m->M, zero, disc, pi);
    for (i = 0; i < 3; i++) std_of(m->m, cd, link, pi + 10 * (1 + 2 * i));
  }
  if (m->opt.effects & RPS3_EFF_PAYLOAD) {
    /* the payload is part of the platform's body: its principal moments
       along the platform axes, by parallel axes to the centre */
    const rps3_payload *p = &m->payload;
    const double Ic[6] = {p->inertia[0], 0.0, 0.0, p->inertia[1], 0.0,
                          p->inertia[2]};
    double q[10];
    std_of(p->mass, p->com, Ic, q);
    for (k = 0; k < 10; k++) pi[k] += q[k];
  }
  for (i = 0; i < 3; i++) {
    pi[NBODYCOL + 2 * i] = m->leg[i].prismatic.viscous;
    pi[NBODYCOL + 2 * i + 1] = m->leg[i].prismatic.coulomb;
    pi[NBODYCOL + 6 + 2 * i] = m->pinf[i].viscous;
    pi[NBODYCOL + 6 + 2 * i + 1] = m->pinf[i].coulomb;
  }
  return RPS3_OK;
}

/* u: m's geometry and options with every parameter zero (general bodies,
   no payload, no friction), the friction laws' regularisation kept */
static void zero_params(const rps3_model *m, rps3_model *u) {
  int i;
  *u = *m;
  u->bodies = RPS3_BODIES_GENERAL;
  memset(u->std, 0, sizeof u->std);
  memset(&u->payload, 0, sizeof u->payload);
  for (i = 0; i < 3; i++) {
    u->leg[i].prismatic.viscous = u->leg[i].prismatic.coulomb = 0.0;
    u->pinf[i].viscous = u->pinf[i].coulomb = 0.0;
  }
}

/* a unit friction law: viscous (k = 0) or Coulomb (k = 1), f's
   regularisation */
static double unit_law(const rps3_friction *f, int k, double v) {
  rps3_friction u = *f;
  u.viscous = k == 0 ? 1.0 : 0.0;
  u.coulomb = k == 1 ? 1.0 : 0.0;
  return rps3_friction_law(&u, v);
}

/* the columns of leg i's bodies and friction: its loads per unit
   parameter (bodies.c, the forces' own rows), through the forces of unit
   leg loads Fb */
static void leg_columns(const rps3_model *m, const rps3_data *d, int i,
                        const double Fb[3][6], double Y[3][RPS3_NSTD]) {
  const int eff = m->opt.effects;
  double WL[20], WT[20], wl[20], wt[20], bdd[3];
  int k, r, col;
  for (k = 0; k < 20; k++) wl[k] = wt[k] = 0.0;
  if (eff & RPS3_EFF_LINK_GRAVITY) {
    rps3_leg_rows(m, i, d->phi[i], d->dphi[i], d->l[i], 0.0, 0.0, NULL, m->g,
                  WL, WT);
    for (k = 0; k < 20; k++) {
      wl[k] += WL[k];
      wt[k] += WT[k];
    }
  }
  if (eff & RPS3_EFF_LINK_INERTIA) {
    RPS3_BALL_ACC_JOINTS(RPS3_V3C, d->phi[i], d->dphi[i], d->l[i], d->dl[i],
                         d->dtheta[i], d->ddl[i], d->ddtheta[i], bdd);
    rps3_leg_rows(m, i, d->phi[i], d->dphi[i], d->l[i], d->dtheta[i],
                  d->ddtheta[i], bdd, 0.0, WL, WT);
    for (k = 0; k < 20; k++) {
      wl[k] += WL[k];
      wt[k] += WT[k];
    }
  }
  for (k = 0; k < 20; k++) {
    col = 10 * (1 + 2 * i) + k; /* cylinder i, then piston i */
    for (r = 0; r < 3; r++)
      Y[r][col] = Fb[r][i] * wl[k] + Fb[r][3 + i] * wt[k];
  }
  for (k = 0; k < 2; k++) {
    /* prismatic friction on l_i, pin friction on theta_i (-T, src/loads.h) */
    const double fp = (eff & RPS3_EFF_PRISMATIC_FRICTION)
                          ? unit_law(&m->leg[i].prismatic, k, d->dl[i])
                          : 0.0;
    const double ft = (eff & RPS3_EFF_PIN_FRICTION)
                          ? unit_law(&m->pinf[i], k, d->dtheta[i])
                          : 0.0;
    for (r = 0; r < 3; r++) {
      Y[r][NBODYCOL + 2 * i + k] = Fb[r][i] * fp;
      Y[r][NBODYCOL + 6 + 2 * i + k] = Fb[r][3 + i] * ft;
    }
  }
}

int rps3_regressor_std(const rps3_model *m, rps3_data *d,
                       double Y[3][RPS3_NSTD]) {
  rps3_cjac J;
  rps3_loads L;
  rps3_model u;
  double rhs[10][6], Fp[3][10], Fb[3][6];
  int status, i, k;
  if (Y != NULL)
    for (i = 0; i < 3; i++)
      for (k = 0; k < RPS3_NSTD; k++) Y[i][k] = (double)NAN;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (Y == NULL) RPS3_ERROR(d, RPS3_EINVAL, "regressor: Y is NULL");
  status = rps3_inverse_motion(m, d, &J, rps3_need_rates(m));
  if (status != RPS3_OK) return status;
  /* the general platform's loads need the frame's accelerations whatever
     m's bodies: prepare with a general copy */
  zero_params(m, &u);
  status = rps3_loads_prepare(&u, d, &J, &L);
  if (status != RPS3_OK) return status;
  rps3_regressor_unset(d);

  /* the platform: its loads with one unit parameter, solved together */
  for (k = 0; k < 10; k++) {
    u.std[0][k] = 1.0;
    rps3_loads_column(m, &u, d, &L,
                      RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA,
                      rhs[k]);
    u.std[0][k] = 0.0;
  }
  rps3_loads_solve(&L, 10, rhs, &Fp[0][0], 10);
  for (i = 0; i < 3; i++)
    for (k = 0; k < 10; k++) Y[i][k] = Fp[i][k];
  /* the legs: each column a load on one leg's (l_i, theta_i) */
  rps3_loads_leg_basis(d, &L, Fb);
  for (i = 0; i < 3; i++)
    leg_columns(m, d, i, (const double(*)[6])Fb, Y);
  return rps3_regressor_finite(d, &Y[0][0], RPS3_NSTD, rps3_std_name);
}
