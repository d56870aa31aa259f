/*
 * scene_design.h - the keys of a design study (included by scene.h).
 *
 * The design variables are the fields of the library's rps3_design: R,
 * rho, M, the payload and g are the manipulator keys every scene has, m
 * (or m_over_M) and d those of the links' actuator body (with
 * link_density 0, the default, exactly the link mass and centroid of any
 * scene); the stroke, the joint ranges, the link radius and the rod's
 * density are the keys below, whose rows are the library's
 * (RPS3_DESIGN_FIELDS: range and unit read, not repeated).  The `design:`
 * section is the runner's own: the grid of poses over alpha, beta and z_c
 * and how the indices are evaluated (rps3_design_opts).  Each case of a
 * design study's sweep is one design (docs/runner.md, "Design studies").
 *
 * Header only: its rows are rows of scene.h's one key table, SCENE_KEYS.
 */
#ifndef RPS3_RUNNER_SCENE_DESIGN_H
#define RPS3_RUNNER_SCENE_DESIGN_H

#include <math.h>

#include "rps3.h"

/* the design section's values, as the scene gives them */
typedef struct {
  double grid_alpha[3]; /* pose grid: lo, hi, cells (rps3_design_grid) */
  double grid_beta[3];
  double grid_z_c[3];
  double good_lti;  /* rps3_design_opts.lti_good */
  double length;    /* rps3_design_opts.length [m]; 0: r */
  double cond_sing; /* rps3_design_opts.cond_sing */
  int per_pose;     /* write the per-pose indices */
} scene_design;

/*
 * The keys, rows of SCENE_KEYS (scene.h): X(ID, path, type, SRC, FIELD,
 * req, symbol, doc).  SRC DES: FIELD is an rps3_design_field_id (the
 * library's row of RPS3_DESIGN_FIELDS); SRC DSEC: FIELD is the row (MEMBER,
 * N, IS_INT, LO, LO_OPEN, HI, UNIT) of a member of scene_design, shaped like
 * the library's; the grid's own rules (lo <= hi, whole counts) are
 * design.c's, the defaults of the options rps3_design_opts_default's
 * (scene_values_default).  The manipulator's design keys stand with the
 * other manipulator keys (the resolved scene writes sections in the order
 * of the rows), the design section's at the end.  "required" means: in a design
 * study (a scene without a design section may not give them).
 */
#define SCENE_DESIGN_MANIP_KEYS(X)                                            \
  X(K_DES_STROKE_MIN, "manipulator.stroke.min", KEY_REAL, DES, RPS3_DF_L_MIN, \
    REQ_YES, "l_min",                                                         \
    "design: shortest link length l_i (the actuator retracted)")              \
  X(K_DES_STROKE_MAX, "manipulator.stroke.max", KEY_REAL, DES, RPS3_DF_L_MAX, \
    REQ_YES, "l_max",                                                         \
    "design: longest link length l_i (the actuator extended), above min")     \
  X(K_DES_PIN_MIN, "manipulator.pin.min", KEY_REAL, DES, RPS3_DF_THETA_MIN,   \
    REQ_NO, "theta_i",                                                        \
    "design: smallest pin joint angle theta_i, link to base plane (39)")      \
  X(K_DES_PIN_MAX, "manipulator.pin.max", KEY_REAL, DES, RPS3_DF_THETA_MAX,   \
    REQ_NO, "theta_i", "design: largest pin joint angle theta_i, above min")  \
  X(K_DES_BALL_MAX, "manipulator.ball.max", KEY_REAL, DES, RPS3_DF_BALL_MAX,  \
    REQ_NO, "-",                                                              \
    "design: ball joint cone half-angle, the largest angle between a link "   \
    "and the platform normal")                                                \
  X(K_DES_LINK_RADIUS, "manipulator.link_radius", KEY_REAL, DES,              \
    RPS3_DF_LINK_RADIUS, REQ_NO, "-",                                         \
    "design: radius of a link's capsule for interference between links; 0: "  \
    "not checked")                                                            \
  X(K_DES_LINK_DENSITY, "manipulator.link_density", KEY_REAL, DES,            \
    RPS3_DF_LINK_DENSITY, REQ_NO, "-",                                        \
    "design: mass per length of a link's rod (pin to l_max), added to the "   \
    "actuator body m at d; 0: the link is m at d")

#define SCENE_DESIGN_KEYS(X)                                                  \
  X(K_DES_ALPHA, "design.alpha", KEY_REAL3, DSEC,                             \
    (des.grid_alpha, 3, 0, -HUGE_VAL, 0, HUGE_VAL, "rad, rad, 1"), REQ_YES,   \
    "alpha",                                                                  \
    "pose grid: [lo, hi, cells] of the precession angle alpha; poses at the " \
    "cell centres")                                                           \
  X(K_DES_BETA, "design.beta", KEY_REAL3, DSEC,                               \
    (des.grid_beta, 3, 0, -HUGE_VAL, 0, HUGE_VAL, "rad, rad, 1"), REQ_YES,    \
    "beta", "pose grid: [lo, hi, cells] of the nutation angle beta")          \
  X(K_DES_Z_C, "design.z_c", KEY_REAL3, DSEC,                                 \
    (des.grid_z_c, 3, 0, -HUGE_VAL, 0, HUGE_VAL, "m, m, 1"), REQ_YES, "z_c",  \
    "pose grid: [lo, hi, cells] of the platform centre height z_c")           \
  X(K_DES_GOOD_LTI, "design.good_lti", KEY_REAL, DSEC,                        \
    (des.good_lti, 1, 0, 0, 0, 1, "1"), REQ_NO, "-",                          \
    "good transmission: a reachable pose whose local transmission index LTI " \
    "is at least this")                                                       \
  X(K_DES_LENGTH, "design.length", KEY_REAL, DSEC,                            \
    (des.length, 1, 0, 0, 0, HUGE_VAL, "m"), REQ_NO, "L",                     \
    "characteristic length of the homogeneous condition number; 0: the "      \
    "platform radius r")                                                      \
  X(K_DES_COND_SING, "design.cond_sing", KEY_REAL, DSEC,                      \
    (des.cond_sing, 1, 0, 1, 0, HUGE_VAL, "1"), REQ_NO, "-",                  \
    "a pose whose homogeneous condition number is above this is singular "    \
    "(not reachable)")                                                        \
  X(K_DES_PER_POSE, "design.per_pose", KEY_BOOL, DSEC,                        \
    (des.per_pose, 1, 1, 0, 0, 1, "-"), REQ_NO, "-",                          \
    "also write the indices of every pose ([case, z_c, beta, alpha] "         \
    "datasets)")

#endif /* RPS3_RUNNER_SCENE_DESIGN_H */
