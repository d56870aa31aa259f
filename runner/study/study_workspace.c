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
#include <string.h>

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

/* the grid over (rho, alpha, beta, z_c) and what each point gives */
typedef struct {
  size_t nr, na, nb, nz;
  double *alpha, *beta, *zc;   /* the axes [rad, rad, m] */
  double *cond, *trans, *fmax; /* per point */
  double *force;               /* per point and link [N] */
  int32_t *status, *mode;      /* per point */
} ws_grid;

/* the values of rho = r / R */
static const double rhos[3] = {0.3, 0.5, 0.8};

/* the grid's sizes and arrays (quick: coarse), the doubles in one block
   (g->alpha) and the int32s in another (g->status); 0 or -1 */
static int grid_alloc(ws_grid *g, int quick) {
  size_t npt;
  g->nr = 3;
  g->na = quick ? 13 : 25;
  g->nb = quick ? 25 : 61;
  g->nz = quick ? 20 : 60;
  npt = g->nr * g->na * g->nb * g->nz;
  g->alpha = malloc((g->na + g->nb + g->nz + 6 * npt) * sizeof(double));
  g->status = malloc(2 * npt * sizeof(int32_t));
  if (!g->alpha || !g->status) return -1;
  g->beta = g->alpha + g->na;
  g->zc = g->beta + g->nb;
  g->cond = g->zc + g->nz;
  g->trans = g->cond + npt;
  g->fmax = g->trans + npt;
  g->force = g->fmax + npt; /* 3 npt */
  g->mode = g->status + npt;
  /* alpha over a full turn (the mechanism repeats every 2 pi / 3), beta to
     1.2 rad, z_c from 0.1 R to 3 R */
  linspace(g->alpha, g->na, -PI, PI);
  linspace(g->beta, g->nb, 0.0, 1.2);
  linspace(g->zc, g->nz, 0.02286, 0.6858);
  return 0;
}

/* point p = (alpha[ia], beta[ib], zc[iz]) of model m */
static void grid_point(const rps3_model *m, rps3_data *d, ws_grid *g, size_t p,
                       size_t ia, size_t ib, size_t iz) {
  int st, i, reached;
  double home;
  /* the assembly mode of the level pose at this height */
  d->pose[0] = d->pose[1] = 0.0;
  d->pose[2] = g->zc[iz];
  home = rps3_ik(m, d) == RPS3_OK ? det_jt(d) : DNAN;
  d->pose[0] = g->alpha[ia];
  d->pose[1] = g->beta[ib];
  d->pose[2] = g->zc[iz];
  g->status[p] = st = rps3_inverse(m, d);
  /* reached: singular points have a pose, a mode and a conditioning */
  reached = st == RPS3_OK || st == RPS3_ESING;
  g->mode[p] = !reached ? 0 : (det_jt(d) > 0) == (home > 0) ? 1 : -1;
  g->cond[p] = reached ? d->cond : DNAN;
  g->trans[p] = reached ? d->transmission : DNAN;
  g->fmax[p] = st == RPS3_OK ? 0.0 : DNAN;
  for (i = 0; i < 3; i++) {
    g->force[3 * p + (size_t)i] = st == RPS3_OK ? d->F[i] : DNAN;
    if (st == RPS3_OK && fabs(d->F[i]) > g->fmax[p]) g->fmax[p] = fabs(d->F[i]);
  }
}

/* every point of the grid, model by model (gravity effects only); 0, or
   -1 with a message */
static int grid_compute(ws_grid *g) {
  size_t ir, ia, ib, iz;
  for (ir = 0; ir < g->nr; ir++) {
    rps3_model m;
    rps3_data *d = NULL;
    rps3_check chk;
    rps3_model_default(&m);
    m.rho = rhos[ir];
    m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
    m.opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
    if (rps3_model_init(&m, &chk) != RPS3_OK ||
        rps3_data_alloc(&m, &d) != RPS3_OK) {
      fprintf(stderr, "rps3-study: workspace model: %s\n", chk.msg);
      return -1;
    }
    for (ia = 0; ia < g->na; ia++)
      for (ib = 0; ib < g->nb; ib++)
        for (iz = 0; iz < g->nz; iz++)
          grid_point(&m, d, g, ((ir * g->na + ia) * g->nb + ib) * g->nz + iz,
                     ia, ib, iz);
    rps3_data_free(d);
  }
  return 0;
}

/* the axes and the maps; 0 or -1 */
static int grid_write(study_h5 *o, const ws_grid *g) {
  int32_t link[3] = {1, 2, 3};
  int rc = 0;
  /* the maps' axes, the first 4 of those with a link axis */
  static const char *const grid[5] = {"rho", "alpha", "beta", "z_c", "link"};
  hsize_t dims[5] = {g->nr, g->na, g->nb, g->nz, 3};
  rc |= study_h5_write(o, "rho", H5T_NATIVE_DOUBLE, 1, &dims[0], rhos, "1",
                       "rho = r / R (R = 0.2286 m, Table II)", NULL);
  rc |= study_h5_write(o, "alpha", H5T_NATIVE_DOUBLE, 1, &dims[1], g->alpha,
                       "rad", "precession angle alpha", NULL);
  rc |= study_h5_write(o, "beta", H5T_NATIVE_DOUBLE, 1, &dims[2], g->beta,
                       "rad", "nutation angle beta (tilt)", NULL);
  rc |= study_h5_write(o, "z_c", H5T_NATIVE_DOUBLE, 1, &dims[3], g->zc, "m",
                       "height of the platform centre", NULL);
  rc |= study_h5_write(o, "link", H5T_NATIVE_INT32, 1, &dims[4], link, "1",
                       "link number", NULL);
  rc |= study_h5_write(o, "status", H5T_NATIVE_INT32, 4, dims, g->status, "1",
                       "rps3_inverse status: 0 ok, 1 unreachable (EREACH), 4 "
                       "singular (ESING, condition above cond_max = 1e13 or "
                       "transmission above trans_max = 1e8)",
                       grid);
  rc |= study_h5_write(o, "condition", H5T_NATIVE_DOUBLE, 4, dims, g->cond, "1",
                       "1-norm condition number of the lambda system "
                       "df/dtheta (NaN where unreachable); warn above 1e6",
                       grid);
  rc |= study_h5_write(o, "transmission", H5T_NATIVE_DOUBLE, 4, dims, g->trans,
                       "1",
                       "force transmission: largest actuator force per unit "
                       "platform load (force, moment / R); warn above 100, "
                       "refused above 1e8 (NaN where not computed)",
                       grid);
  rc |= study_h5_write(o, "mode", H5T_NATIVE_INT32, 4, dims, g->mode, "1",
                       "assembly mode: 1 same sign of det(df/dtheta) as the "
                       "level pose at this height (reachable from it without "
                       "crossing a singularity), -1 the other side, 0 "
                       "unreachable",
                       grid);
  rc |= study_h5_write(o, "force", H5T_NATIVE_DOUBLE, 5, dims, g->force, "N",
                       "static actuating force holding the platform: "
                       "platform and link gravity (M = 0.18 kg, m = 0.09 kg, "
                       "d = 0.1524 m), positive extends the link",
                       grid);
  rc |= study_h5_write(o, "max_force", H5T_NATIVE_DOUBLE, 4, dims, g->fmax, "N",
                       "max_i |force_i|", grid);
  return rc ? -1 : 0;
}

int study_workspace(const char *path, const char *cmdline, int quick) {
  ws_grid g = {0};
  study_h5 o = {-1, -1};
  int rc = -1;
  double t_start = study_now_ns();
  if (grid_alloc(&g, quick) < 0) {
    fprintf(stderr, "rps3-study: out of memory\n");
  } else if (grid_compute(&g) == 0) {
    fprintf(stderr, "rps3-study: workspace: %zu points in %.1f s\n",
            g.nr * g.na * g.nb * g.nz, 1e-9 * (study_now_ns() - t_start));
    if (study_h5_open(&o, path, cmdline,
                      "rps3-study workspace: reachability, condition number "
                      "and the static force holding the platform over (rho, "
                      "alpha, beta, z_c)") == 0 &&
        grid_write(&o, &g) == 0)
      rc = 0;
    if (study_h5_close(&o) < 0) rc = -1;
  }
  free(g.alpha);
  free(g.status);
  return rc ? EXIT_IO : EXIT_OK;
}
