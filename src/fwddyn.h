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
#include "theta.h"

/* largest predicted change of a theta_i [rad] from the last root, for the
   plant's stages and the controllers' ticks: the theta solve's
   (src/theta.h) */
#define RPS3_FD_PREDICT_MAX RPS3_THETA_PREDICT_MAX

/*
 * A state in the links' planes.  Link i moves in the vertical plane of pin
 * i, its ball joint at b_i = h_i u_i + Z_i e_z, h_i = R - l_i cos_i, Z_i =
 * l_i sin_i ((12)-(14)).  The pair k = (i, j), j = i + 1 (mod 3), of
 * (8)-(10) is f_k = |b_i - b_j|^2 - 3 r^2 = h_i^2 + h_j^2 + h_i h_j + (Z_i
 * - Z_j)^2 - 3 r^2 (u_i . u_j = -1/2), so with A = 2 h_i + h_j, B = 2 h_j +
 * h_i, E = 2 (Z_i - Z_j) its derivatives are
 *   df_k/dtheta_i = l_i (A sin_i + E cos_i),  df_k/dtheta_j = l_j (B sin_j
 *   - E cos_j), df_k/dl_i = E sin_i - A cos_i,  df_k/dl_j = -B cos_j - E
 *   sin_j,
 * rps3_constraint_jacobian's entries, two a row: df/dtheta is cyclic
 * bidiagonal, det = a0 a1 a2 + b0 b1 b2, and its inverse is its adjugate
 * over det, nine products.  Everything is formed in this local structure
 * and stored into d and k once: stores through them could alias the
 * inputs as far as the compiler knows.  Its steps are in fwddyn_plane.h.
 */
typedef struct {
  rps3_closure q;        /* lengths, theta, its cos and sin, and
                            A, B, E, at, bt of pair k, in metres */
  double dl[3];          /* rates */
  double al[3], bl[3];   /* df_k/dl_k, df_k/dl_(k+1) */
  double X[3][3];        /* (df/dtheta)^-1 */
  double G[3][3];        /* dtheta'/dl' = -X df/dl */
  double Jc[3][3];       /* dvc/dl' */
  double dth[3], ddb[3]; /* theta', theta'' at l'' = 0 */
  double hd[3], Zd[3];   /* h_i', Z_i' */
  double hdd[3], Zdd[3]; /* h_i'', Z_i'' at l'' = 0 */
  double acb[3];         /* centre acceleration at l'' = 0 */
} plane;

/* what rps3_fwddyn_accel needs of a state: theta' = G l', vc = Jc l',
   omega = Jw l' (columns j the motions for a unit l_j'), the accelerations
   at l'' = 0, and Mq^-1 */
typedef struct rps3_fd_state {
  double G[3][3];
  double Jc[3][3];
  double Jw[3][3]; /* set with dw_b only when have_w */
  int have_w;
  double ddth_b[3];   /* theta'' at l'' = 0 */
  double ac_b[3];     /* centre acceleration at l'' = 0 */
  double dw_b[3];     /* angular acceleration at l'' = 0 */
  double Minv[3][3];  /* Mq^-1, its adjugate over its determinant */
  double l[3], dl[3]; /* the lengths and rates of this state */
  double idl2;        /* 1 / |dl|^2 (0 at rest) */
  double th[3];       /* its theta, and their cosines and sines */
  double c[3], s[3];
  int have_trig; /* th, c, s are the last state's root */
  int nrot;      /* states since c, s were last from sincos */
  int mode;      /* assembly mode of the last successful state, 0
                    before one */
  /* RPS3_FD_KEEP: that state's kinematics (Jw formed too), for a model
     with the same geometry at the same (l, dl): rps3_fwddyn_state_shared */
  plane kin;
  double Mq[3][3], hq[3]; /* and its Mq, hq */
  int have_kin;
  int scratch; /* RPS3_FD_SCRATCH: rps3_fwddyn_accel forms ddl alone */
} rps3_fd_state;

/* flags of rps3_fwddyn_state */
enum {
  RPS3_FD_PREDICT = 1,  /* *k holds the last state this d was evaluated at,
                           successfully (d->theta its root): the theta solve
                           starts from the root predictor's start
                           (rps3_theta_predict) */
  RPS3_FD_LEAN = 2,     /* an integrator's stage, which reads the
                           accelerations and theta' only: the positions
                           (ball joints, link directions, frame), the pose,
                           vc, omega, the pose rates and the angular
                           acceleration are left out (NaN; a payload keeps
                           the positions and the platform's motion) */
  RPS3_FD_NOFACTOR = 4, /* Mq and hq only, for a model's inverse dynamics
                          F = Mq ddl + hq (a controller): no inertia
                          needed, Mq not factored (Minv, Mcond unset) */
  RPS3_FD_TRIG = 8,     /* *k holds the last root of this d (have_trig):
                           a state whose start is within a predicted step
                           of it takes its cosines and sines from it by
                           their series instead of sincos */
  RPS3_FD_KEEP = 16,    /* keep the state's kinematics in k->kin, with Jw
                           (a simulation's state at a controller's tick) */
  RPS3_FD_SCRATCH = 32  /* with RPS3_FD_LEAN: d is the caller's scratch,
                           which it reads nothing of but the accelerations:
                           what a lean state leaves out is left as it was
                           instead of NaN (its stage bits 0 say so), and
                           rps3_fwddyn_accel forms ddl alone */
};

/* a lean state's positions: none (NaN), so that no earlier state's can be
   read as this one's */
void rps3_fd_positions_unset(rps3_data *d);

/* The state part of rps3_fwddyn: reads d->l, d->dl (not d->F); writes the
   positions, the rates, Mq, hq, Mcond and mode, and *k.  On failure the
   status and message of rps3_fwddyn, d->ddl NaN. */
int rps3_fwddyn_state(const rps3_model *m, rps3_data *d, rps3_fd_state *k,
                      int flags);

/* The state part of another model at the state src kept (RPS3_FD_KEEP,
   src_model's): when m has src_model's geometry (R, r), no payload, a
   theta tolerance no tighter than src_model's, warm starts (its own solve
   tracks the root src tracked), and d->l, d->dl are src's
   bit for bit, the kinematics are src's and only Mq, hq (m's masses and
   effects; src's own when m's dynamics are src_model's) and m's checks
   are formed, as rps3_fwddyn_state(m, d, k, RPS3_FD_LEAN |
   RPS3_FD_NOFACTOR) would: returns 1 with *status.  Otherwise returns 0
   and touches nothing. */
int rps3_fwddyn_state_shared(const rps3_model *m, rps3_data *d,
                             rps3_fd_state *k, const rps3_model *src_model,
                             const rps3_fd_state *src, int *status);

/* Whether a theta solve that failed at the lengths d->l, from the last
   root th0 in assembly mode `mode`, failed at the singular surface
   (src/fwddyn_singular.c): RPS3_ESING with the measure in d->err, or
   RPS3_OK when the solve's own status stands.  Failure path only. */
int rps3_fd_solve_failed_singular(const rps3_model *m, rps3_data *d,
                                  const double th0[3], int mode);

/* The force part: ddl, ddtheta, ac, domega from d->F and the state k that
   rps3_fwddyn_state wrote into d (d's positions and rates unchanged since).
   RPS3_OK, RPS3_EINVAL (F not finite), RPS3_ESING (acceleration not
   finite) or RPS3_ERANGE, as rps3_fwddyn. */
int rps3_fwddyn_accel(const rps3_model *m, rps3_data *d,
                      const rps3_fd_state *k);

#endif /* RPS3_FWDDYN_H */
