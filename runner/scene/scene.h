/*
 * scene.h - a scene file (YAML) and its sweep, for rps3-run and the study
 * program.  The scene is parsed with libyaml's document API; every key it
 * may hold is one row of SCENE_KEYS below, which drives parsing, the
 * per-case YAML of scene_resolved and the key list of `rps3-run --keys`.
 *
 * A scene with a sweep is a Cartesian product of cases.  Cases are numbered
 * in row-major order over the sweep keys in the order they appear in the
 * file: the last key varies fastest.  A case is never stored; it is rebuilt
 * from its number by scene_case(), so memory does not grow with the sweep.
 */
#ifndef RPS3_RUNNER_SCENE_H
#define RPS3_RUNNER_SCENE_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "rps3.h"
#include "scene_body_rows.h"
#include "scene_ident_rows.h"
#include "table.h"

/* a position in the scene file, both 1-based; 0:0 when not known */
typedef struct {
  int line;
  int column;
} scene_mark;

/* one error, printed as FILE:LINE:COLUMN: path: what */
typedef struct {
  scene_mark mark;
  char path[128]; /* dotted key path, "yaml" for a syntax error */
  char what[512]; /* what is wrong, with the offending value */
} scene_error;

/* value types of scene keys */
typedef enum {
  KEY_REAL,    /* finite double */
  KEY_INT,     /* integer */
  KEY_BOOL,    /* true | false */
  KEY_ENUM,    /* one of a list of names, stored as the library's enum */
  KEY_REAL3,   /* list of three finite doubles; a sweep picks one: key[k] */
  KEY_REAL6,   /* list of six (an inertia tensor), as KEY_REAL3 */
  KEY_EFFECTS, /* list of effect names, stored as RPS3_EFF_* bits */
  KEY_OUTPUTS, /* list of output names, stored as RPS3_OUT_* bits */
  KEY_TIMES,   /* list of at least 2 numbers (waypoint times) */
  KEY_POSES,   /* list of lists of 3 numbers (waypoint poses) */
  KEY_FILE,    /* a file name, relative to the scene (a table) */
  KEY_PARAMS   /* list of paper parameter names, stored as bits 1 << k of
                  rps3_paper_name(k) */
} key_type;

/* the trajectory kind of a key that belongs to every kind (scene_key_kind:
   else the rps3_traj_kind of its field) */
enum { FOR_ALL = 0 };

/* how a key must be given: required, optional (a default), or exactly one
   of a pair (REQ_ONE_*) */
enum {
  REQ_NO = 0,
  REQ_YES = 1,
  REQ_ONE_MASS = 2,  /* m_over_M | m */
  REQ_ONE_GRID = 3,  /* samples | dt */
  REQ_ONE_BLEND = 4, /* blend | blend_ratio */
  REQ_SHAPE = 5,     /* required by some path shapes (scene_shape_mask) */
  REQ_PAPER = 6,     /* required with manipulator.bodies: paper */
  REQ_GENERAL = 7    /* required with manipulator.bodies: general */
};

/* the values only the runner has; a case turns them into library fields */
typedef struct {
  double m_over_M;    /* link mass over M: model.m = m_over_M * M */
  double blend_ratio; /* t_a / T*: traj.helix.blend = blend_ratio * period */
  int samples;        /* number of time samples, ends included */
  double dt;          /* time step [s] */
  rps3_leg legs;      /* manipulator.legs: the values of every leg */
} scene_own;

/* the simulate section (each field is the value of the simulate.* key of
   its name, SCENE_KEYS); the plant is the scene's manipulator.  SIM_UNSET
   (an int -1) means "not given": the gains are the controller kind's, the
   duration the trajectory's span, the controller's model the plant's.  The
   parser takes finite numbers only, so the sentinel never collides. */
typedef struct {
  int controller; /* rps3_ctrl_kind */
  double kp, kd, rate;
  int integrator; /* rps3_integrator */
  double h, tolerance;
  int max_steps;
  double duration, start_offset[3], fmax, l_min, l_max;
  double noise_l, noise_dl, quant_l, quant_dl;
  int seed;
  double model_M, model_m_over_M, model_payload_mass, model_viscous,
      model_coulomb;
  int model_effects; /* RPS3_EFF_* bits */
} scene_sim;

/* default gains by controller kind (rps3-simstudy's, docs/simulation.md):
   PD [N/m, N s/m], computed torque [1/s^2, 1/s]; open loop has none */
#define SIM_KP_PD 2000.0
#define SIM_KD_PD 40.0
#define SIM_KP_CT 400.0
#define SIM_KD_CT 40.0

/* the default of a value not given (NAN is a float) */
#define SIM_UNSET ((double)NAN)

/* the design section of a design study (docs/runner.md, "Design studies",
   DSEC rows); the design variables are rps3_design's (DES rows) */
typedef struct {
  double grid[3][3]; /* alpha, beta, z_c: lo, hi, cells */
  rps3_design_opts opts;
  int per_pose;
} scene_design;

/* the identify section (docs/identification.md, "Through the runner"):
   the paper model's parameters fitted to the scene's data, and the Monte
   Carlo of force noise on them */
typedef struct {
  int params;         /* bits 1 << k of rps3_paper_name(k); -1: by effects */
  int model;          /* RPS3_BODIES_PAPER or _GENERAL; -1: the scene's
                         manipulator.bodies */
  int legs;           /* IDENT_LEGS_EACH or IDENT_LEGS_IDENTICAL */
  int method;         /* IDENT_OLS or IDENT_WLS */
  int consistent;     /* 1: also the physically consistent fit */
  int max_iter;       /* its iteration limit */
  double level;       /* confidence of the intervals */
  int runs;           /* Monte Carlo draws; 0: none */
  double force_noise; /* noise standard deviation / actuator RMS force */
  int seed;           /* of the draws' noise */
  double holdout;     /* fraction of the samples the draws hold out */
} scene_ident;

/* identify.method */
enum { IDENT_OLS = 0, IDENT_WLS = 1 };

/* identify.legs (model general) */
enum { IDENT_LEGS_EACH = 0, IDENT_LEGS_IDENTICAL = 1 };

/* every value a scene can set: the library's structures, filled through
   the offsets of RPS3_FIELDS, and the runner's own */
typedef struct {
  rps3_model model;
  rps3_traj traj;
  scene_own own;
  const char *file[3]; /* the tables' files, absolute (SCENE_TABLE_OF) */
  scene_sim sim;
  rps3_design design; /* a design study's design */
  scene_design des;
  scene_ident ids; /* an identification's */
} scene_values;

/* ranges of the runner's own values (LO, LO_OPEN, HI) */
#define GE0 0, 0, HUGE_VAL
#define GT0 0, 1, HUGE_VAL
#define ANY -HUGE_VAL, 0, HUGE_VAL

/*
 * SCENE_KEYS X(ID, path, type, SRC, FIELD, req, symbol, doc): each key of a
 * scene file, one row, which drives parsing, checks, units, did-you-mean,
 * the resolved YAML and `rps3-run --keys`.  SRC says where the value lives:
 *  - LIB: FIELD is the library field it fills (rps3_field_id), whose row of
 *    RPS3_FIELDS gives the place, the range (the library's own validation,
 *    read, not repeated), the unit and the trajectory kind;
 *  - DES: a field of a design study's rps3_design, FIELD its id
 *    (rps3_design_field_id), whose row of RPS3_DESIGN_FIELDS gives the
 *    range and the unit; "required" means in a design study;
 *  - LEGS: a value of all three legs (scene_body_rows.h), FIELD leg 1's
 *    library field (RPS3_F_LEG1_*), whose row gives the range and unit;
 *  - OWN, SIM, DSEC, IDS: a value only the runner has, FIELD the row shaped
 * like the library's: MEMBER of scene_values, the range (LO, LO_OPEN, HI) and
 *    the UNIT; an OWN value (scene_own) also has the trajectory kind IN and
 *    FILLS, the library field it is turned into (-1: none); a SIM value
 *    (scene_sim) its DEFAULT and DEFTEXT, the key list's text when DEFAULT
 *    is SIM_UNSET (NULL: the value), and so an IDS value (scene_ident, the
 *    identify section); a DSEC value (scene_design) takes the
 *    defaults of rps3_design_opts_default.
 * The rules that involve several fields are the library's, run when a case
 * is built; a failure comes back as a field id and is mapped to the key (or
 * the swept value) that set it.  Defaults are those of rps3_model_default()
 * and rps3_traj_default().  The resolved scene writes sections in the order
 * of the rows, so the keys of a section stay together.
 */
#define SCENE_KEYS(X)                                                          \
  X(K_R, "manipulator.R", KEY_REAL, LIB, RPS3_F_R, REQ_YES, "R",               \
    "base radius, centre to the pin joints")                                   \
  X(K_RHO, "manipulator.rho", KEY_REAL, LIB, RPS3_F_RHO, REQ_YES, "rho = r/R", \
    "platform radius r (centre to the ball joints) over R")                    \
  X(K_M, "manipulator.M", KEY_REAL, LIB, RPS3_F_PLATFORM_MASS, REQ_PAPER, "M", \
    "platform mass, a uniform disc of radius r")                               \
  X(K_M_OVER_M, "manipulator.m_over_M", KEY_REAL, OWN,                         \
    (own.m_over_M, RPS3_IN_MODEL, GE0, "1", RPS3_F_LINK_MASS), REQ_ONE_MASS,   \
    "m/M", "mass of each link over M; give this or manipulator.m")             \
  X(K_MASS, "manipulator.m", KEY_REAL, LIB, RPS3_F_LINK_MASS, REQ_ONE_MASS,    \
    "m", "mass of each link; give this or m_over_M")                           \
  X(K_D, "manipulator.d", KEY_REAL, LIB, RPS3_F_D, REQ_PAPER, "d_i",           \
    "pin joint to link centroid, constant")                                    \
  X(K_G, "manipulator.g", KEY_REAL, LIB, RPS3_F_G, REQ_NO, "g",                \
    "gravitational acceleration, along -Z")                                    \
  X(K_LINK_IC, "manipulator.link_Ic", KEY_REAL, LIB, RPS3_F_LINK_IC, REQ_NO,   \
    "-",                                                                       \
    "link inertia about its centroid, about the pin axis (0 in the paper)")    \
  X(K_PAY_MASS, "manipulator.payload.mass", KEY_REAL, LIB,                     \
    RPS3_F_PAYLOAD_MASS, REQ_NO, "-",                                          \
    "payload fixed to the platform (effect payload)")                          \
  X(K_PAY_COM, "manipulator.payload.com", KEY_REAL3, LIB, RPS3_F_PAYLOAD_COM,  \
    REQ_NO, "-", "payload centre of mass [x, y, z] in platform axes")          \
  X(K_PAY_INERTIA, "manipulator.payload.inertia", KEY_REAL3, LIB,              \
    RPS3_F_PAYLOAD_INERTIA, REQ_NO, "-",                                       \
    "payload principal moments [Ixx, Iyy, Izz] about its centre of mass")      \
  X(K_VISCOUS, "manipulator.pin_friction.viscous", KEY_REAL, LIB,              \
    RPS3_F_VISCOUS, REQ_NO, "T_{i-3} of (23)",                                 \
    "viscous pin friction (effect pin_friction)")                              \
  X(K_COULOMB, "manipulator.pin_friction.coulomb", KEY_REAL, LIB,              \
    RPS3_F_COULOMB, REQ_NO, "T_{i-3} of (23)",                                 \
    "Coulomb pin friction (effect pin_friction)")                              \
  X(K_VREG, "manipulator.pin_friction.vreg", KEY_REAL, LIB, RPS3_F_VREG,       \
    REQ_NO, "-",                                                               \
    "Coulomb law tanh(dtheta / vreg) instead of sign(dtheta); 0 = sign")       \
  SCENE_BODY_KEYS(X)                                                           \
  X(K_DES_STROKE_MIN, "manipulator.stroke.min", KEY_REAL, DES, RPS3_DF_L_MIN,  \
    REQ_YES, "l_min",                                                          \
    "design: shortest link length l_i (the actuator retracted)")               \
  X(K_DES_STROKE_MAX, "manipulator.stroke.max", KEY_REAL, DES, RPS3_DF_L_MAX,  \
    REQ_YES, "l_max",                                                          \
    "design: longest link length l_i (the actuator extended), above min")      \
  X(K_DES_PIN_MIN, "manipulator.pin.min", KEY_REAL, DES, RPS3_DF_THETA_MIN,    \
    REQ_NO, "theta_i",                                                         \
    "design: smallest pin joint angle theta_i, link to base plane (39)")       \
  X(K_DES_PIN_MAX, "manipulator.pin.max", KEY_REAL, DES, RPS3_DF_THETA_MAX,    \
    REQ_NO, "theta_i", "design: largest pin joint angle theta_i, above min")   \
  X(K_DES_BALL_MAX, "manipulator.ball.max", KEY_REAL, DES, RPS3_DF_BALL_MAX,   \
    REQ_NO, "-",                                                               \
    "design: ball joint cone half-angle, the largest angle between a link "    \
    "and the platform normal")                                                 \
  X(K_DES_LINK_RADIUS, "manipulator.link_radius", KEY_REAL, DES,               \
    RPS3_DF_LINK_RADIUS, REQ_NO, "-",                                          \
    "design: radius of a link's capsule for interference between links; 0: "   \
    "not checked")                                                             \
  X(K_DES_LINK_DENSITY, "manipulator.link_density", KEY_REAL, DES,             \
    RPS3_DF_LINK_DENSITY, REQ_NO, "-",                                         \
    "design: mass per length of a link's rod (pin to l_max), added to the "    \
    "actuator body m at d; 0: the link is m at d")                             \
  X(K_KIND, "trajectory.kind", KEY_ENUM, LIB, RPS3_F_KIND, REQ_YES, "-",       \
    "helix (the paper's section VI), sine, waypoints, path or table "          \
    "(docs/trajectories.md)")                                                  \
  X(K_RADIUS, "trajectory.radius", KEY_REAL, LIB, RPS3_F_HELIX_RADIUS,         \
    REQ_YES, "r*", "helix radius, below r/2, eqs. (35), (37)")                 \
  X(K_PITCH, "trajectory.pitch", KEY_REAL, LIB, RPS3_F_HELIX_PITCH, REQ_YES,   \
    "h", "helix pitch: rise of z_c in T*")                                     \
  X(K_Z0, "trajectory.z0", KEY_REAL, LIB, RPS3_F_HELIX_Z0, REQ_YES, "z_i",     \
    "platform centre height at t = 0, (35)")                                   \
  X(K_PERIOD, "trajectory.period", KEY_REAL, LIB, RPS3_F_HELIX_PERIOD,         \
    REQ_YES, "T*", "time for one pitch (one turn)")                            \
  X(K_BLEND, "trajectory.blend", KEY_REAL, LIB, RPS3_F_HELIX_BLEND,            \
    REQ_ONE_BLEND, "t_a",                                                      \
    "parabolic blend at both ends, t_a <= T*/2; t_b = T* - t_a; or give "      \
    "blend_ratio")                                                             \
  X(K_BLEND_RATIO, "trajectory.blend_ratio", KEY_REAL, OWN,                    \
    (own.blend_ratio, RPS3_IN_HELIX, 0, 1, 0.5, "1", RPS3_F_HELIX_BLEND),      \
    REQ_ONE_BLEND, "t_a/T*",                                                   \
    "the blend as a fraction of T* (Table II: 0.1), so that a sweep of T* "    \
    "keeps the shape of the motion; or give blend")                            \
  X(K_MEAN, "trajectory.mean", KEY_REAL3, LIB, RPS3_F_SINE_MEAN, REQ_YES, "-", \
    "mean of [alpha, beta, z_c]")                                              \
  X(K_AMP, "trajectory.amp", KEY_REAL3, LIB, RPS3_F_SINE_AMP, REQ_YES, "-",    \
    "amplitude of [alpha, beta, z_c]")                                         \
  X(K_FREQ, "trajectory.freq", KEY_REAL3, LIB, RPS3_F_SINE_FREQ, REQ_YES, "-", \
    "frequency of [alpha, beta, z_c]")                                         \
  X(K_PHASE, "trajectory.phase", KEY_REAL3, LIB, RPS3_F_SINE_PHASE, REQ_NO,    \
    "-", "phase of [alpha, beta, z_c]")                                        \
  X(K_DURATION, "trajectory.duration", KEY_REAL, LIB, RPS3_F_SINE_DURATION,    \
    REQ_YES, "-", "time span of the sine trajectory")                          \
  X(K_WP_TIMES, "trajectory.waypoints.times", KEY_TIMES, LIB, RPS3_F_WP_TIME,  \
    REQ_YES, "-", "times of the waypoints, from 0, strictly increasing")       \
  X(K_WP_POSES, "trajectory.waypoints.poses", KEY_POSES, LIB, RPS3_F_WP_POSE,  \
    REQ_YES, "-", "one [alpha, beta, z_c] per time; each must be reachable")   \
  X(K_WP_LAW, "trajectory.waypoints.law", KEY_ENUM, LIB, RPS3_F_WP_LAW,        \
    REQ_NO, "-",                                                               \
    "lspb and minimum_jerk stop at each waypoint; quintic passes through "     \
    "them (docs/trajectories.md)")                                             \
  X(K_WP_BLEND, "trajectory.waypoints.blend_ratio", KEY_REAL, LIB,             \
    RPS3_F_WP_BLEND, REQ_NO, "-",                                              \
    "lspb: blend at each end of a segment, as a fraction of it")               \
  X(K_WP_VMAX, "trajectory.waypoints.vmax", KEY_REAL3, LIB, RPS3_F_WP_VMAX,    \
    REQ_NO, "-",                                                               \
    "rate limits of [alpha, beta, z_c] that stretch a segment (0: none)")      \
  X(K_WP_AMAX, "trajectory.waypoints.amax", KEY_REAL3, LIB, RPS3_F_WP_AMAX,    \
    REQ_NO, "-",                                                               \
    "acceleration limits of [alpha, beta, z_c] that stretch a segment (0: "    \
    "none)")                                                                   \
  X(K_PATH_SHAPE, "trajectory.path.shape", KEY_ENUM, LIB, RPS3_F_PATH_SHAPE,   \
    REQ_YES, "-",                                                              \
    "line, circle, helix or table of the platform centre, through (3)-(4)")    \
  X(K_PATH_START, "trajectory.path.start", KEY_REAL3, LIB, RPS3_F_PATH_START,  \
    REQ_SHAPE, "-", "line: first point [x, y, z] of the centre")               \
  X(K_PATH_END, "trajectory.path.end", KEY_REAL3, LIB, RPS3_F_PATH_END,        \
    REQ_SHAPE, "-", "line: last point [x, y, z] of the centre")                \
  X(K_PATH_CENTRE, "trajectory.path.centre", KEY_REAL3, LIB,                   \
    RPS3_F_PATH_CENTRE, REQ_SHAPE, "-",                                        \
    "circle, helix: centre [x, y, z] of the circle at t = 0")                  \
  X(K_PATH_RADIUS, "trajectory.path.radius", KEY_REAL, LIB,                    \
    RPS3_F_PATH_RADIUS, REQ_SHAPE, "r*",                                       \
    "circle, helix: radius; every point keeps 0 < sqrt(x^2 + y^2) < r/2")      \
  X(K_PATH_ANGLE0, "trajectory.path.angle0", KEY_REAL, LIB,                    \
    RPS3_F_PATH_ANGLE0, REQ_NO, "-",                                           \
    "circle, helix: starting angle from +X (default 0)")                       \
  X(K_PATH_TURNS, "trajectory.path.turns", KEY_REAL, LIB, RPS3_F_PATH_TURNS,   \
    REQ_SHAPE, "-", "circle, helix: turns, negative clockwise")                \
  X(K_PATH_PITCH, "trajectory.path.pitch", KEY_REAL, LIB, RPS3_F_PATH_PITCH,   \
    REQ_SHAPE, "h", "helix: rise per turn, uniform in time as in (35)")        \
  X(K_PATH_DURATION, "trajectory.path.duration", KEY_REAL, LIB,                \
    RPS3_F_PATH_DURATION, REQ_SHAPE, "T*",                                     \
    "line, circle, helix: time to run the path")                               \
  X(K_PATH_LAW, "trajectory.path.law", KEY_ENUM, LIB, RPS3_F_PATH_LAW, REQ_NO, \
    "-", "time law of the path parameter: lspb or minimum_jerk")               \
  X(K_PATH_BLEND, "trajectory.path.blend_ratio", KEY_REAL, LIB,                \
    RPS3_F_PATH_BLEND, REQ_NO, "t_a/T*",                                       \
    "lspb: blend at each end as a fraction of the duration")                   \
  X(K_PATH_FILE, "trajectory.path.file", KEY_FILE, LIB,                        \
    RPS3_F_PATH_TABLE_VALUE, REQ_SHAPE, "-",                                   \
    "table: CSV or HDF5 file of rows t, x, y, z of the centre [, rates "       \
    "NAME_dot [, accelerations NAME_ddot]], relative to the scene; its time "  \
    "is the table's")                                                          \
  X(K_TABLE_FILE, "trajectory.table.file", KEY_FILE, LIB, RPS3_F_TABLE_VALUE,  \
    REQ_YES, "-",                                                              \
    "CSV or HDF5 file of rows t, alpha, beta, z_c [, rates NAME_dot [, "       \
    "accelerations NAME_ddot]], relative to the scene; interpolated by a "     \
    "spline or Hermite polynomials (docs/trajectories.md)")                    \
  X(K_SAMPLES, "trajectory.samples", KEY_INT, OWN,                             \
    (own.samples, RPS3_IN_TRAJ, 2, 0, 2147483647.0, "1", -1), REQ_ONE_GRID,    \
    "-", "time samples over the span, both ends included; or give dt")         \
  X(K_DT, "trajectory.dt", KEY_REAL, OWN,                                      \
    (own.dt, RPS3_IN_TRAJ, GT0, "s", -1), REQ_ONE_GRID, "-",                   \
    "time step; the span must be a whole number of steps; or give samples")    \
  X(K_EFFECTS, "effects", KEY_EFFECTS, LIB, RPS3_F_EFFECTS, REQ_NO, "-",       \
    "effects to compute (default: the paper's four, plus payload, "            \
    "pin_friction and prismatic_friction when configured; a list must name "   \
    "every configured one)")                                                   \
  X(K_THETA, "solver.theta", KEY_ENUM, LIB, RPS3_F_THETA, REQ_NO, "theta_i",   \
    "closed_form (eq. 39) or multiroot (eqs. 8-10, GSL)")                      \
  X(K_METHOD, "solver.method", KEY_ENUM, LIB, RPS3_F_METHOD, REQ_NO, "-",      \
    "lagrange (the paper's eqs. 21-24, 34) or newton_euler")                   \
  X(K_TOL, "solver.tolerance", KEY_REAL, LIB, RPS3_F_TOL, REQ_NO, "-",         \
    "theta solve: stop when max_k abs(f_k) <= tolerance")                      \
  X(K_MAX_ITER, "solver.max_iter", KEY_INT, LIB, RPS3_F_MAX_ITER, REQ_NO, "-", \
    "theta solve iteration limit")                                             \
  X(K_SOLVER, "solver.solver", KEY_ENUM, LIB, RPS3_F_SOLVER, REQ_NO, "-",      \
    "GSL multiroot solver (hybridsj, hybridj, newton, ...)")                   \
  X(K_WARM, "solver.warm_start", KEY_BOOL, LIB, RPS3_F_WARM_START, REQ_NO,     \
    "-", "theta solve starts from the previous sample of the case")            \
  X(K_OUTPUTS, "solver.outputs", KEY_OUTPUTS, LIB, RPS3_F_OUTPUTS, REQ_NO,     \
    "-",                                                                       \
    "results to compute (default: all): forces, effects, theta, lambda, "      \
    "transmission, certify (the energy-rate residual); the others are NaN")    \
  X(K_COND_WARN, "solver.cond_warn", KEY_REAL, LIB, RPS3_F_COND_WARN, REQ_NO,  \
    "-", "warn above this condition number")                                   \
  X(K_COND_MAX, "solver.cond_max", KEY_REAL, LIB, RPS3_F_COND_MAX, REQ_NO,     \
    "-", "fail (singular) above this condition number")                        \
  X(K_TRANS_WARN, "solver.trans_warn", KEY_REAL, LIB, RPS3_F_TRANS_WARN,       \
    REQ_NO, "-",                                                               \
    "warn above this force transmission (actuator force per unit platform "    \
    "load)")                                                                   \
  X(K_TRANS_MAX, "solver.trans_max", KEY_REAL, LIB, RPS3_F_TRANS_MAX, REQ_NO,  \
    "-", "fail (singular) above this force transmission")                      \
  X(K_MODE, "solver.mode", KEY_INT, LIB, RPS3_F_MODE, REQ_NO, "-",             \
    "assembly mode the theta solve must return: 0 any, 1 the level "           \
    "platform's (det df/dtheta > 0), -1 the other")                            \
  X(K_SIM_CONTROLLER, "simulate.controller", KEY_ENUM, SIM,                    \
    (sim.controller, 0, 0, RPS3_NCTRL - 1, "-", RPS3_CTRL_COMPUTED_TORQUE,     \
     NULL),                                                                    \
    REQ_NO, "-",                                                               \
    "the control law (docs/simulation.md): open_loop (the inverse dynamics "   \
    "of the desired motion), pd, pd_gravity or computed_torque")               \
  X(K_SIM_KP, "simulate.kp", KEY_REAL, SIM,                                    \
    (sim.kp, GE0, "N/m or 1/s^2", SIM_UNSET,                                   \
     "by kind: pd 2000, computed_torque 400"),                                 \
    REQ_NO, "-",                                                               \
    "position gain: N/m for pd and pd_gravity, 1/s^2 for computed_torque "     \
    "(e'' + kd e' + kp e = 0); unused by open_loop")                           \
  X(K_SIM_KD, "simulate.kd", KEY_REAL, SIM,                                    \
    (sim.kd, GE0, "N s/m or 1/s", SIM_UNSET,                                   \
     "by kind: pd 40, computed_torque 40"),                                    \
    REQ_NO, "-",                                                               \
    "rate gain: N s/m for pd and pd_gravity, 1/s for computed_torque")         \
  X(K_SIM_RATE, "simulate.rate", KEY_REAL, SIM,                                \
    (sim.rate, GE0, "Hz", 1000.0, NULL), REQ_NO, "-",                          \
    "control rate, zero-order hold; 0: the controller at every evaluation (a " \
    "continuous law)")                                                         \
  X(K_SIM_INTEGRATOR, "simulate.integrator", KEY_ENUM, SIM,                    \
    (sim.integrator, 0, 0, RPS3_NINTEGRATOR - 1, "-", RPS3_INT_RK4, NULL),     \
    REQ_NO, "-",                                                               \
    "rk4 (fixed step, real time), rkf45, rk8pd (adaptive), msbdf, rk4imp "     \
    "(implicit, stiff friction)")                                              \
  X(K_SIM_H, "simulate.h", KEY_REAL, SIM, (sim.h, GT0, "s", 1e-3, NULL),       \
    REQ_NO, "-",                                                               \
    "step of rk4 and rk4imp (the largest dividing each control period), "      \
    "first step of the adaptive ones")                                         \
  X(K_SIM_TOL, "simulate.tolerance", KEY_REAL, SIM,                            \
    (sim.tolerance, GT0, "1", 1e-9, NULL), REQ_NO, "-",                        \
    "adaptive integrators: epsabs = epsrel on (l, dl, work)")                  \
  X(K_SIM_MAX_STEPS, "simulate.max_steps", KEY_INT, SIM,                       \
    (sim.max_steps, 1, 0, 2147483647.0, "1", 100000, NULL), REQ_NO, "-",       \
    "integrator steps per control period before the run fails")                \
  X(K_SIM_DURATION, "simulate.duration", KEY_REAL, SIM,                        \
    (sim.duration, GT0, "s", SIM_UNSET, "the trajectory's span"), REQ_NO, "-", \
    "simulated time, a whole number of the trajectory's time steps; past the " \
    "trajectory the reference is its final pose at rest")                      \
  X(K_SIM_START_OFFSET, "simulate.start_offset", KEY_REAL3, SIM,               \
    (sim.start_offset, ANY, "rad, rad, m", 0.0, NULL), REQ_NO, "-",            \
    "the plant starts at the trajectory's first pose plus this [alpha, beta, " \
    "z_c] offset, at its rates: an initial error to correct")                  \
  X(K_SIM_FMAX, "simulate.fmax", KEY_REAL, SIM,                                \
    (sim.fmax, GE0, "N", 0.0, NULL), REQ_NO, "-",                              \
    "actuator saturation abs(F_i) <= fmax; 0: none")                           \
  X(K_SIM_L_MIN, "simulate.l_min", KEY_REAL, SIM,                              \
    (sim.l_min, GE0, "m", 0.0, NULL), REQ_NO, "-",                             \
    "shortest link (stroke); a shorter one ends the case (reach)")             \
  X(K_SIM_L_MAX, "simulate.l_max", KEY_REAL, SIM,                              \
    (sim.l_max, GE0, "m", 0.0, NULL), REQ_NO, "-",                             \
    "longest link (stroke); 0: no limit")                                      \
  X(K_SIM_NOISE_L, "simulate.noise_l", KEY_REAL, SIM,                          \
    (sim.noise_l, GE0, "m", 0.0, NULL), REQ_NO, "-",                           \
    "standard deviation of the measured link lengths (Gaussian)")              \
  X(K_SIM_NOISE_DL, "simulate.noise_dl", KEY_REAL, SIM,                        \
    (sim.noise_dl, GE0, "m/s", 0.0, NULL), REQ_NO, "-",                        \
    "standard deviation of the measured link rates")                           \
  X(K_SIM_QUANT_L, "simulate.quant_l", KEY_REAL, SIM,                          \
    (sim.quant_l, GE0, "m", 0.0, NULL), REQ_NO, "-",                           \
    "quantum of the measured lengths (an encoder); 0: none")                   \
  X(K_SIM_QUANT_DL, "simulate.quant_dl", KEY_REAL, SIM,                        \
    (sim.quant_dl, GE0, "m/s", 0.0, NULL), REQ_NO, "-",                        \
    "quantum of the measured rates; 0: none")                                  \
  X(K_SIM_SEED, "simulate.seed", KEY_INT, SIM,                                 \
    (sim.seed, 0, 0, 2147483647.0, "1", 24301, NULL), REQ_NO, "-",             \
    "seed of the noise generator (runs are reproducible)")                     \
  X(K_SIM_MODEL_M, "simulate.model.M", KEY_REAL, SIM,                          \
    (sim.model_M, GE0, "kg", SIM_UNSET, "the plant's"), REQ_NO, "M",           \
    "the controller's platform mass")                                          \
  X(K_SIM_MODEL_M_OVER_M, "simulate.model.m_over_M", KEY_REAL, SIM,            \
    (sim.model_m_over_M, GE0, "1", SIM_UNSET, "the plant's"), REQ_NO, "m/M",   \
    "the controller's link mass over its M (0: the paper's case 1)")           \
  X(K_SIM_MODEL_PAY_MASS, "simulate.model.payload.mass", KEY_REAL, SIM,        \
    (sim.model_payload_mass, GE0, "kg", SIM_UNSET, "the plant's"), REQ_NO,     \
    "-",                                                                       \
    "the controller's payload mass (its centre and inertia: the plant's)")     \
  X(K_SIM_MODEL_VISCOUS, "simulate.model.pin_friction.viscous", KEY_REAL, SIM, \
    (sim.model_viscous, GE0, "N m s/rad", SIM_UNSET, "the plant's"), REQ_NO,   \
    "-", "the controller's viscous pin friction")                              \
  X(K_SIM_MODEL_COULOMB, "simulate.model.pin_friction.coulomb", KEY_REAL, SIM, \
    (sim.model_coulomb, GE0, "N m", SIM_UNSET, "the plant's"), REQ_NO, "-",    \
    "the controller's Coulomb pin friction")                                   \
  X(K_SIM_MODEL_EFFECTS, "simulate.model.effects", KEY_EFFECTS, SIM,           \
    (sim.model_effects, 0, 0, RPS3_EFF_ALL, "-", -1, "the plant's"), REQ_NO,   \
    "-",                                                                       \
    "the effects the controller's model computes (pd_gravity: its weights; "   \
    "computed_torque, open_loop: its feedforward)")                            \
  X(K_DES_ALPHA, "design.alpha", KEY_REAL3, DSEC,                              \
    (des.grid[0], ANY, "rad, rad, 1"), REQ_YES, "alpha",                       \
    "pose grid: [lo, hi, cells] of the precession angle alpha; poses at the "  \
    "cell centres")                                                            \
  X(K_DES_BETA, "design.beta", KEY_REAL3, DSEC,                                \
    (des.grid[1], ANY, "rad, rad, 1"), REQ_YES, "beta",                        \
    "pose grid: [lo, hi, cells] of the nutation angle beta")                   \
  X(K_DES_Z_C, "design.z_c", KEY_REAL3, DSEC, (des.grid[2], ANY, "m, m, 1"),   \
    REQ_YES, "z_c",                                                            \
    "pose grid: [lo, hi, cells] of the platform centre height z_c")            \
  X(K_DES_GOOD_LTI, "design.good_lti", KEY_REAL, DSEC,                         \
    (des.opts.lti_good, 0, 0, 1, "1"), REQ_NO, "-",                            \
    "good transmission: a reachable pose whose local transmission index LTI "  \
    "is at least this")                                                        \
  X(K_DES_LENGTH, "design.length", KEY_REAL, DSEC,                             \
    (des.opts.length, GE0, "m"), REQ_NO, "L",                                  \
    "characteristic length of the homogeneous condition number; 0: the "       \
    "platform radius r")                                                       \
  X(K_DES_COND_SING, "design.cond_sing", KEY_REAL, DSEC,                       \
    (des.opts.cond_sing, 1, 0, HUGE_VAL, "1"), REQ_NO, "-",                    \
    "a pose whose homogeneous condition number is above this is singular "     \
    "(not reachable)")                                                         \
  X(K_DES_PER_POSE, "design.per_pose", KEY_BOOL, DSEC,                         \
    (des.per_pose, 0, 0, 1, "-"), REQ_NO, "-",                                 \
    "also write the indices of every pose ([case, z_c, beta, alpha] "          \
    "datasets)")                                                               \
  SCENE_IDENT_KEYS(X)

#define SCENE_KEY_ID(ID, ...) ID,
typedef enum { SCENE_KEYS(SCENE_KEY_ID) SCENE_NKEY } scene_key;
#undef SCENE_KEY_ID

/* where a key's value is stored */
enum {
  SRC_LIB = 0,
  SRC_OWN = 1,
  SRC_SIM = 2,
  SRC_DES = 3,
  SRC_DSEC = 4,
  SRC_IDS = 5,
  SRC_LEGS = 6
};

/* a key of a design study: a field of the library's rps3_design, or of the
   design section */
#define SCENE_KEY_IS_DESIGN(ki) ((ki)->src == SRC_DES || (ki)->src == SRC_DSEC)

/* one row of SCENE_KEYS (its columns described there); f is its field's
   row (offset in scene_values, range, unit, trajectory kind), own the row
   of an OWN, SIM or DSEC key that f then points to */
typedef struct {
  const char *path;
  key_type type;
  int src, req; /* SRC_*, REQ_* */
  const char *symbol, *doc;
  const rps3_field_info *f;
  int fills;  /* the library field it fills, directly or converted (-1) */
  int dfield; /* SRC_DES: its rps3_design_field_id, else -1 */
  double def; /* SRC_SIM, SRC_IDS: DEFAULT */
  const char *deftext;
  rps3_field_info own;
} scene_key_info;

/* the row of key k (0 <= k < SCENE_NKEY) */
const scene_key_info *scene_key_get(int k);

/* the trajectory kind key row ki belongs to (FOR_ALL: every kind) */
int scene_key_kind(const scene_key_info *ki);

/* 1 when key row ki applies to trajectory kind `kind` */
int scene_key_applies(const scene_key_info *ki, int kind);

/* the key with this dotted path, or -1 */
int scene_key_find(const char *path);

/* the numbers of a list key (KEY_REAL3: 3, KEY_REAL6: 6), else 0 */
int scene_key_ncomp(const scene_key_info *ki);

/* the table (TABLE_POSE, TABLE_CENTRE or TABLE_MEASURED) file key k
   reads */
#define SCENE_TABLE_OF(k)              \
  ((k) == K_PATH_FILE ? TABLE_CENTRE   \
   : (k) == K_ID_DATA ? TABLE_MEASURED \
                      : TABLE_POSE)

/* one sweep axis: a key (or one component of a list key) and its values */
typedef struct {
  char path[80];    /* as written, e.g. "trajectory.amp[2]" */
  int key;          /* scene_key */
  int comp;         /* component of a list key, else -1 */
  size_t n;         /* number of values */
  double *val;      /* values; ints, bools and enums as whole numbers */
  scene_mark *mark; /* where each value comes from */
} scene_axis;

typedef struct {
  char *file; /* path as given on the command line */
  char *text; /* the file, verbatim */
  size_t text_len;
  scene_values base;               /* values from the file, else the defaults */
  unsigned char given[SCENE_NKEY]; /* 1: in the file (or swept) */
  scene_mark mark[SCENE_NKEY];     /* where each given key's value is */
  scene_mark section[4];           /* root, manipulator, trajectory, solver */
  scene_mark simulate;             /* the simulate section; line 0: none */
  scene_mark design;               /* the design section; line 0: none */
  scene_mark identify;             /* the identify section; line 0: none */
  size_t naxis;
  scene_axis *axis; /* the sweep, in file order */
  size_t ncase;     /* product of the axis lengths (1: no sweep) */
  /* waypoints, owned here; base.traj.wp points to them */
  double *wp_time;
  double (*wp_pose)[3];
  size_t wp_ntime, wp_npose;
  scene_mark *wp_time_mark, *wp_pose_mark; /* where each row is */
  table_data table[3]; /* the tables (SCENE_TABLE_OF); base.traj views the
                          first two */
  double *path_psi;    /* the path's: its polar angles, unwrapped */

  /* 1: key k is in the file itself (a sweep sets given[k] too) */
  unsigned char in_file[SCENE_NKEY];
} scene;

/* one case, ready to compute */
typedef struct {
  size_t index;       /* case number */
  scene_values v;     /* the scene's values for this case */
  rps3_model model;   /* initialised by rps3_model_init */
  rps3_traj traj;     /* checked by rps3_traj_check */
  size_t nt;          /* number of time samples */
  double span;        /* duration of the trajectory [s] */
  double step;        /* dt [s] */
  int by_ratio;       /* 1: link mass from m_over_M, 0: from m */
  int by_dt;          /* 1: grid from dt, 0: from samples */
  int by_blend_ratio; /* 1: t_a from blend_ratio, 0: from blend */
  int simulate;       /* 1: the scene has a simulate section */
  int design;         /* 1: the scene has a design section */
  int no_traj;        /* 1: a design study without a trajectory section */
} scene_case;

/* Read and parse the scene file `path` into s: 0, or -1 with the first
   error in err (s is then empty; scene_free accepts it). */
int scene_load(scene *s, const char *path, scene_error *err);

/* Free what scene_load allocated; a zeroed or failed scene is accepted. */
void scene_free(scene *s);

/* Build case `index` (< s->ncase): its sweep values, model, trajectory and
   time grid: 0, or -1 with err at the swept value or key that makes the case
   invalid. */
int scene_case_build(const scene *s, size_t index, scene_case *c,
                     scene_error *err);

/* Sweep value index of axis a in case `index`. */
size_t scene_case_coord(const scene *s, size_t index, size_t a);

/* msg into buf, as "case INDEX: msg" when the scene is swept */
void scene_case_what(const scene *s, size_t index, const char *msg, char *buf,
                     size_t sz);

/* Time of sample k of case c [s]; the last sample is exactly the span. */
double scene_case_time(const scene_case *c, size_t k);

/* 1 when cases a and b have the same time grid. */
int scene_case_same_grid(const scene_case *a, const scene_case *b);

/* Values that look like a unit mistake (a length above 10 m, beta above
   pi/2 rad, another angle beyond 2 pi rad) in the file, a sweep or a table,
   once per key, as "FILE:LINE:COL: warning: key: ..." lines on out. */
void scene_warnings_print(const scene *s, FILE *out);

/* err = mark, path and the formatted message; returns -1, so that a check
   fails with `return scene_error_set(...)` (as Lua's luaL_error) */
int scene_error_set(scene_error *err, scene_mark mark, const char *path,
                    const char *fmt, ...);

/* Print err as FILE:LINE:COLUMN: path: what, one line, on stderr. */
void scene_error_print(const char *file, const scene_error *err);

/* A growable text buffer (scene_resolved); allocates only when it grows. */
typedef struct {
  char *s;
  size_t len, cap;
  int oom; /* 1 after a failed allocation */
} scene_text;

/* The full scene of case c as YAML into out (replacing it): every key, no
   sweep, so that the case reruns alone; 0 or -1 (out of memory, libyaml). */
int scene_case_yaml(const scene_case *c, scene_text *out);

/* Free a text buffer's storage. */
void scene_text_free(scene_text *t);

/* Name of an enum value of key k (kind, theta, method, solver), or NULL. */
const char *scene_enum_name(int k, int value);

/* Print the key table (markdown) on stdout. */
void scene_keys_print(void);

#endif /* RPS3_RUNNER_SCENE_H */
