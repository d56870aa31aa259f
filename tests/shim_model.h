/*
 * shim_model.h - the model of the test shims (oracle_shim.c, sim_shim.c)
 * from a flat vector of its input parameters, so that the Python side never
 * mirrors a struct layout:
 *   par = (R, rho, M, m, d, link_Ic, g, payload mass, com x3, inertia x3,
 *          viscous, coulomb, prismatic viscous, prismatic coulomb):
 *   RPS3_SHIM_NPAR numbers.
 */
#ifndef RPS3_TESTS_SHIM_MODEL_H
#define RPS3_TESTS_SHIM_MODEL_H

#include "rps3.h"

#define RPS3_SHIM_NPAR 18

/* Table II with par's values and the effects; not initialised */
static void shim_model(rps3_model *m, const double *par, int effects) {
  int k;
  rps3_model_default(m);
  m->R = par[0];
  m->rho = par[1];
  m->M = par[2];
  m->m = par[3];
  m->d = par[4];
  m->link_Ic = par[5];
  m->g = par[6];
  m->payload.mass = par[7];
  for (k = 0; k < 3; k++) {
    m->payload.com[k] = par[8 + k];
    m->payload.inertia[k] = par[11 + k];
  }
  m->friction.viscous = par[14];
  m->friction.coulomb = par[15];
  for (k = 0; k < 3; k++) {
    m->leg[k].prismatic.viscous = par[16];
    m->leg[k].prismatic.coulomb = par[17];
  }
  m->opt.effects = effects;
}

#endif /* RPS3_TESTS_SHIM_MODEL_H */
