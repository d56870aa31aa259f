/*
 * theta_solver.h - the theta solve's workspace, shared by its two routes:
 * the warm Newton path and the acceptance of a root (fk.c) and GSL's
 * multiroot route (theta_gsl.c).  Internal.
 */
#ifndef RPS3_THETA_SOLVER_H
#define RPS3_THETA_SOLVER_H

#include <math.h>

#include <gsl/gsl_multiroots.h>

#include "internal.h"
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
  rps3_solver kind; /* the solver this state was built for */
  int fdf;          /* 1: fdfsolver (analytic Jacobian) */
  gsl_multiroot_fdfsolver *sfdf;
  gsl_multiroot_fsolver *sf;
  gsl_vector *x; /* starting point */
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

/* the components of a GSL vector (read and written in place: the views'
   accessors cost more than the evaluation's arithmetic) */
#define GV(v, k) ((v)->data[(size_t)(k) * (v)->stride])

static inline void trig3(const double th[3], double c[3], double s[3]) {
  int k;
  for (k = 0; k < 3; k++) {
    double t = th[k]; /* one sincos: c[k] may alias th[k] as far as the
                         compiler knows */
    c[k] = cos(t);
    s[k] = sin(t);
  }
}

/* the multiroot route (theta_gsl.c) */
int rps3_theta_multiroot(const rps3_model *m, rps3_data *d, double th[3]);

#endif /* RPS3_THETA_SOLVER_H */
