/*
 * theta.h - the theta solve's pieces in the links' planes, written once:
 * the closure (8)-(10) at one theta for given link lengths, the series
 * step of theta's cosines and sines, the warm Newton path and the root
 * predictor.  The solve itself is rps3_theta_solve_with (src/fk.c): from a
 * warm start the Newton path below, else (a cold start, or Newton not
 * converging) GSL's multiroot; the forward dynamics (src/fwddyn.c) calls
 * the same Newton path and falls back to the same multiroot route.
 *
 * Link i moves in the vertical plane of pin i, its ball joint at b_i = h_i
 * u_i + Z_i e_z with h_i = R - l_i cos theta_i, Z_i = l_i sin theta_i
 * ((12)-(14)); the pair k = (i, j), j = i + 1 (mod 3), of (8)-(10) and its
 * derivatives are rps3_plane_pair of src/cjac.h.  The unit of length is
 * the caller's: rps3_theta_solve works in units of R (R = 1, as GSL's
 * evaluations), the forward dynamics in metres.
 *
 * Not installed.
 */
#ifndef RPS3_THETA_H
#define RPS3_THETA_H

#include "cjac.h"
#include "internal.h"

/* largest predicted change of a theta_i [rad] from the last root, and the
   largest Newton correction whose cosine and sine rps3_trig_step moves by
   its series: ~0.6 degree, many steps of any run that keeps its accuracy;
   a larger predicted step (a jump, or near a singular configuration, where
   G grows) starts from the last root itself */
#define RPS3_THETA_PREDICT_MAX 1e-2

/* largest Newton correction [rad] of the warm path: beyond it the
   linearisation's error, of relative order the step (theta enters
   through its cosine and sine), passes 10 %, a full Newton step may jump
   to another root, and the start is not warm: the multiroot route, whose
   trust region copes with it, takes over (tests/test_hardcases.c,
   bad_guesses, counts the roots either finds from far starts) */
#define RPS3_THETA_WARM_MAX 0.1

/* the pieces below are meant to compile into their callers' loops (GCC
   otherwise keeps some out of line: a call, and its arguments through
   memory) */
#if defined(__GNUC__)
#define THETA_INLINE static inline __attribute__((always_inline))
#else
#define THETA_INLINE static inline
#endif

/* (8)-(10) at one theta: the lengths, theta, its cosines and sines, and
   each pair's terms there (rps3_plane_pair), in one unit of length */
typedef struct {
  double R, r3;            /* R and 3 r^2 in the unit of length */
  double l[3];             /* link lengths */
  double th[3];            /* theta [rad] */
  double c[3], s[3];       /* cos and sin theta */
  double A[3], B[3], E[3]; /* of pair k (src/cjac.h) */
  double at[3], bt[3];     /* df_k/dtheta_k, df_k/dtheta_(k+1) */
} rps3_closure;

/* the pairs of (8)-(10) at q's l, c, s: f_k into f and A, B, E, at, bt
   into q */
THETA_INLINE void rps3_closure_eval(rps3_closure *q, double f[3]) {
  double h[3], Z[3];
  int i, k;
  for (i = 0; i < 3; i++) {
    h[i] = q->R - q->l[i] * q->c[i];
    Z[i] = q->l[i] * q->s[i];
  }
  for (k = 0; k < 3; k++) {
    const int j = (k + 1) % 3;
    const rps3_plane_pair pk =
        rps3_plane_pair_eval(h[k], h[j], Z[k], Z[j], q->l[k], q->l[j], q->c[k],
                             q->s[k], q->c[j], q->s[j], q->r3);
    q->A[k] = pk.A;
    q->B[k] = pk.B;
    q->E[k] = pk.E;
    f[k] = pk.f;
    q->at[k] = pk.at;
    q->bt[k] = pk.bt;
  }
}

/*
 * The velocity products of (8)-(10) at q for the rates l' = dl, theta' =
 * dth: the second derivative of f along the motion without theta'',
 * (df/dtheta) theta'' = x with
 *   x_k = -(2 |b_i' - b_j'|^2 + A h_i''0 + B h_j''0 + E (Z_i''0 - Z_j''0))
 * (rps3_constraint_acc_rhs in the links' planes; ''0: at theta'' = 0,
 * l'' = 0), and the rates h', Z' and the accelerations h''0, Z''0 of the
 * ball joints in their planes.
 */
THETA_INLINE void rps3_closure_bias(const rps3_closure *q, const double dl[3],
                                    const double dth[3], double x[3],
                                    double hd[3], double Zd[3], double hdd[3],
                                    double Zdd[3]) {
  int i, k;
  for (i = 0; i < 3; i++) {
    const double lth = q->l[i] * dth[i], v = 2.0 * dl[i] * dth[i];
    hd[i] = q->s[i] * lth - q->c[i] * dl[i];
    Zd[i] = q->s[i] * dl[i] + q->c[i] * lth;
    hdd[i] = q->s[i] * v + q->c[i] * lth * dth[i];
    Zdd[i] = q->c[i] * v - q->s[i] * lth * dth[i];
  }
  for (k = 0; k < 3; k++) {
    const int j = (k + 1) % 3;
    const double dz = Zd[k] - Zd[j];
    x[k] = -(2.0 * (hd[k] * hd[k] + hd[j] * hd[j] + hd[k] * hd[j] + dz * dz) +
             q->A[k] * hdd[k] + q->B[k] * hdd[j] + q->E[k] * (Zdd[k] - Zdd[j]));
  }
}

/*
 * c, sn of theta - e from those of theta, for |e| <= RPS3_THETA_PREDICT_MAX:
 * the series of cos e to e^6 / 720 and of sin e to e^7 / 5040 (the next
 * terms, e^8 / 40320 and e^9 / 362880, are below 2.5e-21), or, for |e| <=
 * 1e-5 (a Newton correction, or a predicted step of a slow motion), to e^2
 * / 2 and e^3 / 6 (the next, e^4 / 24 and e^5 / 120, below 4.2e-22); then
 * back onto the unit circle to first order, (3 - |.|^2) / 2, so that the
 * rounding of many steps does not build up in the magnitude (the callers
 * bound the steps between two sincos).  Not a sine of an angle but of a
 * small change of one: a sincos of theta costs more than the rest of a
 * Newton step.
 */
THETA_INLINE void rps3_trig_step(double c[3], double sn[3], const double e[3]) {
  const double a0 = fabs(e[0]), a1 = fabs(e[1]), a2 = fabs(e[2]);
  const double m01 = a0 > a1 ? a0 : a1, big = m01 > a2 ? m01 : a2;
  int i;
  for (i = 0; i < 3; i++) {
    const double x = e[i], x2 = x * x;
    double ce, se, cn, snn, g;
    if (big <= 1e-5) {
      ce = 1.0 - 0.5 * x2;
      se = x - x * x2 * (1.0 / 6.0);
    } else {
      ce = 1.0 - x2 * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0)));
      se = x *
           (1.0 - x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0))));
    }
    cn = c[i] * ce + sn[i] * se;
    snn = sn[i] * ce - c[i] * se;
    g = 1.5 - 0.5 * (cn * cn + snn * snn);
    c[i] = cn * g;
    sn[i] = snn * g;
  }
}

/*
 * The warm Newton path of the theta solve (src/fk.c): theta of (8)-(10)
 * for the lengths q->l by Newton's method from q->th, with its cosines and
 * sines in q->c, q->s when have_trig (else taken here), at most
 * min(8, opt.max_iter) steps, to rps3_theta_solve's test max |f_k| / R^2
 * <= opt.tol.  A correction of at most RPS3_THETA_PREDICT_MAX moves the
 * cosines and sines by rps3_trig_step, a larger one takes sincos, and one
 * beyond RPS3_THETA_WARM_MAX gives up.
 * Returns 0 when it converged to a root in (0, pi), 1 when to one after
 * folding whole turns (the folded angles' cosines and sines by sincos),
 * with the root in
 * q->th, its cosines and sines in q->c, q->s, the pair terms there in q,
 * the steps in *niter, max |f_k| / R^2 in *resid, and *exact 1 when c, s
 * are libm's cos and sin of th (no series step since the last sincos).
 * Returns -1 otherwise (non-finite, singular, no convergence, a root
 * outside (0, pi), or a root whose assembly mode, the sign of
 * det(df/dtheta), is not `mode`, the warm start's: RPS3_MODE_ANY takes
 * either): the caller falls back to the multiroot route, which decides
 * and reports.  The spun platform is the caller's to test, on its
 * positions.
 */
int rps3_theta_newton(const rps3_model *m, rps3_closure *q, int have_trig,
                      int mode, int *niter, double *resid, int *exact);

/*
 * The root predictor: the start of the next theta solve at the lengths l
 * from a root th0 at the lengths l0, where G = dtheta/dl = -(df/dtheta)^-1
 * (df/dl), to second order along a motion whose theta'' the caller has:
 *   th = th0 + G (l - l0) + (tau^2 / 2) Hv,
 * Hv the theta'' of l' = v, l'' = 0 for a direction v of the lengths
 * ((df/dtheta) Hv = x of rps3_closure_bias) and tau the motion's parameter
 * along it, theta along l(s) = l0 + s v being th0 + s G v + (s^2 / 2) Hv.
 * The callers' v and tau:
 *   - the multiroot route (rps3_root_predict): the chord itself, v = l -
 *     l0 and tau = 1, off by O(|l - l0|^3);
 *   - the forward dynamics: the last state's rates, whose bias Hv is
 *     formed already, and tau = (l - l0) . v / |v|^2, off by O(h^3) for an
 *     integrator's stages (RK4's second and fourth lie along the rates,
 *     its third off them by O(h^2));
 *   - a controller's measured state: the last state's rates and tau the
 *     time since it (G (l - l0) carries the length change exactly).
 * Writes th and returns 1, or returns 0 and leaves th alone when the step
 * exceeds max_step [rad] or is not finite (the last root is then the
 * start).  th may be th0.
 */
THETA_INLINE int rps3_theta_predict(double th[3], const double l[3],
                                    const double l0[3], const double th0[3],
                                    const double G[3][3], const double Hv[3],
                                    double tau, double max_step) {
  const double h = 0.5 * tau * tau;
  double dl[3], u[3], big;
  int i;
  for (i = 0; i < 3; i++) dl[i] = l[i] - l0[i];
  for (i = 0; i < 3; i++)
    u[i] = G[i][0] * dl[0] + G[i][1] * dl[1] + G[i][2] * dl[2] + h * Hv[i];
  {
    const double a0 = fabs(u[0]), a1 = fabs(u[1]), a2 = fabs(u[2]);
    const double m01 = a0 > a1 ? a0 : a1;
    big = m01 > a2 ? m01 : a2;
  }
  /* a NaN in u fails the first test or the second */
  if (!(big <= max_step) || !(u[0] + u[1] + u[2] == u[0] + u[1] + u[2]))
    return 0;
  for (i = 0; i < 3; i++) th[i] = th0[i] + u[i];
  return 1;
}

#endif /* RPS3_THETA_H */
