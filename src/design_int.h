/*
 * design_int.h - what the design's evaluation over a set of poses
 * (design_eval.c) and along a task (design_task.c) share: the workspace's
 * scratch, one pose's results and its evaluation.  Internal.
 */
#ifndef RPS3_DESIGN_INT_H
#define RPS3_DESIGN_INT_H

#include "rps3.h"

/* samples of a task per rps3_inverse_batch call (the workspace's arrays) */
#define TASK_BLOCK 64

struct rps3_design_scratch {
  rps3_model stat; /* the design's model for the indices: static (platform
                      weight only), no certificate, limits that never stop
                      a point (the design's own flags decide) */
  rps3_model dyn;  /* the design's model for a task's forces */
  double pose[3 * TASK_BLOCK], dpose[3 * TASK_BLOCK], ddpose[3 * TASK_BLOCK];
  double F[3 * TASK_BLOCK], dl[3 * TASK_BLOCK];
  int status[TASK_BLOCK];
};

/* one pose's results */
typedef struct {
  int flags;
  int status; /* rps3_inverse's */
  double l[3], theta[3], ball[3], c[3];
  double clearance, lti, oti, cti, cond_h, trans, spin;
} pose_res;

static inline double fmax_(double a, double b) { return a > b ? a : b; }
static inline double fmin_(double a, double b) { return a < b ? a : b; }

/* set the workspace up for design ds: its models; RPS3_EINVAL with the
   design's message */
int rps3_design_ws_set(rps3_design_ws *w, const rps3_design *ds,
                       const rps3_design_opts *o);

/* evaluate one pose of the design set up in w (rps3_design_ws_set) */
void rps3_design_eval_pose(rps3_design_ws *w, const rps3_design *ds, double L,
                           double cond_sing, const double pose[3], pose_res *r);

#endif /* RPS3_DESIGN_INT_H */
