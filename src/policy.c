/*
 * policy.c - the singularity policy's decisions past the warning
 * thresholds (src/policy.h), and its one set of messages.
 */
#include "internal.h"

/* each measure: its name in a message, the matrix it conditions (NULL:
   not a condition number), its options and warning bit, and what a value
   past the hard limit means (may be "") */
static const struct {
  const char *what, *matrix, *warn_name, *max_name, *why;
  int warn_bit;
} measures[RPS3_SING_NMEASURE] = {
    {"condition number of the lambda system (df/dtheta)^T",
     "the lambda system (df/dtheta)^T", "cond_warn", "cond_max", "",
     RPS3_WARN_ILLCOND},
    {"condition number of df/dtheta", "df/dtheta", NULL, "cond_max", "", 0},
    {"force transmission", NULL, "trans_warn", "trans_max",
     ": an actuator would carry that many times the load on the platform",
     RPS3_WARN_TRANS},
    {"condition number of Mq", "Mq", NULL, "cond_max", "", 0},
};

static double sing_max(const rps3_model *m, int measure) {
  return measure == RPS3_SING_TRANS ? m->opt.trans_max : m->opt.cond_max;
}

int rps3_sing_decide(const rps3_model *m, rps3_data *d, int measure,
                     double value) {
  const double max = sing_max(m, measure);
  if (value >= 0.0 && value <= max) {
    if (measures[measure].warn_name != NULL &&
        value > rps3_sing_quiet(m, measure))
      d->warn |= measures[measure].warn_bit;
    return RPS3_OK;
  }
  if (measures[measure].matrix != NULL && value == HUGE_VAL)
    RPS3_ERROR(d, RPS3_ESING,
               RPS3_SING_PREFIX
               "%s is singular (condition number inf) at "
               "theta = "
               "(%.6g, %.6g, %.6g)",
               measures[measure].matrix, d->theta[0], d->theta[1], d->theta[2]);
  RPS3_ERROR(d, RPS3_ESING, RPS3_SING_PREFIX "%s %.3g above %s %.3g%s",
             measures[measure].what, value, measures[measure].max_name, max,
             measures[measure].why);
}

int rps3_sing_mass_indefinite(rps3_data *d, int pivot, double ratio,
                              double cond) {
  RPS3_ERROR(d, RPS3_ESING,
             RPS3_SING_PREFIX
             "Mq not positive definite: pivot %d of its "
             "Cholesky factor %.3g times its diagonal entry (condition "
             "number %.3g)",
             pivot, ratio, cond);
}
