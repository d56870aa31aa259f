/*
 * testutil.h - shared helpers of the C unit tests: named tolerances, a
 * deterministic generator of high-entropy inputs, and relative checks.
 *
 * Every C test leaves GSL's default error handler on (it aborts): the
 * library must never reach it, whatever the input.  Only test_nomem.c,
 * which fails GSL's own allocations on purpose, turns it off.
 */
#ifndef RPS3_TESTUTIL_H
#define RPS3_TESTUTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <gsl/gsl_errno.h>

#include "rps3.h"

/*
 * Tolerances, each with its reason.
 * TOL_EXACT: two exact formulas of one quantity differ only by rounding;
 *   with condition numbers ~10 and ~100 operations that is < 1e-13, and
 *   1e-12 leaves room without hiding a wrong term (which shows at 1e-3).
 * TOL_PHYS: identities that hold exactly along a trajectory (energy rate,
 *   Lagrange = Newton-Euler, sum of effects): 1e-9, the project's
 *   required agreement.
 * TOL_FD: central differences with step h: truncation h^2 |f'''| / 6 plus
 *   rounding eps |f| / h; h = 1e-5 s gives ~1e-10 + 1e-11 relative on these
 *   smooth functions, and 1e-7 is a bound with margin.
 */
#define TOL_EXACT 1e-12

#define PI 3.14159265358979323846
#define TOL_PHYS 1e-9
#define TOL_FD 1e-7

/* splitmix64: deterministic, no global state */
static inline double rnd_uniform(uint64_t *s, double lo, double hi) {
  uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return lo + (hi - lo) * (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* rps3_traj_check refuses trajectory tr_ for model m_, naming field id_
   and its component (or row) comp_, or the test fails with the message */
#define TRAJ_REFUSED(m_, tr_, id_, comp_)                                     \
  do {                                                                        \
    rps3_check chk_;                                                          \
    assert_int_equal(rps3_traj_check(&(m_), &(tr_), &chk_), RPS3_EINVAL);  \
    if (chk_.field != (id_) || chk_.comp != (comp_))                          \
      fail_msg("field %d[%d], want %d[%d]: %s", chk_.field, chk_.comp, id_,   \
               comp_, chk_.msg);                                              \
  } while (0)

/* |got - want| <= rtol * max(|want|, scale) or fail with a message */
#define CHECK_REL(got, want, rtol, scale, ...)                                \
  do {                                                                        \
    double g_ = (got), w_ = (want), s_ = fabs(w_) > (scale) ? fabs(w_)        \
                                                             : (scale);       \
    if (!(fabs(g_ - w_) <= (rtol) * s_)) {                                    \
      print_error("got %.17g want %.17g (rel err %.3g > %.3g): ", g_, w_,     \
                  fabs(g_ - w_) / s_, (double)(rtol));                        \
      print_error(__VA_ARGS__);                                               \
      print_error("\n");                                                      \
      fail();                                                                 \
    }                                                                         \
  } while (0)

/* a model with high-entropy parameters (not Table II), all effects on */
static inline void model_entropy(rps3_model *m) {
  rps3_model_default(m);
  m->R = 0.2385;
  m->rho = 0.4387;
  m->M = 0.2381;
  m->m = 0.0917;
  m->d = 0.1383;
  m->link_Ic = 3.17e-4;
  m->g = 9.80665;
  m->payload.mass = 0.0713;
  m->payload.com[0] = 0.0127;
  m->payload.com[1] = -0.0083;
  m->payload.com[2] = 0.0411;
  m->payload.inertia[0] = 1.13e-4;
  m->payload.inertia[1] = 1.71e-4;
  m->payload.inertia[2] = 0.97e-4;
  m->friction.viscous = 0.0137;
  m->friction.coulomb = 0.0029;
  m->opt.effects = RPS3_EFF_ALL;
}

/* a smooth trajectory that exercises every pose coordinate, from seed s */
static inline void traj_random(rps3_traj *tr, uint64_t *s) {
  int k;
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_SINE;
  tr->sine.mean[0] = rnd_uniform(s, -3.0, 3.0);
  tr->sine.amp[0] = rnd_uniform(s, 0.2, 1.5);
  tr->sine.mean[1] = rnd_uniform(s, 0.12, 0.35);
  tr->sine.amp[1] = rnd_uniform(s, 0.02, 0.1);
  tr->sine.mean[2] = rnd_uniform(s, 0.22, 0.35);
  tr->sine.amp[2] = rnd_uniform(s, 0.01, 0.06);
  for (k = 0; k < 3; k++) {
    tr->sine.freq[k] = rnd_uniform(s, 0.3, 2.1);
    tr->sine.phase[k] = rnd_uniform(s, -3.1, 3.1);
  }
  tr->sine.duration = 2.0;
}

static inline void copy_motion(rps3_data *dst, const rps3_data *src) {
  memcpy(dst->pose, src->pose, sizeof(src->pose));
  memcpy(dst->dpose, src->dpose, sizeof(src->dpose));
  memcpy(dst->ddpose, src->ddpose, sizeof(src->ddpose));
}

/*
 * Tilt beta* at which link 1 lies in the platform plane for alpha = 0 and
 * height z (theta_1 = beta): the lambda system is singular there.  Found by
 * bisection on theta_1(beta) - beta to the last bit, between lo and hi.
 */
static inline double singular_beta(const rps3_model *m, rps3_data *d,
                                   double z, double lo, double hi) {
  int it;
  for (it = 0; it < 200 && lo < hi; it++) {
    double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    d->pose[0] = 0.0;
    d->pose[1] = mid;
    d->pose[2] = z;
    if (rps3_ik(m, d) != RPS3_OK) return (double)NAN;
    if (d->theta[0] - mid > 0) lo = mid; else hi = mid;
  }
  return lo;
}

#endif
