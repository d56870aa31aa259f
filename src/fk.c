/*
 * fk.c - the theta solve of (8)-(10), and forward kinematics l -> theta ->
 * pose, (11)-(20).  One solve for every caller: from a warm start the
 * Newton path in the links' planes (rps3_theta_newton, which the forward
 * dynamics calls too), else, and wherever it gives up, GSL's multiroot,
 * which decides and reports; the multiroot route's start from the root
 * predictor of src/theta.h (rps3_root_keep, rps3_root_predict).
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
#include "theta.h"

/* parameters of (8)-(10) in the paper's normalized form: the closure in
   units of R (q.R = 1, q.l = l / R, q.r3 = 3 rho^2) */
typedef struct {
  /* the lengths and, as a memo of the last evaluation, its theta, cosines
     and sines and pair terms: the positions after the solve reuse them
     when the root is that theta (as it is whenever the last trial step
     was accepted), and so does the next evaluation at the same theta --
     the next point's warm start, from this root.  A memo of a pure
     function, keyed on theta's bits (NaN until the first evaluation), so
     never stale */
  rps3_closure q;
  /* broyden only: the residual at the current iterate, and whether a
     trial point gave back exactly that residual (see gsl_f) */
  double fcur[3];
  int watch;
  int stalled;
  /* f and J at the starting point, evaluated by the check before _set:
     _set's own evaluation there takes them instead of computing them
     again (primed until it does) */
  int primed;
  double th0[3], f0[3], J0[3][3];
} theta_params;

struct rps3_solver_state {
  rps3_solver kind;                 /* the solver this state was built for */
  int fdf;                          /* 1: fdfsolver (analytic Jacobian) */
  gsl_multiroot_fdfsolver *sfdf;
  gsl_multiroot_fsolver *sf;
  gsl_vector *x;                    /* starting point */
  gsl_multiroot_function_fdf fn_fdf;
  gsl_multiroot_function fn_f;
  theta_params p;
  /* rps3_inverse's multiroot route: its last root and what the next
     point's predicted start needs there (rps3_root_keep), in metres; one
     use, by the next call, and only while d->theta is still this root,
     bit for bit */
  int root_ok;
  rps3_closure root;
  double root_X[3][3], root_G[3][3]; /* (df/dtheta)^-1, dtheta/dl */
};

static void trig3(const double th[3], double c[3], double s[3]) {
  int k;
  for (k = 0; k < 3; k++) {
    double t = th[k]; /* one sincos: c[k] may alias th[k] as far as the
                         compiler knows */
    c[k] = cos(t);
    s[k] = sin(t);
  }
}

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
static void constraints(const rps3_closure *q0, const double th[3],
                        double f[3], double J[3][3]) {
  rps3_closure q = *q0;
  double fv[3];
  trig3(th, q.c, q.s);
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

/* the components of a GSL vector (read and written in place: the views'
   accessors cost more than the evaluation's arithmetic) */
#define GV(v, k) ((v)->data[(size_t)(k) * (v)->stride])

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
      for (q = 0; q < 3; q++) J->data[(size_t)k * J->tda + (size_t)q] = Jv[k][q];
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

int rps3_theta_guess(const rps3_model *m, rps3_data *d) {
  int i;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  for (i = 0; i < 3; i++) {
    double cth;
    if (!isfinite(d->l[i]) || !(d->l[i] > 0.0))
      RPS3_ERROR(d, RPS3_EINVAL, "link %d length %g m: needs finite and > 0",
                 i + 1, d->l[i]);
    /* level platform: the ball joint sits R - r inwards of the pin */
    cth = (m->R - m->r) / d->l[i];
    if (cth > 0.999) cth = 0.999;
    if (cth < -0.999) cth = -0.999;
    d->theta[i] = acos(cth);
  }
  return RPS3_OK;
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

/* the Newton path's most steps: from a warm start one or two converge;
   more go to the multiroot route, whose trust region copes with a start
   far from the root */
#define NEWTON_MAX 8

/* max |v_k| (fmax is a call at -O2); a NaN is dropped, and each use below
   is preceded or followed by a test that a NaN fails */
static inline double max3abs(const double v[3]) {
  const double a = fabs(v[0]), b = fabs(v[1]), c = fabs(v[2]);
  const double ab = a > b ? a : b;
  return ab > c ? ab : c;
}

int rps3_theta_newton(const rps3_model *m, rps3_closure *q, int have_trig,
                      int *niter, double *resid, int *exact) {
  /* the test of rps3_theta_solve, max |f_k| / R^2 <= tol, in q's unit */
  const double tol = m->opt.tol * q->R * q->R;
  const int max_it = m->opt.max_iter < NEWTON_MAX ? m->opt.max_iter
                                                  : NEWTON_MAX;
  double *th = q->th, *c = q->c, *sn = q->s, f[3], res;
  int it, i, fold = 0, ex = !have_trig;
  if (!have_trig) trig3(th, c, sn);
  for (it = 0;; it++) {
    const double *a = q->at, *b = q->bt;
    double x[3], det, id, big;
    rps3_closure_eval(q, f);
    res = max3abs(f);
    if (!(fabs(f[0]) + fabs(f[1]) + fabs(f[2]) < HUGE_VAL)) return -1;
    if (res <= tol) break;
    if (it >= max_it) return -1;
    /* J x = f for the cyclic bidiagonal J = df/dtheta (J[k][k] = a_k,
       J[k][k+1] = b_k) by its adjugate: det = a0 a1 a2 + b0 b1 b2 */
    det = a[0] * (a[1] * a[2]) + b[0] * (b[1] * b[2]);
    if (!(fabs(det) > 0.0 && fabs(det) < HUGE_VAL)) return -1;
    id = 1.0 / det;
    x[0] = (a[1] * a[2] * f[0] - b[0] * a[2] * f[1] + b[0] * b[1] * f[2]) * id;
    x[1] = (b[1] * b[2] * f[0] + a[0] * a[2] * f[1] - a[0] * b[1] * f[2]) * id;
    x[2] = (a[0] * a[1] * f[2] - a[1] * b[2] * f[0] + b[0] * b[2] * f[1]) * id;
    /* a correction beyond RPS3_THETA_WARM_MAX: not a warm start (the
       multiroot route's trust region copes with it, where Newton's full
       step may jump to another root) */
    big = max3abs(x);
    if (!(big <= RPS3_THETA_WARM_MAX)) return -1;
    for (i = 0; i < 3; i++) th[i] -= x[i];
    if (big <= RPS3_THETA_PREDICT_MAX) {
      rps3_trig_step(c, sn, x); /* cos and sin of theta - x */
      ex = 0;
    } else {
      trig3(th, c, sn);
      ex = 1;
    }
  }
  *niter = it;
  *resid = res / (q->R * q->R);
  /* the branch 0 < theta < pi, after folding whole turns */
  for (i = 0; i < 3; i++) {
    if (th[i] > 0.0 && th[i] < RPS3_PI) continue;
    th[i] = remainder(th[i], 2.0 * RPS3_PI);
    fold = 1;
    if (!(th[i] > 0.0 && th[i] < RPS3_PI)) return -1;
    c[i] = cos(th[i]);
    sn[i] = sin(th[i]);
  }
  /* the pair terms at the folded angles' own trig */
  if (fold) rps3_closure_eval(q, f);
  *exact = ex;
  return fold;
}

void rps3_root_keep(const rps3_model *m, rps3_data *d, const rps3_cjac *J) {
  struct rps3_solver_state *s = d->solver;
  rps3_closure *q = &s->root;
  double f[3];
  int i, k;
  s->root_ok = J->factored && !J->sing;
  if (!s->root_ok) return;
  /* the root in the links' planes, in metres: cos and sin theta are the
     link directions' vertical components (29) */
  q->R = m->R;
  q->r3 = 3.0 * m->r * m->r;
  for (i = 0; i < 3; i++) {
    q->l[i] = d->l[i];
    q->th[i] = d->theta[i];
    q->c[i] = d->dphi[i][2];
    q->s[i] = d->phi[i][2];
  }
  rps3_closure_eval(q, f);
  /* (df/dtheta)^-1 = (A^-1)^T for the lambda system A = (df/dtheta)^T,
     and G = -(df/dtheta)^-1 (df/dl) */
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++) s->root_X[i][k] = J->Ainv[3 * k + i];
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++)
      s->root_G[i][k] = -(s->root_X[i][0] * J->Jl[0][k] +
                          s->root_X[i][1] * J->Jl[1][k] +
                          s->root_X[i][2] * J->Jl[2][k]);
}

void rps3_root_predict(rps3_data *d, double max_step) {
  struct rps3_solver_state *s = d->solver;
  const rps3_closure *q = &s->root;
  double dl[3], u[3], x[3], hd[3], Zd[3], hdd[3], Zdd[3], Hv[3];
  int ok = s->root_ok && d->have_theta &&
           memcmp(d->theta, q->th, sizeof(q->th)) == 0;
  s->root_ok = 0; /* one use */
  if (!ok) return;
  /* the second order along the chord itself (tau = 1): theta'' for l' =
     dl, (df/dtheta) theta'' = x, the velocity products of (8)-(10) */
  v3_sub(dl, d->l, q->l);
  m3_mulv(u, M3C(s->root_G), dl);
  rps3_closure_bias(q, dl, u, x, hd, Zd, hdd, Zdd);
  m3_mulv(Hv, M3C(s->root_X), x);
  rps3_theta_predict(d->theta, d->l, q->l, q->th, M3C(s->root_G), Hv, 1.0,
                     max_step);
}

int rps3_theta_solve(const rps3_model *m, rps3_data *d) {
  return rps3_theta_solve_with(m, d, NULL);
}

int rps3_theta_solve_with(const rps3_model *m, rps3_data *d, rps3_cjac *J) {
  struct rps3_solver_state *s;
  rps3_cjac own;
  double th[3], f[3], resid0;
  const char *unsafe;
  int i, iter, status, prev_mode, same, warm;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  s = d->solver;
  if (s->kind != m->opt.solver)
    RPS3_ERROR(d, RPS3_EINVAL,
               "workspace was allocated for solver %s, the model asks for %s",
               rps3_solver_name(s->kind), rps3_solver_name(m->opt.solver));
  d->stage = 0;
  d->warn = 0;
  d->solve_niter = 0;
  d->solve_resid = 0.0;
  for (i = 0; i < 3; i++)
    if (!isfinite(d->l[i]) || !(d->l[i] > 0.0))
      RPS3_ERROR(d, RPS3_EINVAL, "link %d length %g m: needs finite and > 0",
                 i + 1, d->l[i]);
  /* starting point: explicit warm start, else the level-platform guess;
     a warm start remembers the mode it starts from */
  prev_mode = RPS3_MODE_ANY;
  warm = m->opt.warm_start && d->have_theta && v3_finite(d->theta);
  if (warm) {
    prev_mode = d->mode;
  } else {
    status = rps3_theta_guess(m, d);
    if (status != RPS3_OK) return status;
  }
  d->mode = RPS3_MODE_ANY;
  s->p.primed = 0;
  s->p.q.R = 1.0;
  s->p.q.r3 = 3.0 * m->rho * m->rho;
  for (i = 0; i < 3; i++) {
    s->p.q.l[i] = d->l[i] / m->R;
    GV(s->x, i) = d->theta[i];
  }

  /* a warm start: the Newton path in the links' planes, in units of R as
     GSL's evaluations; where it does not converge (to a root in (0, pi)),
     the multiroot route from the same start decides and reports */
  if (warm) {
    rps3_closure q = s->p.q;
    int exact;
    v3_copy(q.th, d->theta);
    if (rps3_theta_newton(m, &q, 0, &d->solve_niter, &d->solve_resid,
                          &exact) >= 0) {
      v3_copy(th, q.th);
      /* the root's libm trig, for the positions and the next evaluation
         there (a series-stepped one gives way to libm's below) */
      if (exact) s->p.q = q;
      goto root;
    }
    d->solve_niter = 0;
    d->solve_resid = 0.0;
  }

  unsafe = step_unsafe(m, &s->p, d->theta);
  if (unsafe != NULL)
    RPS3_ERROR(d, RPS3_ENOCONV, "%s at the starting point theta = (%.6g, "
               "%.6g, %.6g)", unsafe, d->theta[0], d->theta[1], d->theta[2]);

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
               "(lengths %g, %g, %g m)", d->l[0], d->l[1], d->l[2]);

  /* a start within the tolerance already (a warm start predicted along the
     motion) is the root: the solver is not set up for it */
  resid0 = fmax(fabs(f[0]), fmax(fabs(f[1]), fabs(f[2])));
  if (resid0 <= m->opt.tol) {
    s->p.primed = 0;
    v3_copy(th, d->theta);
    d->solve_niter = 0;
    d->solve_resid = resid0;
    goto root;
  }

  /* initialize */
  status = s->fdf ? gsl_multiroot_fdfsolver_set(s->sfdf, &s->fn_fdf, s->x)
                  : gsl_multiroot_fsolver_set(s->sf, &s->fn_f, s->x);
  if (status == GSL_EBADFUNC)
    RPS3_ERROR(d, RPS3_EINVAL,
               "constraints (8)-(10) do not evaluate at the starting point "
               "(lengths %g, %g, %g m): %s", d->l[0], d->l[1], d->l[2],
               gsl_strerror(status));
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
                   "residual %.3g > tol %.3g unchanged", iter, resid,
                   m->opt.tol);
      RPS3_ERROR(d, RPS3_ENOCONV, "solver stopped after %d iterations: %s",
                 iter, gsl_strerror(status));
    }
  }

root:
  /* the branch 0 < theta < pi, after folding whole turns */
  same = 1;
  for (i = 0; i < 3; i++) {
    double t = th[i];
    if (!(t > 0.0 && t < RPS3_PI)) t = remainder(th[i], 2.0 * RPS3_PI);
    if (!(t > 0.0 && t < RPS3_PI))
      RPS3_ERROR(d, RPS3_EBRANCH,
                 "link %d: theta = %.6g rad is outside (0, pi)", i + 1, t);
    d->theta[i] = t;
    same = same && t == s->p.q.th[i];
  }
  /* (12)-(14) with the trig of the last evaluation when it was at this
     theta (bitwise: the same cos and sin) */
  if (same)
    rps3_links_from_trig(m, d, s->p.q.c, s->p.q.s);
  else
    rps3_links_from_joints(m, d);
  rps3_frame_from_balls(m, d);
  RPS3_CHECK_FINITE(d, d->b, 9, "b");
  RPS3_CHECK_FINITE(d, d->c, 3, "c");
  RPS3_CHECK_FINITE(d, d->rot, 9, "rot");
  /* a pose (alpha, beta, z_c) has rot = Rz(alpha) Ry(beta) Rz(-alpha) (2),
     whose upper-left block has trace 2 - (1 - cos beta) >= 0.  (8)-(10)
     have a second family of roots with 0 < theta < pi: the ball joints
     reflected through the Z axis, (x, y) -> (-x, -y), each still in its
     pin plane -- the platform spun by pi about its normal, trace
     -(1 + cos beta) <= 0.  No pose describes it, so it is not a solution */
  if (d->rot[0][0] + d->rot[1][1] < 0.0) {
    d->have_theta = 0;
    RPS3_ERROR(d, RPS3_EBRANCH,
               "root theta = (%.6g, %.6g, %.6g) is the platform spun by pi "
               "about its normal (ball joints reflected through the Z axis), "
               "which no pose (alpha, beta, z_c) describes",
               d->theta[0], d->theta[1], d->theta[2]);
  }
  /* the assembly mode: flag a warm-started sequence that changed it, and
     refuse one the caller excluded.  The positions are final: the
     Jacobian for the later stages */
  if (J == NULL) J = &own;
  rps3_cjac_eval(d, J);
  d->mode = rps3_mode_of_jac(M3C(J->Jt));
  if (prev_mode != RPS3_MODE_ANY && d->mode != prev_mode)
    d->warn |= RPS3_WARN_MODE;
  if (m->opt.mode != RPS3_MODE_ANY && d->mode != m->opt.mode) {
    d->have_theta = 0;
    RPS3_ERROR(d, RPS3_EMODE,
               "root theta = (%.6g, %.6g, %.6g) is in assembly mode %d "
               "(sign of det df/dtheta; +1 the level platform's), opt.mode "
               "asks for %d", d->theta[0], d->theta[1], d->theta[2], d->mode,
               m->opt.mode);
  }
  d->have_theta = 1;
  d->stage = RPS3_STAGE_POS;
  return RPS3_OK;
}

int rps3_fk(const rps3_model *m, rps3_data *d) {
  int status = rps3_theta_solve(m, d);
  if (status != RPS3_OK) return status;
  rps3_pose_from_frame(d);
  RPS3_CHECK_FINITE(d, d->pose, 3, "pose");
  return RPS3_OK;
}

void rps3_pose_from_frame(rps3_data *d) {
  double a1, a2, a3, sb;
  /* a = rot e_z = (sin b cos a, sin b sin a, cos b) for Rz(a) Ry(b) Rz(-a) */
  a1 = d->rot[0][2];
  a2 = d->rot[1][2];
  a3 = d->rot[2][2];
  sb = hypot(a1, a2);
  d->pose[1] = atan2(sb, a3);
  if (d->pose[1] < 1e-9) {
    /* alpha is a free gauge at beta = 0: report 0 and say so */
    d->pose[0] = 0.0;
    d->warn |= RPS3_WARN_ALPHA;
  } else {
    d->pose[0] = atan2(a2, a1);
  }
  d->pose[2] = d->c[2];
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
