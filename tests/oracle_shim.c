/*
 * oracle_shim.c - a flat C entry point for the Python oracles
 * (tests/oracle.py): the library's forces for n states, with the model given
 * as a vector of its input parameters.  Built by the tests against
 * include/rps3.h and build/librps3.so, so that the Python side never mirrors
 * a struct layout.
 *
 * par: shim_model.h.
 */
#include <stdio.h>
#include <string.h>

#include "rps3.h"
#include "shim_model.h"

int rps3_shim_npar(void);
int rps3_shim_neffect(void);
int rps3_shim_forces(const double *par, int effects, int method, int theta,
                     int n, const double *pose, const double *dpose,
                     const double *ddpose, double *F, double *F_effect,
                     int *status, char *err, int errsz);

int rps3_shim_npar(void) { return RPS3_SHIM_NPAR; }

/* the effects' shares a point of rps3_shim_forces writes */
int rps3_shim_neffect(void) { return RPS3_NEFFECT; }

/* F: n x 3; F_effect: n x RPS3_NEFFECT x 3; status: n.  Returns 0, or the
   status of model or workspace setup (message in err). */
int rps3_shim_forces(const double *par, int effects, int method, int theta,
                     int n, const double *pose, const double *dpose,
                     const double *ddpose, double *F, double *F_effect,
                     int *status, char *err, int errsz) {
  rps3_model m;
  rps3_check chk;
  rps3_data *d;
  int k, st;
  shim_model(&m, par, effects);
  m.opt.method = (rps3_method)method;
  m.opt.theta = (rps3_theta_route)theta;
  m.opt.warm_start = 1;
  st = rps3_model_init(&m, &chk);
  if (st != RPS3_OK) {
    if (err != NULL && errsz > 0) snprintf(err, (size_t)errsz, "%s", chk.msg);
    return st;
  }
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
