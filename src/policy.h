/*
 * policy.h - the one singularity policy of the library: what a measure of
 * a configuration's distance from the singular surface (8)-(10) makes of a
 * result, for every stage that measures one (rps3_invdyn, the rate stages,
 * the forward dynamics and the simulation that calls them, the batch
 * kernels' certificate).  Each measure has a warning threshold (a
 * warning bit, the result kept) and a hard one (RPS3_ESING with a message
 * "singular configuration: <measure> <value> above <option> <limit>"),
 * both the caller's options; not installed.
 */
#ifndef RPS3_POLICY_H
#define RPS3_POLICY_H

#include "rps3.h"

/* the first words of every refusal at the singular surface: the
   simulation adds the time after them (src/sim.c) */
#define RPS3_SING_PREFIX "singular configuration: "

/* the measures the policy knows */
enum rps3_sing_measure {
  RPS3_SING_LAMBDA, /* 1-norm condition number of the lambda system
                       (df/dtheta)^T (23): RPS3_WARN_ILLCOND past
                       cond_warn, RPS3_ESING past cond_max */
  RPS3_SING_JT,     /* condition number of df/dtheta, the rate stages'
                       solve (29)-(30): RPS3_ESING past cond_max */
  RPS3_SING_TRANS,  /* force transmission (rps3_data.transmission):
                       RPS3_WARN_TRANS past trans_warn, RPS3_ESING past
                       trans_max */
  RPS3_SING_MQ,     /* condition number of the generalized mass matrix
                       Mq: RPS3_ESING past cond_max */
  RPS3_SING_NMEASURE
};

/* the decision past the warning threshold (src/policy.c): the warning bit
   into d->warn and RPS3_OK, or RPS3_ESING with the message in d->err.  A
   singular matrix is measured HUGE_VAL; NaN and negative values are
   refused */
int rps3_sing_decide(const rps3_model *m, rps3_data *d, int measure,
                     double value);

/* Mq not positive definite (its Cholesky factor's pivot `pivot`, 1-based,
   is `ratio` times its diagonal entry): RPS3_ESING, with Mq's condition
   number cond */
int rps3_sing_mass_indefinite(rps3_data *d, int pivot, double ratio,
                              double cond);

/* the threshold below which a measure is silent */
static inline double rps3_sing_quiet(const rps3_model *m, int measure) {
  switch (measure) {
  case RPS3_SING_LAMBDA: return m->opt.cond_warn;
  case RPS3_SING_TRANS: return m->opt.trans_warn;
  default: return m->opt.cond_max;
  }
}

/*
 * The policy on one measure: RPS3_OK when value is at or below its quiet
 * threshold (inline: every point passes here), else rps3_sing_decide.
 */
static inline int rps3_sing_check(const rps3_model *m, rps3_data *d,
                                  int measure, double value) {
  if (value >= 0.0 && value <= rps3_sing_quiet(m, measure)) return RPS3_OK;
  return rps3_sing_decide(m, d, measure, value);
}

/*
 * The batch kernels' certificate: a point is theirs only when its
 * condition number and transmission lie below the lower of the warning
 * and hard thresholds by the relative margin `margin` (the kernels'
 * rounding differs from the scalar stages'), where the policy would be
 * silent; every other point goes to the scalar stages and the policy.
 */
static inline void rps3_sing_certify_limits(const rps3_model *m, double margin,
                                            double *cond_lim,
                                            double *trans_lim) {
  const double c = rps3_sing_quiet(m, RPS3_SING_LAMBDA);
  const double t = rps3_sing_quiet(m, RPS3_SING_TRANS);
  *cond_lim = (c < m->opt.cond_max ? c : m->opt.cond_max) * (1.0 - margin);
  *trans_lim = (t < m->opt.trans_max ? t : m->opt.trans_max) * (1.0 - margin);
}

#endif /* RPS3_POLICY_H */
