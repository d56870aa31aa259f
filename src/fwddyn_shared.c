/*
 * fwddyn_shared.c - the state part of a model at another model's kept
 * state (RPS3_FD_KEEP): a controller at its simulation's plant state takes
 * the plant's kinematics, and its Mq and hq when its dynamics are the
 * plant's, instead of solving the same state again (src/fwddyn.h).
 */
#include <string.h>

#include "fwddyn_plane.h"

/* a and b give the same Mq and hq from the same kinematics: the fields
   assemble reads (rps3_friction_torque's with them); test_fwddyn perturbs
   every field of the model to hold this list to assemble */
static int same_dynamics(const rps3_model *a, const rps3_model *b) {
  return a->opt.effects == b->opt.effects && a->M == b->M && a->m == b->m &&
         a->d == b->d && a->g == b->g && a->Jlink == b->Jlink &&
         a->bodies == b->bodies &&
         memcmp(a->pinf, b->pinf, sizeof a->pinf) == 0 &&
         memcmp(a->std, b->std, sizeof a->std) == 0 &&
         memcmp(a->leg, b->leg, sizeof a->leg) == 0;
}

/* the state part of rps3_fwddyn_state_shared, once it applies */
static int state_shared(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                        const rps3_model *src_model, const rps3_fd_state *src) {
  const plane *p = &src->kin;
  double cond;
  int st;
  /* what rps3_fwddyn_state writes of a lean state, from src's */
  d->stage = 0;
  d->warn = 0;
  d->mode = src->mode;
  d->have_theta = 1;
  v3_copy(d->theta, src->th);
  v3_copy(d->dtheta, p->dth);
  rps3_fd_positions_unset(d);
  d->pose[0] = d->pose[1] = d->pose[2] = (double)NAN;
  d->vc[0] = d->vc[1] = d->vc[2] = (double)NAN;
  d->omega[0] = d->omega[1] = d->omega[2] = (double)NAN;
  d->dpose[0] = d->dpose[1] = d->dpose[2] = (double)NAN;
  /* what the next own state's predicted start reads (a controller's
     state part has no accelerations to form: no Jc, Jw, ac_b) */
  memcpy(k->G, p->G, sizeof(p->G));
  v3_copy(k->ddth_b, p->ddb);
  v3_copy(k->l, p->q.l);
  v3_copy(k->dl, p->dl);
  k->idl2 = src->idl2;
  v3_copy(k->th, src->th);
  v3_copy(k->c, p->q.c);
  v3_copy(k->s, p->q.s);
  k->have_trig = 1;
  k->nrot = src->nrot;
  k->have_w = 0;
  k->scratch = 0;
  /* m's checks: df/dtheta's condition (plane_jacobian's), the lambda
     system's and the transmission (invdyn_limits), the mode */
  cond = plane_cond1(p);
  st = rps3_sing_check(m, d, RPS3_SING_JT, cond);
  if (st != RPS3_OK) return st;
  st = invdyn_limits(m, d, p, src);
  if (st != RPS3_OK) return st;
  st = mode_refused(m, d, k);
  if (st != RPS3_OK) return st;
  /* the plant's Mq and hq when they are this model's too (a controller
     with the exact model), else this model's own from the kinematics */
  if (same_dynamics(m, src_model)) {
    memcpy(d->Mq, src->Mq, sizeof(d->Mq));
    v3_copy(d->hq, src->hq);
  } else {
    assemble(m, d, k, p);
  }
  RPS3_CHECK_FINITE(d, d->hq, 3, "hq");
  RPS3_CHECK_FINITE(d, d->Mq, 9, "Mq");
  return RPS3_OK;
}

int rps3_fwddyn_state_shared(const rps3_model *m, rps3_data *d,
                             rps3_fd_state *k, const rps3_model *src_model,
                             const rps3_fd_state *src, int *status) {
  int i;
  if (src == NULL || src_model == NULL || !src->have_kin ||
      m->R != src_model->R || m->r != src_model->r ||
      !(src_model->opt.tol <= m->opt.tol) || !m->opt.warm_start ||
      (m->opt.effects & RPS3_EFF_PAYLOAD))
    return 0;
  for (i = 0; i < 3; i++)
    if (!(d->l[i] == src->kin.q.l[i] && d->dl[i] == src->kin.dl[i])) return 0;
  *status = state_shared(m, d, k, src_model, src);
  poison(d); /* no acceleration: Mq and hq are the answer */
  if (*status == RPS3_OK) k->mode = d->mode;
  return 1;
}
