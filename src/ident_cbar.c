/*
 * ident_cbar.c - the consistent fit's barrier stage.  In the bodies'
 * standard parameters and the columns of no body, y, the problem is
 * convex: phi(y) = |R11 pi - r|^2 + reg sum_b tr J_b, quadratic, over
 * every J_b (linear in y) positive semidefinite and the >= 0 columns >=
 * 0.  From the Cholesky stages' point, moved inside, it is solved by the
 * barrier method (Boyd & Vandenberghe, Convex Optimization, 2004, sec.
 * 11.3): Newton's method with the exact Hessian on phi + mu B, B = sum_b
 * (c_b tr J_b - log det J_b) + sum_j (c_j pi_j - log pi_j) (the >= 0
 * columns), a backtracking line search that stays inside, mu decreased
 * whenever the iterate is centred (its Newton decrement small).  A
 * central point's duality gap is about mu times the barrier's degree (4
 * a body, 1 a column); the fit's own optimality measure, after every
 * step, says when it is done.  Newton's steps cost a factorisation of nx
 * x nx (76 for the general model's layout), tens of them where the
 * Cholesky variables' trust region crawls along a face of the cone for
 * hundreds.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "ident_cfit.h"
#include "internal.h"

/* Armijo's fraction and the backtracking factor (Boyd & Vandenberghe's
   alpha in 0.01..0.3, beta in 0.1..0.8) */
#define LS_ALPHA 0.01
#define LS_BETA 0.5
/* a step below this fraction of Newton's: stalled (rounding) */
#define LS_TMIN 1e-10
/* centred: the Newton decrement lambda^2 / mu (of phi / mu + B, the
   self-concordant scale) at most this; in Newton's quadratic region
   (lambda < 1/4 .. 1/2 in Nesterov & Nemirovski's analysis) */
#define CENTRED 0.25
/* the first mu, of the start's measure (or phi): a tenth of the gap a
   central point would have, the measure at a point not yet central
   being mostly its dual violation terms (measured: a tenth to a
   hundredth saves a few of Newton's steps over 1) */
#define MU_START 0.1
/* the barrier stage goes on to this fraction of the optimality test
   (then a test met on the way, when a step stalls or the budget ends):
   two of its centrings past the test, a few Newton steps, for an
   objective within about 1e-8 of the optimum where the test guarantees
   opt_tol = 1e-6 */
#define AIM 1e-2
/* ... for at most this many steps once the test is met (a far, flat
   optimum at reg 0 can take hundreds) */
#define AIM_STEPS 20
/* mu's decrease once centred (Boyd & Vandenberghe's mu, 10..20 typical) */
#define MU_FACTOR 20.0

/* the start's margin: a pseudo-inertia eigenvalue raised to at least
   this fraction of its body's largest, a >= 0 column to this fraction of
   the largest of them (the plain stage's point may be on the boundary,
   U_ii = 0, or at rounding from it); the first centring takes back what
   it costs in a few steps (measured on the boundary cases: 1e-8 to 1e-2
   all converge, 1e-4 and 1e-2 in the fewest steps) */
#define START_MARGIN 1e-4

/* y's index of column j */
static size_t ycol(const cfit *c, size_t j) {
  return c->owner[j] >= 0 ? 10 * (size_t)c->owner[j] + (size_t)c->slot[j]
                          : (size_t)c->slot[j];
}

/* tr J of a body's ten standard parameters (or of a step in them) */
static double trace_of(const double *s) {
  return s[0] + 0.5 * (s[4] + s[7] + s[9]);
}

int rps3_cbar_alloc(cbar *w, const cfit *c) {
  const size_t p = c->p, n = c->nx;
  size_t i, j, k;
  memset(w, 0, sizeof *w);
  w->M = gsl_matrix_alloc(p, p);
  w->H = gsl_matrix_alloc(n, n);
  w->g = gsl_vector_alloc(n);
  w->dy = gsl_vector_alloc(n);
  w->D = gsl_vector_alloc(n);
  w->yt = gsl_vector_alloc(n);
  w->perm = gsl_permutation_alloc(n);
  w->res = malloc((p + 1) * sizeof(double));
  w->Ji = malloc((16 * c->nb + 1) * sizeof(double));
  w->cw = malloc((c->nb + p + 1) * sizeof(double));
  if (!w->M || !w->H || !w->g || !w->dy || !w->D || !w->yt || !w->perm ||
      !w->res || !w->Ji || !w->cw)
    return RPS3_ENOMEM;
  /* M = R11^T R11, R11 upper triangular */
  for (i = 0; i < p; i++)
    for (j = i; j < p; j++) {
      double s = 0.0;
      for (k = 0; k <= i; k++)
        s += c->R[k * (p + 1) + i] * c->R[k * (p + 1) + j];
      gsl_matrix_set(w->M, i, j, s);
      gsl_matrix_set(w->M, j, i, s);
    }
  return RPS3_OK;
}

void rps3_cbar_free(cbar *w) {
  gsl_matrix_free(w->M);
  gsl_matrix_free(w->H);
  gsl_vector_free(w->g);
  gsl_vector_free(w->dy);
  gsl_vector_free(w->D);
  gsl_vector_free(w->yt);
  if (w->perm) gsl_permutation_free(w->perm);
  free(w->res);
  free(w->Ji);
  free(w->cw);
  memset(w, 0, sizeof *w);
}

/* B(y), and (Ji not NULL) each body's J^-1: 1 inside, 0 outside (an
   eigenvalue or a >= 0 column not above 0, or not finite) */
static int barrier_of(const cfit *c, const cbar *w, const double *y, double *B,
                      double *Ji) {
  double s = 0.0;
  size_t b, j;
  for (b = 0; b < c->nb; b++) {
    double J[4][4];
    int k, q, r;
    rps3_cfit_pseudo_of(y + 10 * b, J);
    if (!rps3_all_finite(&J[0][0], 16)) return 0;
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) gsl_matrix_set(c->E, k, q, J[k][q]);
    gsl_eigen_symmv(c->E, c->lam, c->Q, c->ew);
    for (k = 0; k < 4; k++) {
      if (!(gsl_vector_get(c->lam, k) > 0.0)) return 0;
      s -= log(gsl_vector_get(c->lam, k));
    }
    s += w->cw[b] * trace_of(y + 10 * b);
    if (Ji == NULL) continue;
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) {
        double v = 0.0;
        for (r = 0; r < 4; r++)
          v += gsl_matrix_get(c->Q, k, r) * gsl_matrix_get(c->Q, q, r) /
               gsl_vector_get(c->lam, r);
        Ji[16 * b + 4 * (size_t)k + (size_t)q] = v;
      }
  }
  for (j = 0; j < c->p; j++)
    if (c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j)) {
      double v = y[c->slot[j]];
      if (!(v > 0.0)) return 0;
      s += w->cw[c->nb + j] * v - log(v);
    }
  *B = s;
  return isfinite(s);
}

/* y moved inside by START_MARGIN where it is not */
static void inside(const cfit *c, double *y) {
  double fmaxv = 0.0;
  size_t b, j;
  for (b = 0; b < c->nb; b++) {
    double J[4][4], lmax = 0.0;
    int k, q, r, raise = 0;
    rps3_cfit_pseudo_of(y + 10 * b, J);
    if (!rps3_all_finite(&J[0][0], 16)) continue; /* the barrier says */
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) gsl_matrix_set(c->E, k, q, J[k][q]);
    gsl_eigen_symmv(c->E, c->lam, c->Q, c->ew);
    for (k = 0; k < 4; k++) lmax = fmax(lmax, gsl_vector_get(c->lam, k));
    if (!(lmax > 0.0)) lmax = 1.0;
    for (k = 0; k < 4; k++)
      if (!(gsl_vector_get(c->lam, k) >= START_MARGIN * lmax)) {
        gsl_vector_set(c->lam, k, START_MARGIN * lmax);
        raise = 1;
      }
    if (!raise) continue;
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) {
        double v = 0.0;
        for (r = 0; r < 4; r++)
          v += gsl_matrix_get(c->Q, k, r) * gsl_vector_get(c->lam, r) *
               gsl_matrix_get(c->Q, q, r);
        J[k][q] = v;
      }
    rps3_cfit_std_of(M4C(J), y + 10 * b);
  }
  for (j = 0; j < c->p; j++)
    if (c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j))
      fmaxv = fmax(fmaxv, y[c->slot[j]]);
  if (!(fmaxv > 0.0)) fmaxv = 1.0;
  for (j = 0; j < c->p; j++)
    if (c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j) &&
        !(y[c->slot[j]] >= START_MARGIN * fmaxv))
      y[c->slot[j]] = START_MARGIN * fmaxv;
}

/* the barrier's linear terms, c_b tr J_b and c_j pi_j: without them a
   body or column the data do not see (wholly, or along a direction) at
   reg 0 has no barrier minimiser (-log det J_b falls without end as
   J_b grows) and Newton's steps chase it; with c_b = 4 / (CW_FAR tr
   J_b), c_j = 1 / (CW_FAR pi_j) of the start each term alone has its
   minimum at CW_FAR times the start's size, far enough not to pull a
   seen body (measured on the boundary cases: 1 slows some fits by 2 to
   10 times, 1e4 and 1e6 both take 60 to 110 steps at reg 1e-9, 1e-12
   and 0).  Like the barrier they weigh mu, and vanish with it */
#define CW_FAR 1e4
static void weights(const cfit *c, cbar *w, const double *y) {
  size_t b, j;
  for (b = 0; b < c->nb; b++) {
    double t = trace_of(y + 10 * b);
    w->cw[b] = t > 0.0 && isfinite(t) ? 4.0 / (CW_FAR * t) : 0.0;
  }
  for (j = 0; j < c->p; j++) {
    double v = c->owner[j] < 0 ? y[c->slot[j]] : 0.0;
    w->cw[c->nb + j] = rps3_cfit_is_nonneg(c, j) && v > 0.0 && isfinite(v)
                           ? 1.0 / (CW_FAR * v)
                           : 0.0;
  }
}

/* phi(y), w->res = R11 pi - r of it */
static double phi_of(const cfit *c, cbar *w, const double *y, double reg) {
  const size_t p = c->p, P1 = c->p + 1;
  double s = 0.0;
  size_t i, j, b;
  for (i = 0; i < p; i++) {
    double r = -c->R[i * P1 + p];
    for (j = i; j < p; j++) r += c->R[i * P1 + j] * y[ycol(c, j)];
    w->res[i] = r;
    s += r * r;
  }
  for (b = 0; b < c->nb; b++) s += reg * trace_of(y + 10 * b);
  return s;
}

/* the gradient w->g and Hessian w->H of phi + mu B at y (w->res and
   w->Ji of y) */
static void newton_system(const cfit *c, cbar *w, const double *y, double reg,
                          double mu) {
  const size_t p = c->p, P1 = c->p + 1;
  double A[10][4][4];
  size_t i, j, b;
  int k, q, a, d;
  gsl_vector_set_zero(w->g);
  gsl_matrix_set_zero(w->H);
  /* the residual term: 2 R11^T res, 2 R11^T R11 through pi = P y */
  for (j = 0; j < p; j++) {
    double s = 0.0;
    for (i = 0; i <= j; i++) s += c->R[i * P1 + j] * w->res[i];
    w->g->data[ycol(c, j)] += 2.0 * s;
    for (i = 0; i < p; i++)
      *gsl_matrix_ptr(w->H, ycol(c, i), ycol(c, j)) +=
          2.0 * gsl_matrix_get(w->M, i, j);
  }
  /* J = sum_k y_k A_k: A_k the pseudo-inertia of the unit parameter k */
  for (k = 0; k < 10; k++) {
    double e[10] = {0};
    e[k] = 1.0;
    rps3_cfit_pseudo_of(e, A[k]);
  }
  for (b = 0; b < c->nb; b++) {
    /* -log det J: gradient -tr(J^-1 A_k), Hessian tr(J^-1 A_j J^-1 A_k) */
    const double *Ji = w->Ji + 16 * b;
    double G[10][4][4];
    size_t o = 10 * b;
    const double tw = reg + mu * w->cw[b];
    w->g->data[o] += tw;
    w->g->data[o + 4] += 0.5 * tw;
    w->g->data[o + 7] += 0.5 * tw;
    w->g->data[o + 9] += 0.5 * tw;
    for (k = 0; k < 10; k++) {
      double tr = 0.0;
      for (a = 0; a < 4; a++)
        for (d = 0; d < 4; d++) {
          double s = 0.0;
          for (q = 0; q < 4; q++) s += Ji[4 * a + q] * A[k][q][d];
          G[k][a][d] = s;
        }
      for (a = 0; a < 4; a++) tr += G[k][a][a];
      w->g->data[o + (size_t)k] -= mu * tr;
    }
    for (k = 0; k < 10; k++)
      for (q = 0; q <= k; q++) {
        double s = 0.0;
        for (a = 0; a < 4; a++)
          for (d = 0; d < 4; d++) s += G[k][a][d] * G[q][d][a];
        *gsl_matrix_ptr(w->H, o + (size_t)k, o + (size_t)q) += mu * s;
        if (q != k)
          *gsl_matrix_ptr(w->H, o + (size_t)q, o + (size_t)k) += mu * s;
      }
  }
  for (j = 0; j < p; j++)
    if (c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j)) {
      size_t s = (size_t)c->slot[j];
      w->g->data[s] += mu * (w->cw[c->nb + j] - 1.0 / y[s]);
      *gsl_matrix_ptr(w->H, s, s) += mu / (y[s] * y[s]);
    }
}

/* Newton's step w->dy = -H^-1 g: H scaled to a unit diagonal (its
   entries span the bodies' units and the barrier's 1 / eigenvalue^2),
   then GSL's modified Cholesky (a positive definite H factored as it is;
   a direction neither the data nor the barrier see, a zero row, made
   definite instead of failing).  0 when it is not finite */
static int newton_step(const cfit *c, cbar *w) {
  const size_t n = c->nx;
  size_t i, j;
  for (i = 0; i < n; i++) {
    double h = gsl_matrix_get(w->H, i, i);
    gsl_vector_set(w->D, i, h > 0.0 && isfinite(h) ? 1.0 / sqrt(h) : 1.0);
  }
  for (i = 0; i < n; i++) {
    for (j = 0; j < n; j++)
      *gsl_matrix_ptr(w->H, i, j) *= w->D->data[i] * w->D->data[j];
    w->dy->data[i] = -w->D->data[i] * w->g->data[i];
  }
  if (!rps3_all_finite(w->H->data, (int)(n * n))) return 0;
  if (gsl_linalg_mcholesky_decomp(w->H, w->perm, NULL) != GSL_SUCCESS ||
      gsl_linalg_mcholesky_svx(w->H, w->perm, w->dy) != GSL_SUCCESS)
    return 0;
  for (i = 0; i < n; i++) w->dy->data[i] *= w->D->data[i];
  return rps3_all_finite(w->dy->data, (int)n);
}

/* theta and body of y, their optimality measure and cost */
static void measure(const cfit *c, const double *y, double reg, double ph,
                    double *theta, double *body, double *gap, double *cost) {
  const double rr = c->R[c->p * (c->p + 1) + c->p];
  size_t j;
  for (j = 0; j < c->p; j++) theta[j] = y[ycol(c, j)];
  memcpy(body, y, 10 * c->nb * sizeof(double));
  *gap = rps3_cfit_optimality(c, theta, body, reg, NULL);
  *cost = rr * rr + ph;
}

int rps3_cbar_solve(const cfit *c, cbar *w, double *y, double reg,
                    double opt_tol, size_t max_iter, int *niter, double *theta,
                    double *body, double *gap, double *cost) {
  const size_t p = c->p, P1 = c->p + 1, n = c->nx;
  const double aim = AIM * opt_tol;
  double B, ph, mu, deg = 4.0 * (double)c->nb;
  size_t it = 0, past = 0, i, j, b;
  for (j = 0; j < p; j++) deg += c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j);
  inside(c, y);
  weights(c, w, y);
  if (!barrier_of(c, w, y, &B, w->Ji)) return 0;
  ph = phi_of(c, w, y, reg);
  measure(c, y, reg, ph, theta, body, gap, cost);
  mu = MU_START * fmin(*gap, ph) / deg;
  if (!(mu > 0.0) || !isfinite(mu)) return 0;
  while (!rps3_cfit_optimal(*gap, *cost, aim) && past < AIM_STEPS) {
    double lam2 = 0.0, lin = 0.0, quad = 0.0, t = 1.0, Bt = 0.0;
    newton_system(c, w, y, reg, mu);
    if (!newton_step(c, w)) break;
    for (i = 0; i < n; i++) lam2 -= w->g->data[i] * w->dy->data[i];
    if (!(lam2 >= 0.0)) break; /* not a descent: H's rounding */
    if (lam2 <= CENTRED * mu) {
      /* centred: on along the path, to a central gap of half the aim,
         and below it while the measure's other terms (the dual
         violations of a point not quite central) keep it above */
      const double mu_end = 0.5 * aim * *cost / deg;
      if (mu * deg < 1e-3 * RPS3_CFIT_GAP_FLOOR) break;
      mu = mu > mu_end ? fmax(mu / MU_FACTOR, mu_end) : mu / MU_FACTOR;
      continue;
    }
    if (it == max_iter) break;
    /* phi along the step, exactly: phi + t lin + t^2 quad */
    for (i = 0; i < p; i++) {
      double s = 0.0;
      for (j = i; j < p; j++) s += c->R[i * P1 + j] * w->dy->data[ycol(c, j)];
      lin += 2.0 * w->res[i] * s;
      quad += s * s;
    }
    for (b = 0; b < c->nb; b++) lin += reg * trace_of(w->dy->data + 10 * b);
    for (;;) {
      for (i = 0; i < n; i++) w->yt->data[i] = y[i] + t * w->dy->data[i];
      if (barrier_of(c, w, w->yt->data, &Bt, NULL) &&
          t * lin + t * t * quad + mu * (Bt - B) <= -LS_ALPHA * t * lam2)
        break;
      t *= LS_BETA;
      if (t < LS_TMIN) break;
    }
    if (t < LS_TMIN) break; /* stalled: rounding */
    memcpy(y, w->yt->data, n * sizeof(double));
    it++;
    (*niter)++;
    barrier_of(c, w, y, &B, w->Ji); /* inside: the line search's test */
    ph = phi_of(c, w, y, reg);
    measure(c, y, reg, ph, theta, body, gap, cost);
    past += rps3_cfit_optimal(*gap, *cost, opt_tol);
  }
  return rps3_cfit_optimal(*gap, *cost, opt_tol);
}
