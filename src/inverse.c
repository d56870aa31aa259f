/*
 * inverse.c - the whole per-point pipeline: pose -> positions -> rates ->
 * forces, computing only what the selected effects need.
 */
#include "internal.h"

int rps3_inverse(const rps3_model *m, rps3_data *d) {
  rps3_pose_trig trig; /* sines and cosines of the pose, for every stage */
  int status, need_rates, multiroot;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;

  /* positions: the closed form (39), or the multiroot solve of (8)-(10)
     from the link lengths, warm-started from this data's previous point */
  multiroot = (m->opt.theta == RPS3_THETA_MULTIROOT);
  status = rps3_ik_with(m, d, &trig, !multiroot);
  if (status != RPS3_OK) return status;
  if (multiroot) {
    /* ik left theta alone (no closed form leaks into the starting point):
       the solve starts from this data's previous solution */
    status = rps3_theta_solve(m, d);
    if (status != RPS3_OK) return status;
  }

  /* rates only when an effect (or the certificate) needs them */
  need_rates = (m->opt.effects & RPS3_EFF_DYNAMIC) || m->opt.certify;
  if (need_rates) {
    status = rps3_velocity_with(m, d, &trig);
    if (status != RPS3_OK) return status;
    status = rps3_acceleration_with(m, d, &trig);
    if (status != RPS3_OK) return status;
  }
  return rps3_invdyn(m, d);
}
