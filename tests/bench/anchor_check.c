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
 * accuracy study covers.
 *
 * The batched anchor (rps3_anchor_forces_batch: the same generated
 * assignments in a vectorised loop over structures of arrays, the benchmark's
 * anchor_generated_batch) is held to the scalar one on the same states in
 * one call: the same operations in the same order (no contraction into
 * FMA), the sines and cosines libm's or glibc's vector ones, so the same
 * forces to TOL_BATCH and the same status.  Prints three lines and exits 0
 * or 1.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "anchor_gen.h"
#include "rps3.h"

#define NSTATE 21001 /* the helix's 1001 points and 20000 random states */
/* batched against scalar anchor, relative to the scale of the
   comparison with the library (sum_e |F_effect|): the same operations in
   the same order (the same bits with libm's scalar sines), but with
   libmvec the sines and cosines are glibc's vector ones, within 4 ulp of
   its scalar ones, and the forces' sensitivity to the pose angles
   amplifies that where dl/dq is near singular: measured 2.5e-13 at the
   edge of the sampled workspace (beta 0.59, z_c 0.16 m, |F| 900 N), below
   5e-14 elsewhere */
#define TOL_BATCH 1e-12

/* uniform in [lo, hi) from a fixed LCG: the same points on every machine */
static double uni(unsigned long long *s, double lo, double hi) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return lo + (hi - lo) * (double)(*s >> 11) / 9007199254740992.0;
}

/* compare one state; returns the largest normalized error, or -1 when one
   side fails (not counted: a pose outside the workspace); the scales of
   the three forces go to scale (0 when the library fails) */
static double compare(const rps3_model *m, rps3_data *d, const double par[6],
                      double scale[3]) {
  double F[3], worst = 0.0;
  int i, e;
  scale[0] = scale[1] = scale[2] = 0.0;
  if (rps3_inverse(m, d) != RPS3_OK) return -1.0;
  for (i = 0; i < 3; i++)
    for (e = 0; e < RPS3_NEFFECT; e++) scale[i] += fabs(d->F_effect[e][i]);
  if (rps3_anchor_forces(par, d->pose, d->dpose, d->ddpose, F) != 0)
    return -1.0;
  for (i = 0; i < 3; i++) {
    double err = fabs(F[i] - d->F[i]) / scale[i];
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

/* the batched anchor over the states of soa (component-major, 9 NSTATE:
   pose, dpose, ddpose) against the scalar one, each force's difference
   over scale[3 k + i] (the library's sum_e |F_effect|, or the largest
   |F_i| of the state where the library fails); returns the largest, or 1
   when a status differs (printed) */
static double batch_check(const double par[6], const double *soa,
                          const double *fscale) {
  static double F[3 * NSTATE];
  static int st[NSTATE];
  double worst = 0.0;
  int i, c;
  const int n = NSTATE;
  rps3_anchor_forces_batch(par, n, soa, soa + 3 * n, soa + 6 * n, F, st);
  for (i = 0; i < n; i++) {
    double pose[3], dpose[3], ddpose[3], Fs[3], scale = 0.0;
    int s;
    for (c = 0; c < 3; c++) {
      pose[c] = soa[c * n + i];
      dpose[c] = soa[(3 + c) * n + i];
      ddpose[c] = soa[(6 + c) * n + i];
    }
    s = rps3_anchor_forces(par, pose, dpose, ddpose, Fs);
    if (s != st[i]) {
      fprintf(stderr, "anchor-check: state %d: batch status %d, scalar %d\n",
              i, st[i], s);
      return 1.0;
    }
    if (s != 0) continue;
    for (c = 0; c < 3; c++)
      if (fabs(Fs[c]) > scale) scale = fabs(Fs[c]);
    for (c = 0; c < 3; c++) {
      double sc = fscale[3 * i + c] > 0.0 ? fscale[3 * i + c] : scale;
      double e = fabs(F[c * n + i] - Fs[c]) / sc;
      if (!(e <= worst)) worst = e; /* NaN propagates as a failure */
    }
  }
  return worst;
}

/* state k of the run into the structures of arrays */
static void put(double *soa, long k, const rps3_data *d) {
  int c;
  for (c = 0; c < 3; c++) {
    soa[c * NSTATE + k] = d->pose[c];
    soa[(3 + c) * NSTATE + k] = d->dpose[c];
    soa[(6 + c) * NSTATE + k] = d->ddpose[c];
  }
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
  static double soa[9 * NSTATE]; /* every state, for the batched anchor */
  static double fscale[3 * NSTATE]; /* ... and its forces' scales */
  double bworst;

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
    put(soa, k, d);
    e = compare(&m, d, par, fscale + 3 * k);
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
    put(soa, 1001 + k, d);
    e = compare(&m, d, par, fscale + 3 * (1001 + k));
    if (e < 0.0) {
      skipped++;
      continue;
    }
    if (!(e <= worst)) worst = keep(e, d, at);
    n++;
  }
  rps3_data_free(d);
  bworst = batch_check(par, soa, fscale);
  printf("anchor-check: %ld states (%ld outside the workspace skipped): "
         "largest |F_anchor - F_rps3| / sum_e |F_e| = %.3g (tol %.3g) %s\n",
         n, skipped, worst, tol, worst <= tol ? "PASS" : "FAIL");
  printf("anchor-check: largest at pose (%.17g, %.17g, %.17g), rates "
         "(%.17g, %.17g, %.17g), accelerations (%.17g, %.17g, %.17g)\n",
         at[0], at[1], at[2], at[3], at[4], at[5], at[6], at[7], at[8]);
  printf("anchor-check: batched anchor, %d states in one call: largest "
         "|F_batch - F_anchor| / sum_e |F_e| = %.3g (tol %.3g) %s\n",
         NSTATE, bworst, TOL_BATCH, bworst <= TOL_BATCH ? "PASS" : "FAIL");
  return worst <= tol && bworst <= TOL_BATCH ? 0 : 1;
}
