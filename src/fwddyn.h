/*
 * fwddyn.h - rps3_fwddyn in two parts, for a caller that evaluates the same
 * state (l, dl) again with other forces: Mq, hq and the velocity maps
 * depend on the state only, F enters the right-hand side alone.  The
 * simulation evaluates the state at the end of a control period to report
 * it, and the next period's first Runge-Kutta stage is that state under
 * the controller's new force: one product with Mq^-1 instead of a second
 * evaluation.  The controllers use the state part alone: their model's
 * inverse dynamics is F = Mq ddl + hq (RPS3_FD_NOFACTOR).
 */
#ifndef RPS3_FWDDYN_H
#define RPS3_FWDDYN_H

#include "internal.h"

/* largest predicted change of a theta_i [rad] from the last root, for the
   plant's stages and the controllers' ticks: ~0.6 degree, many steps of
   any run that keeps its accuracy; a larger one (near a singular
   configuration, where G grows) starts from the last root itself */
#define RPS3_FD_PREDICT_MAX 1e-2

/* what rps3_fwddyn_accel needs of a state: theta' = G l', vc = Jc l',
   omega = Jw l' (columns j the motions for a unit l_j'), the accelerations
   at l'' = 0, and Mq^-1 */
typedef struct rps3_fd_state {
  double G[3][3];
  double Jc[3][3];
  double Jw[3][3];     /* set with dw_b only when have_w */
  int have_w;
  double ddth_b[3];   /* theta'' at l'' = 0 */
  double ac_b[3];     /* centre acceleration at l'' = 0 */
  double dw_b[3];     /* angular acceleration at l'' = 0 */
  double Minv[3][3];  /* Mq^-1, its adjugate over its determinant */
  double l[3];        /* the lengths of this state */
  double th[3];       /* its theta, and their cosines and sines */
  double c[3], s[3];
  int have_trig;      /* th, c, s are the last state's root */
  int nrot;           /* states since c, s were last from sincos */
  int mode;           /* assembly mode of the last successful state, 0
                         before one */
} rps3_fd_state;

/* flags of rps3_fwddyn_state */
enum {
  RPS3_FD_PREDICT = 1, /* *k holds the last state this d was evaluated at,
                          successfully (d->theta its root): the theta solve
                          starts from theta + G (l - k->l) */
  RPS3_FD_LEAN = 2,    /* an integrator's stage, which reads the
                          accelerations and theta' only: the positions
                          (ball joints, link directions, frame), the pose,
                          vc, omega, the pose rates and the angular
                          acceleration are left out (NaN; a payload keeps
                          the positions and the platform's motion) */
  RPS3_FD_NOFACTOR = 4, /* Mq and hq only, for a model's inverse dynamics
                          F = Mq ddl + hq (a controller): no inertia
                          needed, Mq not factored (Minv, Mcond unset) */
  RPS3_FD_TRIG = 8     /* *k holds the last root of this d (have_trig):
                          a lean state whose start is within a predicted
                          step of it takes its cosines and sines from it
                          by their series instead of sincos */
};

/* fwddyn_theta.c: theta from d->l by Newton's method from d->theta (its
   cosines and sines in c, sn when have_trig, else taken here), to a root
   rps3_theta_solve would accept; 0 with the root's cosines and sines in
   c, sn and the positions (when `positions`) and pose (when `pose`)
   written, -1 for the caller to fall back to rps3_fk.  And c, sn moved
   to theta - e by their series (|e| <= RPS3_FD_PREDICT_MAX), back onto
   the unit circle */
int rps3_fd_theta_newton(const rps3_model *m, rps3_data *d, double c[3],
                         double sn[3], int have_trig, int positions,
                         int pose);
void rps3_fd_trig_step(double c[3], double sn[3], const double e[3]);

/* The state part of rps3_fwddyn: reads d->l, d->dl (not d->F); writes the
   positions, the rates, Mq, hq, Mcond and mode, and *k.  On failure the
   status and message of rps3_fwddyn, d->ddl NaN. */
int rps3_fwddyn_state(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags);

/* The force part: ddl, ddtheta, ac, domega from d->F and the state k that
   rps3_fwddyn_state wrote into d (d's positions and rates unchanged since).
   RPS3_OK, RPS3_EINVAL (F not finite), RPS3_ESING (acceleration not
   finite) or RPS3_ERANGE, as rps3_fwddyn. */
int rps3_fwddyn_accel(const rps3_model *m, rps3_data *d,
                      const rps3_fd_state *k);

#endif /* RPS3_FWDDYN_H */
