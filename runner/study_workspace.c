/*
 * study_workspace.c - rps3-study workspace: a grid over (rho, alpha, beta,
 * z_c): status of inverse kinematics + static dynamics, the condition
 * number of the lambda system, the assembly mode and the static force that
 * holds the platform (gravity effects only).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "study.h"

/* det of d f / d theta from the vector form (b_i - b_j) . l dphi */
static double det_jt(const rps3_data *d) {
  double J[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  int k, q;
  for (k = 0; k < 3; k++) {
    int i = k, j = (k + 1) % 3;
    double si = 0.0, sj = 0.0;
    for (q = 0; q < 3; q++) {
      double D = d->b[i][q] - d->b[j][q];
      si += D * d->dphi[i][q];
      sj += D * d->dphi[j][q];
    }
    J[k][i] = 2.0 * d->l[i] * si;
    J[k][j] = -2.0 * d->l[j] * sj;
  }
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

static void linspace(double *v, size_t n, double a, double b) {
  size_t k;
  for (k = 0; k < n; k++)
    v[k] = n == 1 ? a : a + (b - a) * (double)k / (double)(n - 1);
}

int study_workspace(const char *path, const char *cmdline, int quick) {
  static const double rhos[3] = {0.3, 0.5, 0.8};
  size_t na = quick ? 13 : 25, nb = quick ? 25 : 61, nz = quick ? 20 : 60;
  size_t nr = 3, npt, ir, ia, ib, iz, p;
  double *alpha, *beta, *zc, *cond, *trans, *force, *fmax;
  int32_t *status, *mode, link[3] = {1, 2, 3};
  study_h5 o = {-1, -1};
  int rc = 0;
  double t_start = study_now_ns();
  npt = nr * na * nb * nz;
  alpha = malloc(na * sizeof(double));
  beta = malloc(nb * sizeof(double));
  zc = malloc(nz * sizeof(double));
  cond = malloc(npt * sizeof(double));
  trans = malloc(npt * sizeof(double));
  fmax = malloc(npt * sizeof(double));
  force = malloc(3 * npt * sizeof(double));
  status = malloc(npt * sizeof(int32_t));
  mode = malloc(npt * sizeof(int32_t));
  if (!alpha || !beta || !zc || !cond || !trans || !fmax || !force || !status ||
      !mode) {
    fprintf(stderr, "rps3-study: out of memory\n");
    return EXIT_IO;
  }
  /* alpha over a full turn (the mechanism repeats every 2 pi / 3), beta to
     1.2 rad, z_c from 0.1 R to 3 R */
  linspace(alpha, na, -PI, PI);
  linspace(beta, nb, 0.0, 1.2);
  linspace(zc, nz, 0.02286, 0.6858);
  for (ir = 0; ir < nr; ir++) {
    rps3_model m;
    rps3_data *d = NULL;
    char err[256];
    rps3_model_default(&m);
    m.rho = rhos[ir];
    m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
    m.opt.certify = 0;
    if (rps3_model_init(&m, err, sizeof err) != RPS3_OK ||
        rps3_data_alloc(&m, &d) != RPS3_OK) {
      fprintf(stderr, "rps3-study: workspace model: %s\n", err);
      return EXIT_IO;
    }
    for (ia = 0; ia < na; ia++)
      for (ib = 0; ib < nb; ib++)
        for (iz = 0; iz < nz; iz++) {
          int st, i;
          double home;
          p = ((ir * na + ia) * nb + ib) * nz + iz;
          /* the assembly mode of the level pose at this height */
          d->pose[0] = 0.0;
          d->pose[1] = 0.0;
          d->pose[2] = zc[iz];
          home = rps3_ik(&m, d) == RPS3_OK ? det_jt(d) : DNAN;
          d->pose[0] = alpha[ia];
          d->pose[1] = beta[ib];
          d->pose[2] = zc[iz];
          st = rps3_inverse(&m, d);
          status[p] = st;
          mode[p] = 0;
          if (st == RPS3_OK || st == RPS3_ESING) {
            double dj = det_jt(d);
            mode[p] = (dj > 0) == (home > 0) ? 1 : -1;
          }
          cond[p] = (st == RPS3_OK || st == RPS3_ESING) ? d->cond : DNAN;
          trans[p] = (st == RPS3_OK || st == RPS3_ESING) ? d->transmission
                                                         : DNAN;
          fmax[p] = st == RPS3_OK ? 0.0 : DNAN;
          for (i = 0; i < 3; i++) {
            force[3 * p + (size_t)i] = st == RPS3_OK ? d->F[i] : DNAN;
            if (st == RPS3_OK && fabs(d->F[i]) > fmax[p])
              fmax[p] = fabs(d->F[i]);
          }
        }
    rps3_data_free(d);
  }
  fprintf(stderr, "rps3-study: workspace: %zu points in %.1f s\n", npt,
          1e-9 * (study_now_ns() - t_start));

  if (study_h5_open(&o, path, cmdline,
                    "rps3-study workspace: reachability, condition number and "
                    "the static force holding the platform over (rho, alpha, "
                    "beta, z_c)") < 0)
    rc = -1;
  if (rc == 0) {
    static const char *const self[1] = {NULL};
    static const char *const grid[4] = {"rho", "alpha", "beta", "z_c"};
    static const char *const gridl[5] = {"rho", "alpha", "beta", "z_c",
                                         "link"};
    hsize_t dims[5] = {nr, na, nb, nz, 3}, d3 = 3;
    rc |= study_h5_write(&o, "rho", H5T_NATIVE_DOUBLE, 1, &dims[0], rhos, "1",
                         "rho = r / R (R = 0.2286 m, Table II)", self);
    rc |= study_h5_write(&o, "alpha", H5T_NATIVE_DOUBLE, 1, &dims[1], alpha,
                         "rad", "precession angle alpha", self);
    rc |= study_h5_write(&o, "beta", H5T_NATIVE_DOUBLE, 1, &dims[2], beta,
                         "rad", "nutation angle beta (tilt)", self);
    rc |= study_h5_write(&o, "z_c", H5T_NATIVE_DOUBLE, 1, &dims[3], zc, "m",
                         "height of the platform centre", self);
    rc |= study_h5_write(&o, "link", H5T_NATIVE_INT32, 1, &d3, link, "1",
                         "link number", self);
    rc |= study_h5_write(&o, "status", H5T_NATIVE_INT32, 4, dims, status, "1",
                         "rps3_inverse status: 0 ok, 1 unreachable (EREACH), 4 "
                         "singular (ESING, condition above cond_max = 1e13 or "
                         "transmission above trans_max = 1e8)", grid);
    rc |= study_h5_write(&o, "condition", H5T_NATIVE_DOUBLE, 4, dims, cond, "1",
                         "1-norm condition number of the lambda system "
                         "df/dtheta (NaN where unreachable); warn above 1e6",
                         grid);
    rc |= study_h5_write(&o, "transmission", H5T_NATIVE_DOUBLE, 4, dims, trans,
                         "1",
                         "force transmission: largest actuator force per unit "
                         "platform load (force, moment / R); warn above 100, "
                         "refused above 1e8 (NaN where not computed)", grid);
    rc |= study_h5_write(&o, "mode", H5T_NATIVE_INT32, 4, dims, mode, "1",
                         "assembly mode: 1 same sign of det(df/dtheta) as the "
                         "level pose at this height (reachable from it without "
                         "crossing a singularity), -1 the other side, 0 "
                         "unreachable", grid);
    rc |= study_h5_write(&o, "force", H5T_NATIVE_DOUBLE, 5, dims, force, "N",
                         "static actuating force holding the platform: "
                         "platform and link gravity (M = 0.18 kg, m = 0.09 kg, "
                         "d = 0.1524 m), positive extends the link", gridl);
    rc |= study_h5_write(&o, "max_force", H5T_NATIVE_DOUBLE, 4, dims, fmax, "N",
                         "max_i |force_i|", grid);
  }
  if (study_h5_close(&o) < 0) rc = -1;
  free(alpha);
  free(beta);
  free(zc);
  free(cond);
  free(trans);
  free(fmax);
  free(force);
  free(status);
  free(mode);
  return rc ? EXIT_IO : EXIT_OK;
}

