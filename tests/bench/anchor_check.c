/*
 * anchor_check.c - the generated anchor (tests/bench/gen_anchor.py) against
 * the library: the same forces from two independent derivations.
 *
 *   anchor-check [TOL]
 *
 * The library solves Lagrange's equations in (l, theta) with multipliers
 * (23), (34); the anchor eliminates the constraints and writes the
 * equations of motion in the pose coordinates q = (alpha, beta, z_c) by
 * virtual power, then solves (dl/dq)^T F = Q.  Both are exact, so they
 * agree to rounding amplified by the conditioning of the two 3x3 solves.
 * The error of each force is measured against the scale
 * sum_e |F_effect[e][i]| (the effects' shares may cancel in F), and the
 * run fails when the largest exceeds TOL (default 1e-13: rounding of some
 * thousand operations, times the conditioning of dl/dq and of the lambda
 * system at these poses; measured 1.7e-14).  Points: the paper's helix
 * (Table II) at 100 Hz and random states over the part of the workspace the
 * accuracy study covers.  Prints one line and exits 0 or 1.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "anchor_gen.h"
#include "rps3.h"

/* uniform in [lo, hi) from a fixed LCG: the same points on every machine */
static double uni(unsigned long long *s, double lo, double hi) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return lo + (hi - lo) * (double)(*s >> 11) / 9007199254740992.0;
}

/* compare one state; returns the largest normalized error, or -1 when one
   side fails (not counted: a pose outside the workspace) */
static double compare(const rps3_model *m, rps3_data *d, const double par[6]) {
  double F[3], worst = 0.0;
  int i, e;
  if (rps3_inverse(m, d) != RPS3_OK) return -1.0;
  if (rps3_anchor_forces(par, d->pose, d->dpose, d->ddpose, F) != 0)
    return -1.0;
  for (i = 0; i < 3; i++) {
    double scale = 0.0, err;
    for (e = 0; e < RPS3_NEFFECT; e++) scale += fabs(d->F_effect[e][i]);
    err = fabs(F[i] - d->F[i]) / scale;
    if (!(err <= worst)) worst = err; /* NaN propagates as a failure */
  }
  return worst;
}

/* note the state of a new largest difference; returns that difference */
static double keep(double e, const rps3_data *d, double at[9]) {
  int k;
  for (k = 0; k < 3; k++) {
    at[k] = d->pose[k];
    at[3 + k] = d->dpose[k];
    at[6 + k] = d->ddpose[k];
  }
  return e;
}

int main(int argc, char **argv) {
  double tol = (argc > 1) ? atof(argv[1]) : 1e-13;
  double par[6], worst = 0.0, T;
  unsigned long long seed = 2385;
  rps3_check chk;
  rps3_model m;
  rps3_traj tr;
  rps3_data *d = NULL;
  long n = 0, skipped = 0, k;
  double at[9] = {0}; /* the state of the largest difference */

  gsl_set_error_handler_off();
  rps3_model_default(&m);
  m.opt.effects = RPS3_EFF_DEFAULT; /* the paper's four effects */
  m.opt.outputs &= ~RPS3_OUT_CERTIFY;
  if (rps3_model_init(&m, &chk) != RPS3_OK ||
      rps3_data_alloc(&m, &d) != RPS3_OK) {
    fprintf(stderr, "anchor-check: model: %s\n", chk.msg);
    return 2;
  }
  par[0] = m.R;
  par[1] = m.rho;
  par[2] = m.M;
  par[3] = m.m;
  par[4] = m.d;
  par[5] = m.g;

  /* the paper's helix */
  rps3_traj_default(&tr);
  T = rps3_traj_duration(&tr);
  for (k = 0; k <= 1000; k++) {
    double e;
    rps3_traj_eval(&m, &tr, T * (double)k / 1000.0, d->pose, d->dpose,
                   d->ddpose);
    e = compare(&m, d, par);
    if (e < 0.0) {
      fprintf(stderr, "anchor-check: helix point %ld fails\n", k);
      return 1;
    }
    if (!(e <= worst)) worst = keep(e, d, at);
    n++;
  }
  /* random states: alpha anywhere, beta up to 0.6 rad, z_c 0.15-0.5 m,
     rates ~ 1/s and accelerations ~ 10/s^2 */
  for (k = 0; k < 20000; k++) {
    double e;
    d->pose[0] = uni(&seed, -3.14, 3.14);
    d->pose[1] = uni(&seed, 0.01, 0.6);
    d->pose[2] = uni(&seed, 0.15, 0.5);
    d->dpose[0] = uni(&seed, -2.0, 2.0);
    d->dpose[1] = uni(&seed, -1.0, 1.0);
    d->dpose[2] = uni(&seed, -0.3, 0.3);
    d->ddpose[0] = uni(&seed, -20.0, 20.0);
    d->ddpose[1] = uni(&seed, -10.0, 10.0);
    d->ddpose[2] = uni(&seed, -3.0, 3.0);
    e = compare(&m, d, par);
    if (e < 0.0) {
      skipped++;
      continue;
    }
    if (!(e <= worst)) worst = keep(e, d, at);
    n++;
  }
  rps3_data_free(d);
  printf("anchor-check: %ld states (%ld outside the workspace skipped): "
         "largest |F_anchor - F_rps3| / sum_e |F_e| = %.3g (tol %.3g) %s\n",
         n, skipped, worst, tol, worst <= tol ? "PASS" : "FAIL");
  printf("anchor-check: largest at pose (%.17g, %.17g, %.17g), rates "
         "(%.17g, %.17g, %.17g), accelerations (%.17g, %.17g, %.17g)\n",
         at[0], at[1], at[2], at[3], at[4], at[5], at[6], at[7], at[8]);
  return worst <= tol ? 0 : 1;
}
