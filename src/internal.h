/*
 * internal.h - helpers shared by the library's source files; not installed.
 */
#ifndef RPS3_INTERNAL_H
#define RPS3_INTERNAL_H

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cjac.h"
#include "policy.h"
#include "rps3.h"

#define RPS3_SQRT3 1.7320508075688772935
#define RPS3_PI 3.14159265358979323846

/* C99 does not convert double (*)[3] to const double (*)[3] implicitly */
#define M3C(A) ((const double(*)[3])(A))

/*
 * Record an error in d->err and return its code from the calling function.
 * snprintf writes into the fixed buffer of the data: no allocation, no I/O.
 */
#define RPS3_ERROR(d, code_, ...)                              \
  do {                                                         \
    (d)->err.code = (code_);                                   \
    (d)->err.func = __func__;                                  \
    (d)->err.file = __FILE__;                                  \
    (d)->err.line = __LINE__;                                  \
    snprintf((d)->err.msg, sizeof((d)->err.msg), __VA_ARGS__); \
    rps3_error_hook((d)->err.code);                            \
    return (code_);                                            \
  } while (0)

/*
 * The last check of every status-returning function: the n values at a are
 * finite, or RPS3_ERANGE with a message naming the quantity (name) and the
 * first non-finite component.  The inputs were checked finite on entry, so
 * a non-finite result is an overflow of finite inputs.
 */
#define RPS3_CHECK_FINITE(d, a, n, name)                                \
  do {                                                                  \
    if (!rps3_all_finite((const double *)(a), (n))) {                   \
      int k_ = rps3_first_nonfinite((const double *)(a), (n));          \
      RPS3_ERROR(d, RPS3_ERANGE,                                        \
                 "%s[%d] = %g is not finite: finite inputs overflowed " \
                 "(a mass, length or rate too large)",                  \
                 (name), k_, ((const double *)(a))[k_]);                \
    }                                                                   \
  } while (0)

/* index of the first non-finite of the n values at a, -1 if all finite */
int rps3_first_nonfinite(const double *a, int n);

/* whether the n values at a are all finite: inline and without a branch
   per value (every stage checks its outputs at every point); a NaN
   compares false */
static inline int rps3_all_finite(const double *a, int n) {
  int k, ok = 1;
  for (k = 0; k < n; k++) ok &= (fabs(a[k]) <= DBL_MAX);
  return ok;
}

/* An empty function to put a breakpoint on: every error passes here.
   Cold: the compiler lays the paths that reach it (the error messages'
   snprintf) out of the per-point code */
#if defined(__GNUC__)
__attribute__((cold))
#endif
void rps3_error_hook(int code);

/* field.c: reset a check; record a failure of field (component comp) with
   value and reason, naming up to two related fields; returns RPS3_EINVAL */
void rps3_check_clear(rps3_check *chk);
int rps3_check_fail(rps3_check *chk, int field, int comp, double value,
                    int rel0, int rel1, const char *why);
/* 1 when x is finite and inside the range of row f */
int rps3_field_in_range(const rps3_field_info *f, double x);
/* the range check of every row of RPS3_FIELDS held in `in` (enum
   rps3_field_in) by the structure at base; RPS3_OK or RPS3_EINVAL */
int rps3_fields_check(int in, const void *base, rps3_check *chk);

/* timelaw.c: s, s', s'' (per unit tau) of time law `law` (blend fraction f
   for LSPB; QUINTIC is taken as MINJERK) at tau in [0, 1]; its peak rate
   and acceleration */
void rps3_law_eval(int law, double f, double tau, double s[3]);
void rps3_law_peaks(int law, double f, double *vpeak, double *apeak);
/* waypoints: span, evaluation at t in [0, span], validation */
double rps3_waypoints_duration(const rps3_waypoints *w);
int rps3_waypoints_eval(const rps3_waypoints *w, double t, double q[3],
                        double dq[3], double ddq[3]);
int rps3_waypoints_check(const rps3_model *m, const rps3_waypoints *w,
                         rps3_check *chk);
/* 1 when rps3_ik accepts the pose (a local workspace, no allocation) */
int rps3_pose_reachable(const rps3_model *m, const double pose[3]);
/* 1 when a motion's rates and accelerations are finite and so are the
   rates' squares, which the dynamics form (velocity products): what
   rps3_traj_check asks of every sample of every kind */
static inline int rps3_motion_finite(const double dq[3], const double ddq[3]) {
  int k;
  for (k = 0; k < 3; k++)
    if (!isfinite(dq[k] * dq[k]) || !isfinite(ddq[k])) return 0;
  return 1;
}
/* path.c: evaluation (RPS3_EREACH off 0 < rho_c < r/2), validation */
int rps3_path_eval(const rps3_model *m, const rps3_path *p, double t,
                   double q[3], double dq[3], double ddq[3]);
int rps3_path_check(const rps3_model *m, const rps3_path *p, rps3_check *chk);
double rps3_path_duration(const rps3_path *p);

/* table.c: span, evaluation at t in [0, span] (rows checked), validation
   naming the fields id[] = {time, value, rate, acc}; pose: the values are
   poses, each row and the interpolant between rows must be reachable */
double rps3_table_duration(const rps3_table *tb);
size_t rps3_table_eval(const rps3_table *tb, double t, double q[3],
                       double dq[3], double ddq[3]); /* returns the segment */
int rps3_table_check(const rps3_model *m, const rps3_table *tb, const int id[4],
                     int pose, rps3_check *chk);

/* internal state of the theta solve, owned by rps3_data */
struct rps3_solver_state;
int rps3_solver_alloc(const rps3_model *m, struct rps3_solver_state **out);
void rps3_solver_free(struct rps3_solver_state *s);

/* sines and cosines of a pose (alpha, beta), computed once per point and
   shared by the stages of rps3_inverse; cb is left out (NaN) when with_cb
   is 0, for rps3_velocity alone, which does not read it */
typedef struct {
  double ca, sa; /* cos, sin alpha */
  double sb, cb; /* sin, cos beta */
  double vb;     /* 1 - cos beta as 2 sin^2(beta/2) */
  double C, S;   /* cos 2 alpha, sin 2 alpha */
} rps3_pose_trig;

static inline void rps3_pose_trig_eval(rps3_pose_trig *t, const double pose[3],
                                       int with_cb) {
  /* locals first: stores through t could alias pose, and would keep the
     compiler from pairing sin and cos into one sincos call */
  double alpha = pose[0], beta = pose[1];
  double ca = cos(alpha), sa = sin(alpha), sb = sin(beta);
  double cb = with_cb ? cos(beta) : (double)NAN, hb = sin(0.5 * beta);
  t->ca = ca;
  t->sa = sa;
  t->sb = sb;
  t->cb = cb;
  /* 1 - cos(beta) as 2 sin^2(beta/2): no cancellation as beta -> 0 */
  t->vb = 2.0 * hb * hb;
  t->C = ca * ca - sa * sa;
  t->S = 2.0 * sa * ca;
}

/* what rps3_ik_with computes besides c, rot, b, l */
enum {
  RPS3_IK_NO_THETA = 0, /* neither theta (39) nor the link directions: the
                           multiroot route computes them from the lengths */
  RPS3_IK_THETA = 1,    /* theta by (39) and the link directions */
  RPS3_IK_DIRS = 2 /* the link directions only, theta NaN (no RPS3_OUT_THETA) */
};

/*
 * The constraint Jacobian of (8)-(10) at one point's positions and the
 * lambda system of (23), (df/dtheta)^T, factored, with its condition
 * number: the assembly mode, the multiroot route's own-root check and the
 * inverse dynamics all read it.  Validity: rps3_inverse builds one a
 * point, in the stage that sets the positions (rps3_ik_with or
 * rps3_theta_solve_with, after the last write to b, l, phi, dphi), and
 * hands it to the later stages of the same call, which do not move the
 * positions.  It lives on that call's stack; rps3_data keeps none, so no
 * other call can read a Jacobian of other positions (a caller may write
 * d's positions between calls).  The public stage functions build their
 * own (a NULL rps3_cjac).
 */
typedef struct {
  double Jl[3][3], Jt[3][3]; /* Jl[k][i] = d f_k / d l_i, Jt: d / d theta_i */
  int factored;              /* the members below are set (rps3_cjac_factor) */
  int sing;                  /* a zero or non-finite pivot: LU unusable */
  double A[9], LU[9];        /* A = Jt^T row-major, and its LU with rows perm */
  int perm[3];
  double Ainv[9]; /* A^-1 row-major: (df/dtheta)^-1 = Ainv^T */
  double cond;    /* 1-norm condition number of A; HUGE_VAL if sing */
} rps3_cjac;

/* Jl and Jt at d's positions (rps3_constraint_jacobian), not factored */
void rps3_cjac_eval(const rps3_data *d, rps3_cjac *J);
/* factor the lambda system and its condition number, once */
void rps3_cjac_factor(rps3_cjac *J);
/* the assembly mode of Jt = df/dtheta: sign of its determinant */
int rps3_mode_of_jac(const double Jt[3][3]);

/* the stages with the pose's trig: rps3_ik_with fills *t and does what
   `theta` (RPS3_IK_*) says, and *J (may be NULL) when it sets theta or
   the link directions; the rate stages take t, or NULL to compute it */
int rps3_ik_with(const rps3_model *m, rps3_data *d, rps3_pose_trig *t,
                 int theta, rps3_cjac *J);
/* rps3_theta_solve, and the Jacobian at its root into *J (may be NULL) */
int rps3_theta_solve_with(const rps3_model *m, rps3_data *d, rps3_cjac *J);
/* rps3_inverse's multiroot route (src/inverse.c): keep the root d holds
   with its Jacobian J (factored) in d's solver state, and move the next
   point's start d->theta along the change of the lengths to d->l, to
   second order, when d->theta is still that root (the step no larger
   than max_step rad; one use of what was kept); 1 when it moved it */
void rps3_root_keep(const rps3_model *m, rps3_data *d, const rps3_cjac *J);
int rps3_root_predict(rps3_data *d, double max_step);
/* 1 when rps3_inverse and rps3_invdyn need the rates and accelerations:
   a dynamic effect is selected, or the certificate asked for */
static inline int rps3_need_rates(const rps3_model *m) {
  return (m->opt.effects & RPS3_EFF_DYNAMIC) ||
         (m->opt.outputs & RPS3_OUT_CERTIFY);
}
/* NaN into d's results of the outputs left out of m->opt.outputs (theta
   aside: the position stage's), has_lambda 0 without lambda (invdyn.c) */
void rps3_outputs_clear(const rps3_model *m, rps3_data *d);
/* the energy-rate certificate of d's point into d (power, dTdt, dPdt,
   friction_power, energy_residual, energy_scale; invdyn_certify.c) */
void rps3_certify(const rps3_model *m, rps3_data *d);
/* rps3_invdyn with this point's Jacobian (NULL: built here) */
int rps3_invdyn_with(const rps3_model *m, rps3_data *d, rps3_cjac *J);

/* the ten standard parameters of body b in its frame (RPS3_NSTD's
   order; model.c) */
void rps3_body_std(const rps3_body *b, double p[10]);

/* the Newton-Euler wrench about its origin O (force f, moment n, base
   frame) of a body of standard parameters p (body axes e: e[k] axis k in
   the base frame) turning at omega, omega', O accelerating at a less
   gravity (a = a_O + g e_z): f = m a + omega' x h + omega x (omega x h),
   n = I omega' + omega x I omega + h x a (bodies.c) */
void rps3_body_wrench(const double p[10], const double e[3][3],
                      const double om[3], const double dom[3],
                      const double a[3], double f[3], double n[3]);
/* its rows: f = Wf p, n = Wn p */
void rps3_body_wrench_rows(const double e[3][3], const double om[3],
                           const double dom[3], const double a[3],
                           double Wf[3][10], double Wn[3][10]);
/* leg i's loads per unit standard parameter, its cylinder's (0-9) and
   piston's (10-19): wl = WL . p, wt = WT . p (arguments as
   rps3_leg_loads) */
void rps3_leg_rows(const rps3_model *m, int i, const double phi[3],
                   const double dphi[3], double l, double dth, double ddth,
                   const double bdd[3], double g, double WL[20],
                   double WT[20]);

/* the certificate's dT/dt (*pT) and dP/dt (*pP) of a general body whose
   origin moves at vO, aO, turning at omega, omega' (bodies.c); *s the
   magnitude of their terms */
void rps3_body_power(const double p[10], const double e[3][3],
                     const double vO[3], const double aO[3],
                     const double om[3], const double dom[3], double g,
                     double *pT, double *pP, double *s);

/* the loads of leg i's general bodies (bodies.c) on (l_i, theta_i): its
   weight (g, bdd NULL, the rates 0) or its inertia (g 0, bdd the ball
   joint's acceleration b_i'', the link's theta' and theta''), from the
   standard parameters m->std of its cylinder and piston */
void rps3_leg_loads(const rps3_model *m, int i, const double phi[3],
                    const double dphi[3], double l, double dth, double ddth,
                    const double bdd[3], double g, double *wl, double *wt);

/* kinematic quantities of the Lagrange route at one point (invdyn.c) */
typedef struct {
  double bdd[3][3];                      /* ball joint accelerations */
  double n[3], o[3];                     /* frame columns (18)-(19) */
  double cdd[3], ndd[3], odd[3], add[3]; /* second time derivatives */
} rps3_lag_kin;

/*
 * The pieces of rps3_invdyn that the regressor (src/ident.c) pushes unit
 * parameters through, so that its columns are the formulation's own
 * loads and solve (invdyn.c).  rps3_loads_prepare runs rps3_invdyn's
 * singularity checks at d's positions (J their Jacobian) and keeps what
 * every load of the point reads: the Lagrange route's kinematics, or the
 * Newton-Euler system factored.  rps3_loads_effect: the right-hand side
 * of effect e (index, bit 1 << e) computed with the parameters of u, a
 * model of m's geometry (its masses, payload and friction may differ);
 * Lagrange: the loads on (l, theta), Newton-Euler: the system's
 * right-hand side.  rps3_loads_solve: the forces of ncol <=
 * RPS3_LOADS_MAXCOL right-hand sides (rhs overwritten) into F[i * ldf +
 * col], i the actuator.
 */
#define RPS3_LOADS_MAXCOL RPS3_NSTD
typedef struct {
  int method;       /* m->opt.method */
  rps3_lag_kin k;   /* Lagrange */
  double rho[3][3]; /* Newton-Euler: b_i - c */
  double LU6[36];   /* Newton-Euler: the system, factored */
  int perm6[6];
  const rps3_cjac *J; /* the point's Jacobian, factored */
} rps3_loads;
int rps3_loads_prepare(const rps3_model *m, rps3_data *d, rps3_cjac *J,
                       rps3_loads *L);
void rps3_loads_effect(const rps3_model *u, const rps3_data *d,
                       const rps3_loads *L, int e, double rhs[6]);
/* a regressor column's right-hand side: the loads of the effects among
   `effects` that m selects, computed with u's parameters, summed */
void rps3_loads_column(const rps3_model *m, const rps3_model *u,
                       const rps3_data *d, const rps3_loads *L, int effects,
                       double rhs[6]);
void rps3_loads_solve(const rps3_loads *L, int ncol, double (*rhs)[6],
                      double *F, int ldf);
/* Fb: the forces of unit leg loads, column j the load 1 on l_j (j < 3) or
   on theta_{j-3}, through L's method */
void rps3_loads_leg_basis(const rps3_data *d, const rps3_loads *L,
                          double Fb[3][6]);
/* the Lagrange route's loads (the left-hand side of (23): w[0..2] on l,
   w[3..5] on theta) of the effects `effects` (RPS3_EFF_* bits), summed,
   at the point t: reads its l, phi, dphi, the frame's n and o (rot's
   first two columns), dl, dtheta, ddl and ddtheta (invdyn.c) */
void rps3_lagrange_loads(const rps3_model *m, const rps3_data *t, int effects,
                         double w[6]);
/* Newton-Euler (invdyn_ne.c): the 6x6 system at d's point factored into
   LU, perm with rho_i = b_i - c (0, or -1 when singular); effect e's
   right-hand side; and the whole formulation's F into d */
int rps3_ne_system(const rps3_model *m, const rps3_data *d, double LU[36],
                   int perm[6], double rho[3][3]);
void rps3_ne_rhs(const rps3_model *m, const rps3_data *d,
                 const double rho[3][3], int e, double x[6]);
/* the right-hand side of leg loads w alone (w[i] on l_i, w[3 + i] on
   theta_i, as the Lagrange route's): the piston's share on F_i, the ball
   force's dphi_i component s_i = -w[3 + i] / l_i */
void rps3_ne_rhs_legs(const rps3_data *d, const double rho[3][3],
                      const double w[6], double x[6]);
int rps3_newton_euler(const rps3_model *m, rps3_data *d);
/* rot diag(I) rot^T v, and the payload's centre of mass relative to c
   with its velocity and acceleration (invdyn_ne.c; also the certificate's) */
void rps3_inertia_apply(double res[3], const double rot[3][3],
                        const double I[3], const double v[3]);
void rps3_payload_kin(const rps3_model *m, const rps3_data *d, double rg[3],
                      double vg[3], double ag[3]);
/* prefix d->err.msg with "point I: " (batch.c), for a batch's first
   failing point */
void rps3_batch_name_point(rps3_data *d, int status, size_t i);
/* rps3_inverse's positions and, when need_rates, rates and accelerations
   (inverse.c), with the point's Jacobian into *J */
int rps3_inverse_motion(const rps3_model *m, rps3_data *d, rps3_cjac *J,
                        int need_rates);
int rps3_velocity_with(const rps3_model *m, rps3_data *d,
                       const rps3_pose_trig *pt);
/* the platform's frame (2)-(4) at height z, its twist (omega, vc) and the
   twist's rate (domega, ac) from the pose's trigonometry and rates */
void rps3_pose_frame(const rps3_model *m, const rps3_pose_trig *t, double z,
                     double rot[3][3], double c[3]);
void rps3_pose_twist(const rps3_model *m, const rps3_pose_trig *t,
                     const double dpose[3], double w[3], double vc[3]);
void rps3_pose_twist_rate(const rps3_model *m, const rps3_pose_trig *t,
                          const double dpose[3], const double ddpose[3],
                          const double w[3], double dw[3], double ac[3]);
/* rps3_link_motion (a controller's desired motion) is public: rps3.h */
int rps3_acceleration_with(const rps3_model *m, rps3_data *d,
                           const rps3_pose_trig *pt);

/* positions of the ball joints b_i and the link unit vectors from (l, theta),
   eqs. (12)-(14) and (29); then the platform frame from b, (11), (18)-(20) */
void rps3_link_dirs(const rps3_model *m, rps3_data *d);
void rps3_links_from_joints(const rps3_model *m, rps3_data *d);
/* the same with cos and sin of d->theta given (c[i], s[i]) */
void rps3_links_from_trig(const rps3_model *m, rps3_data *d, const double c[3],
                          const double s[3]);
void rps3_frame_from_balls(const rps3_model *m, rps3_data *d);

/* the theta solve's (8)-(10) in units of R, f_k(theta) for lengths L = l / R,
   and the analytic Jacobian J = df/dtheta it hands to GSL (J may be NULL) */
void rps3_theta_constraints(const double L[3], double rho, const double th[3],
                            double f[3], double J[3][3]);
/* the same from the cosines c and sines s of theta */
void rps3_theta_constraints_trig(const double L[3], double rho,
                                 const double c[3], const double s[3],
                                 double f[3], double J[3][3]);

/* the pose (alpha, beta, z_c) of the frame rot, c, as rps3_fk reports it
   (alpha = 0 and RPS3_WARN_ALPHA when beta ~ 0) */
void rps3_pose_from_frame(rps3_data *d);

/* assembly mode of the current positions (enum rps3_mode): the sign of
   det(df/dtheta), positive for every level platform */
int rps3_mode_of(const rps3_data *d);

/* constraint Jacobian blocks of f_k = |b_i - b_j|^2 - 3 r^2 (8)-(10):
   Jl[k][i] = d f_k / d l_i, Jt[k][i] = d f_k / d theta_i */
void rps3_constraint_jacobian(const rps3_data *d, double Jl[3][3],
                              double Jt[3][3]);

/* the friction law of rps3_friction, the force (or torque) that opposes
   the rate v, with the sign of v: viscous v + coulomb s(v), s the exact
   sign (sign(0) = 0) or, with vreg > 0, the smooth tanh(v / vreg).  Pins
   and prismatic joints share it */
static inline double rps3_friction_law(const rps3_friction *f, double v) {
  double s;
  if (f->vreg > 0.0)
    s = tanh(v / f->vreg);
  else
    s = (double)((v > 0) - (v < 0));
  return f->viscous * v + f->coulomb * s;
}

/* pin friction torque on link i, opposing theta-dot: the law of its pin
   (rps3_model.pinf) */
static inline double rps3_friction_torque(const rps3_model *m, int i,
                                          double dtheta) {
  return -rps3_friction_law(&m->pinf[i], dtheta);
}

/* angular velocity (or acceleration) of the platform from the motion u_i
   of its ball joints relative to the centre, rho_i = b_i - c, a the
   platform normal: (26)-(28) solved for omega in closed form */
void rps3_omega_from_balls(double omega[3], const double rho[3][3],
                           const double u[3][3], const double a[3], double r);

/* the parts of rps3_joint_velocity and rps3_joint_acceleration after their
   solve with df/dtheta: vc, omega, dpose from dtheta; Jt ddtheta = x and
   b'' without its ddtheta part (known); ac, domega from ddtheta and
   known.  The _from parts end
   with the stage's finiteness checks and set its stage bit; dpose = 0
   leaves the pose rates out (NaN) */
int rps3_joint_velocity_from(const rps3_model *m, rps3_data *d, int dpose);
/* the pose rates (alpha, beta, z_c)' from omega and vc (RPS3_WARN_ALPHA
   and alpha' = 0 where beta ~ 0) */
void rps3_pose_rates(rps3_data *d);
void rps3_joint_acc_rhs(const rps3_data *d, double known[3][3], double x[3]);
/* the same from its parts: D[k] = b_k - b_(k+1) of the pairs of (8)-(10),
   the links' phi, dphi, l, their rates dl, dtheta and ddl (NULL: 0) */
void rps3_constraint_acc_rhs(const double D[3][3], const double phi[3][3],
                             const double dphi[3][3], const double l[3],
                             const double dl[3], const double dth[3],
                             const double ddl[3], double known[3][3],
                             double x[3]);
int rps3_joint_acc_from(const rps3_model *m, rps3_data *d,
                        const double known[3][3]);
/* df/dtheta factored for the rate stages (RPS3_ESING when singular or
   conditioned worse than opt.cond_max) */
int rps3_jt_factor(const rps3_model *m, rps3_data *d, const double Jt[3][3],
                   double LU[9], int perm[3]);

/* index of name in names[0..n), or -1 (NULL name: -1) */
static inline int rps3_name_lookup(const char *const *names, int n,
                                   const char *name) {
  int k;
  if (name == NULL) return -1;
  for (k = 0; k < n; k++)
    if (strcmp(name, names[k]) == 0) return k;
  return -1;
}

/* ----------------------------------------------------------- 3-vectors */

static inline double v3_dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(double res[3], const double a[3],
                            const double b[3]) {
  double t0 = a[1] * b[2] - a[2] * b[1];
  double t1 = a[2] * b[0] - a[0] * b[2];
  double t2 = a[0] * b[1] - a[1] * b[0];
  res[0] = t0;
  res[1] = t1;
  res[2] = t2;
}

/* res = a + s b */
static inline void v3_axpy(double res[3], const double a[3], double s,
                           const double b[3]) {
  res[0] = a[0] + s * b[0];
  res[1] = a[1] + s * b[1];
  res[2] = a[2] + s * b[2];
}

static inline void v3_scale(double res[3], double s, const double a[3]) {
  res[0] = s * a[0];
  res[1] = s * a[1];
  res[2] = s * a[2];
}

static inline void v3_sub(double res[3], const double a[3], const double b[3]) {
  res[0] = a[0] - b[0];
  res[1] = a[1] - b[1];
  res[2] = a[2] - b[2];
}

static inline void v3_copy(double res[3], const double a[3]) {
  res[0] = a[0];
  res[1] = a[1];
  res[2] = a[2];
}

static inline double v3_norm(const double a[3]) { return sqrt(v3_dot(a, a)); }

/* res = A v */
static inline void m3_mulv(double res[3], const double A[3][3],
                           const double v[3]) {
  double t0 = A[0][0] * v[0] + A[0][1] * v[1] + A[0][2] * v[2];
  double t1 = A[1][0] * v[0] + A[1][1] * v[1] + A[1][2] * v[2];
  double t2 = A[2][0] * v[0] + A[2][1] * v[1] + A[2][2] * v[2];
  res[0] = t0;
  res[1] = t1;
  res[2] = t2;
}

/* res = A^T v */
static inline void m3_mulvt(double res[3], const double A[3][3],
                            const double v[3]) {
  double t0 = A[0][0] * v[0] + A[1][0] * v[1] + A[2][0] * v[2];
  double t1 = A[0][1] * v[0] + A[1][1] * v[1] + A[2][1] * v[2];
  double t2 = A[0][2] * v[0] + A[1][2] * v[1] + A[2][2] * v[2];
  res[0] = t0;
  res[1] = t1;
  res[2] = t2;
}

/* x - x is +0 for a finite x and NaN for an infinite or NaN one: one test
   without branches, exact (the build never uses -ffast-math) */
static inline int v3_finite(const double a[3]) {
  return (a[0] - a[0]) + (a[1] - a[1]) + (a[2] - a[2]) == 0.0;
}

#endif /* RPS3_INTERNAL_H */
