/*
 * oracle_shim.c - a flat C entry point for the Python oracles
 * (tests/oracle.py): the library's forces for n states, with the model given
 * as a vector of its input parameters.  Built by the tests against
 * include/rps3.h and build/librps3.so, so that the Python side never mirrors
 * a struct layout.
 *
 * par = (R, rho, M, m, d, link_Ic, g, payload mass, com x3, inertia x3,
 *        viscous, coulomb): RPS3_SHIM_NPAR numbers.
 */
#include <string.h>

#include "rps3.h"

#define RPS3_SHIM_NPAR 16

int rps3_shim_npar(void);
int rps3_shim_forces(const double *par, int effects, int method, int theta,
                     int n, const double *pose, const double *dpose,
                     const double *ddpose, double *F, double *F_effect,
                     int *status, char *err, int errsz);

int rps3_shim_npar(void) { return RPS3_SHIM_NPAR; }

/* F: n x 3; F_effect: n x RPS3_NEFFECT x 3; status: n.  Returns 0, or the
   status of model or workspace setup (message in err). */
int rps3_shim_forces(const double *par, int effects, int method, int theta,
                     int n, const double *pose, const double *dpose,
                     const double *ddpose, double *F, double *F_effect,
                     int *status, char *err, int errsz) {
  rps3_model m;
  rps3_data *d;
  int k, st;
  rps3_model_default(&m);
  m.R = par[0];
  m.rho = par[1];
  m.M = par[2];
  m.m = par[3];
  m.d = par[4];
  m.link_Ic = par[5];
  m.g = par[6];
  m.payload.mass = par[7];
  for (k = 0; k < 3; k++) {
    m.payload.com[k] = par[8 + k];
    m.payload.inertia[k] = par[11 + k];
  }
  m.friction.viscous = par[14];
  m.friction.coulomb = par[15];
  m.opt.effects = effects;
  m.opt.method = (rps3_method)method;
  m.opt.theta = (rps3_theta_route)theta;
  m.opt.warm_start = 1;
  st = rps3_model_init(&m, err, (size_t)errsz);
  if (st != RPS3_OK) return st;
  st = rps3_data_alloc(&m, &d);
  if (st != RPS3_OK) return st;
  for (k = 0; k < n; k++) {
    memcpy(d->pose, pose + 3 * k, sizeof d->pose);
    memcpy(d->dpose, dpose + 3 * k, sizeof d->dpose);
    memcpy(d->ddpose, ddpose + 3 * k, sizeof d->ddpose);
    status[k] = rps3_inverse(&m, d);
    memcpy(F + 3 * k, d->F, sizeof d->F);
    memcpy(F_effect + 3 * RPS3_NEFFECT * k, d->F_effect, sizeof d->F_effect);
  }
  rps3_data_free(d);
  return 0;
}
