/*
 * theta_gsl.c - the theta solve's robust route: GSL's multiroot on
 * (8)-(10) in units of R (opt.solver, hybridsj by default), for a cold
 * start and wherever the warm Newton path of fk.c gives up.
 *
 * The solver and its vectors are allocated once, in rps3_data_alloc().  For
 * the default hybridsj (and hybridj) GSL 2.7 allocates only in _alloc, so a
 * warm-started solve allocates nothing; newton and gnewton allocate inside
 * every iteration and are offered for studies only.
 */
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>

#include "internal.h"
#include "linalg.h"
#include "theta_solver.h"

/* df/dtheta of the closure q evaluated: row k holds at[k] at column k and
   bt[k] at column k + 1 */
static void closure_jac(const rps3_closure *q, double J[3][3]) {
  int k;
  for (k = 0; k < 3; k++) {
    J[k][0] = J[k][1] = J[k][2] = 0.0;
    J[k][k] = q->at[k];
    J[k][(k + 1) % 3] = q->bt[k];
  }
}

/* (8)-(10) and their analytic Jacobian (f or J may be NULL) at theta th for
   the lengths of q0, in q0's unit */
static void constraints(const rps3_closure *q0, const double th[3], double f[3],
                        double J[3][3]) {
  rps3_closure q = *q0;
  double fv[3];
  trig3(th, q.c, q.s);
  rps3_closure_eval(&q, fv);
  if (f != NULL) v3_copy(f, fv);
  if (J != NULL) closure_jac(&q, J);
}

/* (8)-(10) and the Jacobian the solver uses, for normalized lengths L and
   ratio rho: the tests check J against differences of f */
void rps3_theta_constraints(const double L[3], double rho, const double th[3],
                            double f[3], double J[3][3]) {
  rps3_closure q;
  q.R = 1.0;
  q.r3 = 3.0 * rho * rho;
  v3_copy(q.l, L);
  constraints(&q, th, f, J);
}

/* the same from theta's cosines c and sines s, which a caller keeps for
   the positions of the root (rps3_links_from_trig) */
void rps3_theta_constraints_trig(const double L[3], double rho,
                                 const double c[3], const double s[3],
                                 double f[3], double J[3][3]) {
  rps3_closure q;
  double fv[3];
  q.R = 1.0;
  q.r3 = 3.0 * rho * rho;
  v3_copy(q.l, L);
  v3_copy(q.c, c);
  v3_copy(q.s, s);
  rps3_closure_eval(&q, fv);
  if (f != NULL) v3_copy(f, fv);
  if (J != NULL) closure_jac(&q, J);
}

/* an evaluation by GSL: f and J (either may be NULL) as constraints(),
   keeping theta's trig in the memo p->q for the positions after the solve
   (and taking it when theta is the last evaluation's, bit for bit); the
   start's f and J from the check before _set when theta is that start */
static void evaluate(theta_params *p, const double th[3], double f[3],
                     double J[3][3]) {
  double fv[3];
  if (p->primed && th[0] == p->th0[0] && th[1] == p->th0[1] &&
      th[2] == p->th0[2]) {
    p->primed = 0;
    if (f != NULL) v3_copy(f, p->f0);
    if (J != NULL) memcpy(J, p->J0, sizeof(p->J0));
    return;
  }
  if (memcmp(th, p->q.th, sizeof(p->q.th)) != 0) {
    v3_copy(p->q.th, th);
    trig3(th, p->q.c, p->q.s);
  }
  rps3_closure_eval(&p->q, fv);
  if (f != NULL) v3_copy(f, fv);
  if (J != NULL) closure_jac(&p->q, J);
}

/* f of the derivative-free solvers.  Broyden's update divides by p . H y,
   y the change of f over the step, and GSL raises "approximation to
   Jacobian has collapsed" (broyden.c) when it is 0 -- as it is when a
   stalled iteration's step no longer changes f.  While p->watch is set (a
   broyden iterate), a trial point whose f equals the current iterate's
   bit for bit is reported as a bad function value instead, which GSL
   returns without raising; the solve reports the stall. */
static int gsl_f(const gsl_vector *x, void *params, gsl_vector *f) {
  theta_params *p = (theta_params *)params;
  double th[3], fv[3];
  int k;
  for (k = 0; k < 3; k++) th[k] = GV(x, k);
  if (!v3_finite(th)) return GSL_EBADFUNC;
  evaluate(p, th, fv, NULL);
  if (!v3_finite(fv)) return GSL_EBADFUNC;
  if (p->watch && fv[0] == p->fcur[0] && fv[1] == p->fcur[1] &&
      fv[2] == p->fcur[2]) {
    p->stalled = 1;
    return GSL_EBADFUNC;
  }
  for (k = 0; k < 3; k++) GV(f, k) = fv[k];
  return GSL_SUCCESS;
}

static int gsl_fdf(const gsl_vector *x, void *params, gsl_vector *f,
                   gsl_matrix *J) {
  double th[3], fv[3] = {0, 0, 0}, Jv[3][3];
  int k, q;
  for (k = 0; k < 3; k++) th[k] = GV(x, k);
  if (!v3_finite(th)) return GSL_EBADFUNC;
  /* a Jacobian-only call (J of finite theta and lengths is finite) skips
     f; a function-only call goes to gsl_f, which skips J */
  evaluate((theta_params *)params, th, f != NULL ? fv : NULL,
           J != NULL ? Jv : NULL);
  if (!v3_finite(fv)) return GSL_EBADFUNC;
  for (k = 0; k < 3; k++) {
    if (f != NULL) GV(f, k) = fv[k];
    if (J != NULL)
      for (q = 0; q < 3; q++)
        J->data[(size_t)k * J->tda + (size_t)q] = Jv[k][q];
  }
  return GSL_SUCCESS;
}

static int gsl_df(const gsl_vector *x, void *params, gsl_matrix *J) {
  return gsl_fdf(x, params, NULL, J);
}

int rps3_solver_alloc(const rps3_model *m, struct rps3_solver_state **out) {
  struct rps3_solver_state *s;
  const gsl_multiroot_fdfsolver_type *tfdf = NULL;
  const gsl_multiroot_fsolver_type *tf = NULL;
  *out = NULL;
  switch (m->opt.solver) {
  case RPS3_SOLVER_HYBRIDSJ: tfdf = gsl_multiroot_fdfsolver_hybridsj; break;
  case RPS3_SOLVER_HYBRIDJ: tfdf = gsl_multiroot_fdfsolver_hybridj; break;
  case RPS3_SOLVER_NEWTON: tfdf = gsl_multiroot_fdfsolver_newton; break;
  case RPS3_SOLVER_GNEWTON: tfdf = gsl_multiroot_fdfsolver_gnewton; break;
  case RPS3_SOLVER_HYBRIDS: tf = gsl_multiroot_fsolver_hybrids; break;
  case RPS3_SOLVER_HYBRID: tf = gsl_multiroot_fsolver_hybrid; break;
  case RPS3_SOLVER_DNEWTON: tf = gsl_multiroot_fsolver_dnewton; break;
  case RPS3_SOLVER_BROYDEN: tf = gsl_multiroot_fsolver_broyden; break;
  default: return RPS3_EINVAL;
  }
  s = (struct rps3_solver_state *)calloc(1, sizeof(*s));
  if (s == NULL) return RPS3_ENOMEM;
  s->kind = m->opt.solver;
  s->fdf = (tfdf != NULL);
  s->p.q.th[0] = s->p.q.th[1] = s->p.q.th[2] = (double)NAN;
  s->x = gsl_vector_alloc(3);
  if (s->fdf)
    s->sfdf = gsl_multiroot_fdfsolver_alloc(tfdf, 3);
  else
    s->sf = gsl_multiroot_fsolver_alloc(tf, 3);
  if (s->x == NULL || (s->fdf ? (void *)s->sfdf : (void *)s->sf) == NULL) {
    rps3_solver_free(s);
    return RPS3_ENOMEM;
  }
  /* the functions point at s->p, which lives as long as the solver */
  s->fn_fdf.f = gsl_f; /* function only: no Jacobian built */
  s->fn_fdf.df = gsl_df;
  s->fn_fdf.fdf = gsl_fdf;
  s->fn_fdf.n = 3;
  s->fn_fdf.params = &s->p;
  s->fn_f.f = gsl_f;
  s->fn_f.n = 3;
  s->fn_f.params = &s->p;
  *out = s;
  return RPS3_OK;
}

void rps3_solver_free(struct rps3_solver_state *s) {
  if (s == NULL) return;
  if (s->sfdf != NULL) gsl_multiroot_fdfsolver_free(s->sfdf);
  if (s->sf != NULL) gsl_multiroot_fsolver_free(s->sf);
  if (s->x != NULL) gsl_vector_free(s->x);
  free(s);
}

/* 1-norm condition number of the 3 x 3 matrix J, HUGE_VAL when its LU
   meets a zero (or non-finite) pivot */
static double cond3(const double J[3][3]) {
  double A[9], LU[9];
  int perm[3], i, k;
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++) A[3 * i + k] = LU[3 * i + k] = J[i][k];
  if (rps3_lu_factor(3, LU, perm) != 0) return HUGE_VAL;
  return rps3_lu_cond1(3, A, LU, perm);
}

/*
 * Whether the solver may take its next step from th without reaching
 * GSL's error handler, which aborts a program that left it on: NULL when
 * it may, else the reason.  The Newton-type solvers solve with an LU of
 * their Jacobian, and GSL's LU (lu.c) raises "matrix is singular" on an
 * exactly zero pivot; with partial pivoting a pivot is at least about
 * |J| / cond(J) against rounding of n eps |J|, so cond <= cond_max (1e13)
 * keeps it away from zero.  newton and gnewton use the analytic Jacobian.
 * dnewton and broyden use GSL's forward-difference Jacobian
 * (gsl_multiroot_fdjacobian: step GSL_SQRT_DBL_EPSILON |theta_j|, or
 * GSL_SQRT_DBL_EPSILON at 0), which is rebuilt here exactly as GSL builds
 * it, from the same function values, and must be as well conditioned.  It
 * must also agree with the analytic one to 1e-3 (relative, 1-norm): a
 * forward difference with that step is good to ~1e-8 wherever the first
 * derivatives are not small against the second, and where they are (all
 * theta at 0 or pi, where every sine vanishes) the difference quotient is
 * curvature, a Newton step on it goes nowhere, and Broyden's update then
 * collapses (broyden.c: "approximation to Jacobian has collapsed").  The
 * hybrid solvers use QR and report failures as return values.
 */
static const char *step_unsafe(const rps3_model *m, const theta_params *p,
                               const double th[3]) {
  double f[3], J[3][3], Jd[3][3], xs[3], f1[3], dn = 0.0, an = 0.0;
  int i, k;
  switch (m->opt.solver) {
  case RPS3_SOLVER_NEWTON:
  case RPS3_SOLVER_GNEWTON:
  case RPS3_SOLVER_DNEWTON:
  case RPS3_SOLVER_BROYDEN: break;
  default: return NULL;
  }
  constraints(&p->q, th, f, J);
  if (!(cond3(M3C(J)) <= m->opt.cond_max))
    return "singular constraint Jacobian";
  if (m->opt.solver == RPS3_SOLVER_NEWTON ||
      m->opt.solver == RPS3_SOLVER_GNEWTON)
    return NULL;
  /* the forward-difference Jacobian of gsl_multiroot_fdjacobian */
  for (k = 0; k < 3; k++) {
    double h = GSL_SQRT_DBL_EPSILON * fabs(th[k]);
    if (h == 0.0) h = GSL_SQRT_DBL_EPSILON;
    v3_copy(xs, th);
    xs[k] = th[k] + h;
    constraints(&p->q, xs, f1, NULL);
    for (i = 0; i < 3; i++) Jd[i][k] = (f1[i] - f[i]) / h;
  }
  for (k = 0; k < 3; k++) {
    double cd = 0.0, ca = 0.0;
    for (i = 0; i < 3; i++) {
      cd += fabs(Jd[i][k] - J[i][k]);
      ca += fabs(J[i][k]);
    }
    if (cd > dn) dn = cd;
    if (ca > an) an = ca;
  }
  if (!(dn <= 1e-3 * an))
    return "difference Jacobian dominated by curvature (all sines ~ 0)";
  if (!(cond3(M3C(Jd)) <= m->opt.cond_max))
    return "singular difference Jacobian";
  return NULL;
}

/*
 * The multiroot route from d->theta (the lengths in s->p.q, in units of
 * R): the checks that keep GSL's error handler away, then GSL's iteration
 * to max |f_k| <= opt.tol.  RPS3_OK with the root in th (d->solve_niter,
 * d->solve_resid set), or the status and message of the failure.
 */
int rps3_theta_multiroot(const rps3_model *m, rps3_data *d, double th[3]) {
  struct rps3_solver_state *s = d->solver;
  double f[3], resid0;
  const char *unsafe;
  int i, iter, status;
  unsafe = step_unsafe(m, &s->p, d->theta);
  if (unsafe != NULL)
    RPS3_ERROR(d, RPS3_ENOCONV,
               "%s at the starting point theta = (%.6g, "
               "%.6g, %.6g)",
               unsafe, d->theta[0], d->theta[1], d->theta[2]);

  /* GSL's hybrid solvers ignore the status of the first evaluation in
     _set, so a starting point where (8)-(10) overflow would look converged
     with f = 0: check it here.  _set's evaluation at this point then
     takes these values (and J, for the fdf solvers) */
  v3_copy(s->p.th0, d->theta);
  evaluate(&s->p, d->theta, s->p.f0, s->fdf ? s->p.J0 : NULL);
  v3_copy(f, s->p.f0);
  s->p.primed = 1;
  if (!v3_finite(f))
    RPS3_ERROR(d, RPS3_EINVAL,
               "constraints (8)-(10) do not evaluate at the starting point "
               "(lengths %g, %g, %g m)",
               d->l[0], d->l[1], d->l[2]);

  /* a start within the tolerance already (a warm start predicted along the
     motion) is the root: the solver is not set up for it */
  resid0 = fmax(fabs(f[0]), fmax(fabs(f[1]), fabs(f[2])));
  if (resid0 <= m->opt.tol) {
    s->p.primed = 0;
    v3_copy(th, d->theta);
    d->solve_niter = 0;
    d->solve_resid = resid0;
    return RPS3_OK;
  }

  /* initialize */
  status = s->fdf ? gsl_multiroot_fdfsolver_set(s->sfdf, &s->fn_fdf, s->x)
                  : gsl_multiroot_fsolver_set(s->sf, &s->fn_f, s->x);
  if (status == GSL_EBADFUNC)
    RPS3_ERROR(d, RPS3_EINVAL,
               "constraints (8)-(10) do not evaluate at the starting point "
               "(lengths %g, %g, %g m): %s",
               d->l[0], d->l[1], d->l[2], gsl_strerror(status));
  /* the derivative-free solvers difference a Jacobian in _set: at a start
     where it is singular (e.g. theta = 0) GSL stops with GSL_ESING, a
     point-level failure of this start, not a caller error */
  if (status != GSL_SUCCESS)
    RPS3_ERROR(d, RPS3_ENOCONV,
               "solver cannot start at theta = (%.6g, %.6g, %.6g): %s",
               d->theta[0], d->theta[1], d->theta[2], gsl_strerror(status));

  /* iterate / test: residual first, so that an exact start costs nothing */
  iter = 0;
  for (;;) {
    const gsl_vector *xv = s->fdf ? s->sfdf->x : s->sf->x;
    const gsl_vector *fv = s->fdf ? s->sfdf->f : s->sf->f;
    double resid = 0.0;
    for (i = 0; i < 3; i++) {
      th[i] = GV(xv, i);
      f[i] = GV(fv, i);
      if (fabs(f[i]) > resid || !isfinite(f[i])) resid = fabs(f[i]);
    }
    d->solve_niter = iter;
    d->solve_resid = resid;
    if (resid <= m->opt.tol) break;
    if (!isfinite(resid))
      RPS3_ERROR(d, RPS3_ENOCONV,
                 "constraints not finite after %d iterations: diverged", iter);
    if (iter >= m->opt.max_iter)
      RPS3_ERROR(d, RPS3_ENOCONV,
                 "no convergence in %d iterations (residual %.3g > tol %.3g)",
                 iter, resid, m->opt.tol);
    unsafe = step_unsafe(m, &s->p, th);
    if (unsafe != NULL)
      RPS3_ERROR(d, RPS3_ENOCONV, "%s after %d iterations", unsafe, iter);
    v3_copy(s->p.fcur, f);
    s->p.watch = (m->opt.solver == RPS3_SOLVER_BROYDEN);
    s->p.stalled = 0;
    status = s->fdf ? gsl_multiroot_fdfsolver_iterate(s->sfdf)
                    : gsl_multiroot_fsolver_iterate(s->sf);
    s->p.watch = 0;
    iter++;
    if (status != GSL_SUCCESS) {
      d->solve_niter = iter;
      if (s->p.stalled)
        RPS3_ERROR(d, RPS3_ENOCONV,
                   "solver stalled after %d iterations: a step left the "
                   "residual %.3g > tol %.3g unchanged",
                   iter, resid, m->opt.tol);
      RPS3_ERROR(d, RPS3_ENOCONV, "solver stopped after %d iterations: %s",
                 iter, gsl_strerror(status));
    }
  }

  return RPS3_OK;
}
