/*
 * inverse.c - the whole per-point pipeline: pose -> positions -> rates ->
 * forces, computing only what the selected effects need.
 */
#include "internal.h"

int rps3_inverse(const rps3_model *m, rps3_data *d) {
  double prev[3];
  int status, had, need_rates;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;

  /* positions: the closed form (39), or the multiroot solve of (8)-(10)
     from the link lengths, warm-started from this data's previous point */
  had = d->have_theta;
  v3_copy(prev, d->theta);
  status = rps3_ik(m, d);
  if (status != RPS3_OK) return status;
  if (m->opt.theta == RPS3_THETA_MULTIROOT) {
    /* the closed form must not leak into the solver's starting point */
    v3_copy(d->theta, prev);
    d->have_theta = had;
    status = rps3_theta_solve(m, d);
    if (status != RPS3_OK) return status;
  }

  /* rates only when an effect (or the certificate) needs them */
  need_rates = (m->opt.effects & RPS3_EFF_DYNAMIC) || m->opt.certify;
  if (need_rates) {
    status = rps3_velocity(m, d);
    if (status != RPS3_OK) return status;
    status = rps3_acceleration(m, d);
    if (status != RPS3_OK) return status;
  }
  return rps3_invdyn(m, d);
}
