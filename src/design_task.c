/*
 * design_task.c - what a task asks of a design's actuators: its samples'
 * forces by the library's batch inverse dynamics, each sample checked
 * against the design's workspace first (rps3_design_task_eval; the
 * definitions in docs/design.md).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "design_int.h"
#include "internal.h"

/* the flags of bits f as names, "stroke, ball" */
static void flag_list(int f, char *buf, size_t sz) {
  size_t len = 0;
  int k;
  buf[0] = '\0';
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
    if ((f & (1 << k)) && len < sz)
      len += (size_t)snprintf(buf + len, sz - len, "%s%s", len ? ", " : "",
                              rps3_design_flag_name(k));
}

/* time of sample k of n over [0, T]: k T / (n - 1), the last exactly T */
static double sample_time(double T, size_t k, size_t n) {
  return k + 1 == n ? T : T * (double)k / (double)(n - 1);
}

/* the task's model into the scratch (the design's, links' mass left out
   when asked), checked with the trajectory */
static int task_model(rps3_design_ws *w, const rps3_traj *tr, size_t nsamples,
                      int link_mass_on) {
  rps3_model *dm = &w->scr->dyn;
  rps3_check chk;
  if (tr == NULL) RPS3_ERROR(w, RPS3_EINVAL, "trajectory is NULL");
  if (nsamples < 2)
    RPS3_ERROR(w, RPS3_EINVAL, "nsamples = %zu: must be >= 2", nsamples);
  if (link_mass_on != RPS3_DESIGN_NO_LINK_MASS &&
      link_mass_on != RPS3_DESIGN_LINK_MASS)
    RPS3_ERROR(w, RPS3_EINVAL, "link_mass = %d: must be 0 or 1", link_mass_on);
  *dm = w->model;
  if (!link_mass_on)
    dm->opt.effects &= ~(RPS3_EFF_LINK_GRAVITY | RPS3_EFF_LINK_INERTIA);
  dm->opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
  if (rps3_model_init(dm, &chk) != RPS3_OK)
    RPS3_ERROR(w, RPS3_EINVAL, "task model: %.200s", chk.msg);
  if (rps3_traj_check(dm, tr, &chk) != RPS3_OK)
    RPS3_ERROR(w, RPS3_EINVAL, "%.250s", chk.msg);
  return RPS3_OK;
}

/* samples k0 .. k0 + nb - 1 of the task and their forces by the library's
   batch inverse dynamics, into the scratch */
static int task_block(rps3_design_ws *w, const rps3_traj *tr, double T,
                      size_t nsamples, size_t k0, size_t nb) {
  struct rps3_design_scratch *s = w->scr;
  rps3_batch_in in;
  rps3_batch_out bo;
  size_t i;
  int j, st;
  for (i = 0; i < nb; i++) {
    double t = sample_time(T, k0 + i, nsamples);
    double q[3], dq[3], ddq[3];
    st = rps3_traj_eval(&s->dyn, tr, t, q, dq, ddq);
    if (st != RPS3_OK)
      RPS3_ERROR(w, st,
                 "t = %.9g s: the trajectory does not evaluate "
                 "(%s)",
                 t, rps3_strerror(st));
    for (j = 0; j < 3; j++) {
      s->pose[j * nb + i] = q[j];
      s->dpose[j * nb + i] = dq[j];
      s->ddpose[j * nb + i] = ddq[j];
    }
  }
  memset(&in, 0, sizeof(in));
  memset(&bo, 0, sizeof(bo));
  in.n = nb;
  in.pose = s->pose;
  in.dpose = s->dpose;
  in.ddpose = s->ddpose;
  bo.status = s->status;
  bo.F = s->F;
  bo.dl = s->dl;
  st = rps3_inverse_batch(&s->dyn, w->d, &in, &bo);
  if (st != RPS3_OK)
    RPS3_ERROR(w, st, "task: rps3_inverse_batch: %.200s", w->d->err.msg);
  return RPS3_OK;
}

/* sample k (index i of its block of nb): where it leaves the workspace or
   its inverse dynamics fail, the result up to it and RPS3_EREACH; else
   its requirements added to res (sumsq: the squared forces) */
static int task_sample(rps3_design_ws *w, const rps3_design *ds,
                       const rps3_design_opts *o, double L, double t, size_t k,
                       size_t i, size_t nb, double sumsq[3],
                       rps3_design_task *res) {
  struct rps3_design_scratch *s = w->scr;
  double q[3];
  pose_res r;
  int j;
  q[0] = s->pose[i];
  q[1] = s->pose[nb + i];
  q[2] = s->pose[2 * nb + i];
  rps3_design_eval_pose(w, ds, L, o->cond_sing, q, &r);
  if (r.flags != 0 || s->status[i] != RPS3_OK) {
    char fl[96];
    res->fail_index = k;
    res->fail_time = t;
    res->fail_flags = r.flags;
    res->fail_status = s->status[i];
    for (j = 0; j < 3 && res->nsamples > 0; j++)
      res->F_rms[j] = sqrt(sumsq[j] / (double)res->nsamples);
    if (res->nsamples == 0) {
      res->lti_min = 0.0;
      for (j = 0; j < 3; j++) res->l_lo[j] = 0.0;
    }
    flag_list(r.flags, fl, sizeof fl);
    if (r.flags != 0)
      RPS3_ERROR(w, RPS3_EREACH,
                 "t = %.9g s (sample %zu): the task leaves the "
                 "workspace: %s (l = %.6g, %.6g, %.6g m)",
                 t, k, fl, r.l[0], r.l[1], r.l[2]);
    RPS3_ERROR(w, RPS3_EREACH,
               "t = %.9g s (sample %zu): the inverse dynamics fail: %s", t, k,
               rps3_strerror(s->status[i]));
  }
  for (j = 0; j < 3; j++) {
    double F = s->F[j * nb + i], v = s->dl[j * nb + i];
    res->F_peak[j] = fmax_(res->F_peak[j], fabs(F));
    res->P_peak[j] = fmax_(res->P_peak[j], fabs(F * v));
    res->v_peak[j] = fmax_(res->v_peak[j], fabs(v));
    res->l_lo[j] = fmin_(res->l_lo[j], r.l[j]);
    res->l_hi[j] = fmax_(res->l_hi[j], r.l[j]);
    sumsq[j] += F * F;
  }
  res->lti_min = fmin_(res->lti_min, r.lti);
  res->nsamples++;
  return RPS3_OK;
}

int rps3_design_task_eval(rps3_design_ws *w, const rps3_design *ds,
                          const rps3_design_opts *o, const rps3_traj *tr,
                          size_t nsamples, int link_mass_on,
                          rps3_design_task *res) {
  rps3_design_opts def;
  double T, L, sumsq[3] = {0, 0, 0};
  size_t k0;
  int st, j;
  if (w == NULL) return RPS3_EINVAL;
  if (res == NULL) RPS3_ERROR(w, RPS3_EINVAL, "task result is NULL");
  memset(res, 0, sizeof(*res));
  res->fail_index = nsamples;
  res->fail_time = (double)NAN;
  if (o == NULL) {
    rps3_design_opts_default(&def);
    o = &def;
  }
  st = rps3_design_ws_set(w, ds, o);
  if (st == RPS3_OK) st = task_model(w, tr, nsamples, link_mass_on);
  if (st != RPS3_OK) return st;
  T = rps3_traj_duration(tr);
  L = o->length > 0.0 ? o->length : w->scr->stat.r;
  for (j = 0; j < 3; j++) {
    res->l_lo[j] = HUGE_VAL;
    res->l_hi[j] = 0.0;
  }
  res->lti_min = HUGE_VAL;
  for (k0 = 0; k0 < nsamples; k0 += TASK_BLOCK) {
    size_t nb = nsamples - k0 < TASK_BLOCK ? nsamples - k0 : TASK_BLOCK, i;
    st = task_block(w, tr, T, nsamples, k0, nb);
    if (st != RPS3_OK) return st;
    /* each sample in order: the workspace, then its forces */
    for (i = 0; i < nb; i++) {
      st = task_sample(w, ds, o, L, sample_time(T, k0 + i, nsamples), k0 + i, i,
                       nb, sumsq, res);
      if (st != RPS3_OK) return st;
    }
  }
  for (j = 0; j < 3; j++)
    res->F_rms[j] = sqrt(sumsq[j] / (double)res->nsamples);
  return RPS3_OK;
}
