/*
 * fwddyn_singular.c - whether a theta solve of the forward-dynamics state
 * that failed did so at the singular surface (the lengths moved past the
 * fold of (8)-(10)), so that the state reports RPS3_ESING and the measure
 * instead of the solver's status.  Called by src/fwddyn.c on its failure
 * path only.
 */
#include "fwddyn_plane.h"
#include "linalg.h"

/* det df/dtheta at lengths l and angles th, with p's constraint terms
   there (plane_constraints) */
static double det_at(const rps3_model *m, plane *p, const double l[3],
                     const double th[3], double f[3]) {
  int i;
  for (i = 0; i < 3; i++) {
    p->q.l[i] = l[i];
    p->q.c[i] = cos(th[i]);
    p->q.s[i] = sin(th[i]);
  }
  plane_constraints(m, p, f);
  return plane_det(p);
}

/*
 * Whether a theta solve that failed at the lengths d->l from the last
 * root th0 failed at the singular surface, by the quadratic model of the
 * constraints about th0 along the Newton step x = (df/dtheta)^-1 f:
 * along it f = f0 (1 - t) + q t^2 and det df/dtheta is linear, so that
 * near a fold (smallest singular value sigma of df/dtheta, curvature c)
 * the model has no root exactly when the step is more than half the
 * distance sigma / c to det = 0 (its discriminant sigma^2 - 2 c |f0|).
 * The test: det df/dtheta changes sign on [th0, th0 - 2 x] (sampled at
 * SING_SAMPLES points).  Then the lengths moved past the fold and no
 * root is left in the tracked assembly mode.  The model decides only
 * where it holds: df/dtheta at th0 and the new lengths on the last root's
 * side (its mode), and a step of at most SING_STEP_MAX; elsewhere (lengths
 * far from the last root's) and at a regular pose, where the doubled step
 * stays on its side, the solve's own status stands.  On the failure path
 * only: RPS3_ESING with the measure, or RPS3_OK.
 */
#define SING_SAMPLES 32
/* the largest Newton step [rad] for which the quadratic model decides:
   its neglected cubic terms, of relative order the step (the constraints'
   angles enter through cos and sin), stay a few per cent */
#define SING_STEP_MAX 0.05
int rps3_fd_solve_failed_singular(const rps3_model *m, rps3_data *d,
                                  const double th0[3], int mode) {
  plane p;
  double f[3], x[3], th[3], det0, det, cond;
  int i, j;
  if (!v3_finite(th0) || !v3_finite(d->l) || !(mode == 1 || mode == -1))
    return RPS3_OK;
  det0 = det_at(m, &p, d->l, th0, f);
  /* the model about th0 holds where the new lengths leave df/dtheta on
     the last root's side */
  if (!((det0 > 0.0) == (mode > 0) && fabs(det0) < HUGE_VAL)) return RPS3_OK;
  {
    plane_inverse(&p, det0);
    cond = plane_cond1(&p);
    m3_mulv(x, M3C(p.X), f);
    /* and along a step of at most SING_STEP_MAX: a larger one, lengths
       far from the last root's, is not the fold's business */
    if (!(max2(max2(fabs(x[0]), fabs(x[1])), fabs(x[2])) <= SING_STEP_MAX))
      return RPS3_OK;
    for (j = 1; j <= SING_SAMPLES; j++) {
      const double tau = 2.0 * (double)j / SING_SAMPLES;
      for (i = 0; i < 3; i++) th[i] = th0[i] - tau * x[i];
      det = det_at(m, &p, d->l, th, f);
      if ((det > 0.0) != (det0 > 0.0)) break;
    }
    if (j > SING_SAMPLES) return RPS3_OK;
  }
  RPS3_ERROR(d, RPS3_ESING,
             RPS3_SING_PREFIX
             "no theta near the last root, twice "
             "its Newton step crosses det df/dtheta = 0 (from %.3g to %.3g; "
             "condition number of df/dtheta %.3g at the root)",
             det0, det, cond);
}
