/*
 * scene_sim.h - the keys of a scene's `simulate:` section (included by
 * scene.h): the controller, its gains and its own model of the mechanism,
 * the control rate, the integrator, the duration, the measurement and the
 * actuators.  The plant is the scene's manipulator with its effects.
 *
 * Header only, so that everything that parses scenes (the runner, the
 * study, the scene fuzzer) sees the same rows.  A value NaN (an int -1)
 * in the defaults means "not given": for the gains the controller kind's
 * default, for the duration the trajectory's span, for the controller's
 * model the plant's value.  Scene files cannot hold NaN (the parser takes
 * finite numbers only), so the sentinel never collides with a value.
 */
#ifndef RPS3_RUNNER_SCENE_SIM_H
#define RPS3_RUNNER_SCENE_SIM_H

#include <math.h>

#include "rps3.h"

/* the values of the simulate section, as the scene gives them */
typedef struct {
  int controller;           /* rps3_ctrl_kind */
  double kp, kd;            /* gains (units by kind); NaN: the kind's */
  double rate;              /* control rate [Hz]; 0: continuous */
  int integrator;           /* rps3_integrator */
  double h;                 /* fixed step / first step [s] */
  double tolerance;         /* epsabs = epsrel of the adaptive methods */
  int max_steps;            /* integrator steps per control period */
  double duration;          /* simulated time [s]; NaN: the trajectory's */
  double start_offset[3];   /* the plant's start pose minus the trajectory's
                               [rad, rad, m] */
  double fmax;              /* actuator saturation [N]; 0: none */
  double l_min, l_max;      /* stroke [m]; l_max 0: none */
  double noise_l, noise_dl; /* measurement noise, standard deviations */
  double quant_l, quant_dl; /* measurement quanta; 0: none */
  int seed;                 /* noise generator seed */
  /* the controller's model: NaN (effects -1) = the plant's value */
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

/*
 * SCENE_SIM_FIELDS X(ID, MEMBER, IS_INT, LO, LO_OPEN, HI, UNIT, DEFAULT,
 *                    DEFTEXT): rows shaped like the library's RPS3_FIELDS
 * for the members of scene_sim, with the default value and, when the
 * default is not a value, the text the key table shows.
 */
#define SCENE_SIM_FIELDS(X)                                                   \
  X(SIM_CONTROLLER, controller, 1, 0, 0, RPS3_NCTRL - 1, "-",                 \
    RPS3_CTRL_COMPUTED_TORQUE, NULL)                                          \
  X(SIM_KP, kp, 0, 0, 0, HUGE_VAL, "N/m or 1/s^2", SIM_UNSET,                 \
    "by kind: pd 2000, computed_torque 400")                                  \
  X(SIM_KD, kd, 0, 0, 0, HUGE_VAL, "N s/m or 1/s", SIM_UNSET,                 \
    "by kind: pd 40, computed_torque 40")                                     \
  X(SIM_RATE, rate, 0, 0, 0, HUGE_VAL, "Hz", 1000.0, NULL)                    \
  X(SIM_INTEGRATOR, integrator, 1, 0, 0, RPS3_NINTEGRATOR - 1, "-",           \
    RPS3_INT_RK4, NULL)                                                       \
  X(SIM_H, h, 0, 0, 1, HUGE_VAL, "s", 1e-3, NULL)                             \
  X(SIM_TOL, tolerance, 0, 0, 1, HUGE_VAL, "1", 1e-9, NULL)                   \
  X(SIM_MAX_STEPS, max_steps, 1, 1, 0, 2147483647.0, "1", 100000, NULL)       \
  X(SIM_DURATION, duration, 0, 0, 1, HUGE_VAL, "s", SIM_UNSET,                \
    "the trajectory's span")                                                  \
  X(SIM_START_OFFSET, start_offset, 0, -HUGE_VAL, 0, HUGE_VAL, "rad, rad, m", \
    0.0, NULL)                                                                \
  X(SIM_FMAX, fmax, 0, 0, 0, HUGE_VAL, "N", 0.0, NULL)                        \
  X(SIM_L_MIN, l_min, 0, 0, 0, HUGE_VAL, "m", 0.0, NULL)                      \
  X(SIM_L_MAX, l_max, 0, 0, 0, HUGE_VAL, "m", 0.0, NULL)                      \
  X(SIM_NOISE_L, noise_l, 0, 0, 0, HUGE_VAL, "m", 0.0, NULL)                  \
  X(SIM_NOISE_DL, noise_dl, 0, 0, 0, HUGE_VAL, "m/s", 0.0, NULL)              \
  X(SIM_QUANT_L, quant_l, 0, 0, 0, HUGE_VAL, "m", 0.0, NULL)                  \
  X(SIM_QUANT_DL, quant_dl, 0, 0, 0, HUGE_VAL, "m/s", 0.0, NULL)              \
  X(SIM_SEED, seed, 1, 0, 0, 2147483647.0, "1", 24301, NULL)                  \
  X(SIM_MODEL_M, model_M, 0, 0, 0, HUGE_VAL, "kg", SIM_UNSET, "the plant's")  \
  X(SIM_MODEL_M_OVER_M, model_m_over_M, 0, 0, 0, HUGE_VAL, "1", SIM_UNSET,    \
    "the plant's")                                                            \
  X(SIM_MODEL_PAY_MASS, model_payload_mass, 0, 0, 0, HUGE_VAL, "kg",          \
    SIM_UNSET, "the plant's")                                                 \
  X(SIM_MODEL_VISCOUS, model_viscous, 0, 0, 0, HUGE_VAL, "N m s/rad",         \
    SIM_UNSET, "the plant's")                                                 \
  X(SIM_MODEL_COULOMB, model_coulomb, 0, 0, 0, HUGE_VAL, "N m", SIM_UNSET,    \
    "the plant's")                                                            \
  X(SIM_MODEL_EFFECTS, model_effects, 1, 0, 0, RPS3_EFF_ALL, "-", -1,         \
    "the plant's")

#define SCENE_SIM_ID(ID, ...) ID,
enum { SCENE_SIM_FIELDS(SCENE_SIM_ID) SCENE_NSIM };
#undef SCENE_SIM_ID

/*
 * The keys, rows of SCENE_KEYS (scene.h): X(ID, path, type, SRC, FIELD,
 * req, symbol, doc).  The simulate.model.* keys stay together (the
 * resolved scene writes sections in the order of the rows).
 */
#define SCENE_SIM_KEYS(X)                                                      \
  X(K_SIM_CONTROLLER, "simulate.controller", KEY_ENUM, SIM, SIM_CONTROLLER,    \
    REQ_NO, "-",                                                               \
    "the control law (docs/simulation.md): open_loop (the inverse dynamics "   \
    "of the desired motion), pd, pd_gravity or computed_torque")               \
  X(K_SIM_KP, "simulate.kp", KEY_REAL, SIM, SIM_KP, REQ_NO, "-",               \
    "position gain: N/m for pd and pd_gravity, 1/s^2 for computed_torque "     \
    "(e'' + kd e' + kp e = 0); unused by open_loop")                           \
  X(K_SIM_KD, "simulate.kd", KEY_REAL, SIM, SIM_KD, REQ_NO, "-",               \
    "rate gain: N s/m for pd and pd_gravity, 1/s for computed_torque")         \
  X(K_SIM_RATE, "simulate.rate", KEY_REAL, SIM, SIM_RATE, REQ_NO, "-",         \
    "control rate, zero-order hold; 0: the controller at every evaluation "    \
    "(a continuous law)")                                                      \
  X(K_SIM_INTEGRATOR, "simulate.integrator", KEY_ENUM, SIM, SIM_INTEGRATOR,    \
    REQ_NO, "-",                                                               \
    "rk4 (fixed step, real time), rkf45, rk8pd (adaptive), msbdf, rk4imp "     \
    "(implicit, stiff friction)")                                              \
  X(K_SIM_H, "simulate.h", KEY_REAL, SIM, SIM_H, REQ_NO, "-",                  \
    "step of rk4 and rk4imp (the largest dividing each control period), "      \
    "first step of the adaptive ones")                                         \
  X(K_SIM_TOL, "simulate.tolerance", KEY_REAL, SIM, SIM_TOL, REQ_NO, "-",      \
    "adaptive integrators: epsabs = epsrel on (l, dl, work)")                  \
  X(K_SIM_MAX_STEPS, "simulate.max_steps", KEY_INT, SIM, SIM_MAX_STEPS,        \
    REQ_NO, "-", "integrator steps per control period before the run fails")   \
  X(K_SIM_DURATION, "simulate.duration", KEY_REAL, SIM, SIM_DURATION, REQ_NO,  \
    "-",                                                                       \
    "simulated time, a whole number of the trajectory's time steps; past "     \
    "the trajectory the reference is its final pose at rest")                  \
  X(K_SIM_START_OFFSET, "simulate.start_offset", KEY_REAL3, SIM,               \
    SIM_START_OFFSET, REQ_NO, "-",                                             \
    "the plant starts at the trajectory's first pose plus this [alpha, "       \
    "beta, z_c] offset, at its rates: an initial error to correct")            \
  X(K_SIM_FMAX, "simulate.fmax", KEY_REAL, SIM, SIM_FMAX, REQ_NO, "-",         \
    "actuator saturation abs(F_i) <= fmax; 0: none")                           \
  X(K_SIM_L_MIN, "simulate.l_min", KEY_REAL, SIM, SIM_L_MIN, REQ_NO, "-",      \
    "shortest link (stroke); a shorter one ends the case (reach)")             \
  X(K_SIM_L_MAX, "simulate.l_max", KEY_REAL, SIM, SIM_L_MAX, REQ_NO, "-",      \
    "longest link (stroke); 0: no limit")                                      \
  X(K_SIM_NOISE_L, "simulate.noise_l", KEY_REAL, SIM, SIM_NOISE_L, REQ_NO,     \
    "-", "standard deviation of the measured link lengths (Gaussian)")         \
  X(K_SIM_NOISE_DL, "simulate.noise_dl", KEY_REAL, SIM, SIM_NOISE_DL, REQ_NO,  \
    "-", "standard deviation of the measured link rates")                      \
  X(K_SIM_QUANT_L, "simulate.quant_l", KEY_REAL, SIM, SIM_QUANT_L, REQ_NO,     \
    "-", "quantum of the measured lengths (an encoder); 0: none")              \
  X(K_SIM_QUANT_DL, "simulate.quant_dl", KEY_REAL, SIM, SIM_QUANT_DL, REQ_NO,  \
    "-", "quantum of the measured rates; 0: none")                             \
  X(K_SIM_SEED, "simulate.seed", KEY_INT, SIM, SIM_SEED, REQ_NO, "-",          \
    "seed of the noise generator (runs are reproducible)")                     \
  X(K_SIM_MODEL_M, "simulate.model.M", KEY_REAL, SIM, SIM_MODEL_M, REQ_NO,     \
    "M", "the controller's platform mass")                                     \
  X(K_SIM_MODEL_M_OVER_M, "simulate.model.m_over_M", KEY_REAL, SIM,            \
    SIM_MODEL_M_OVER_M, REQ_NO, "m/M",                                         \
    "the controller's link mass over its M (0: the paper's case 1)")           \
  X(K_SIM_MODEL_PAY_MASS, "simulate.model.payload.mass", KEY_REAL, SIM,        \
    SIM_MODEL_PAY_MASS, REQ_NO, "-",                                           \
    "the controller's payload mass (its centre and inertia: the plant's)")     \
  X(K_SIM_MODEL_VISCOUS, "simulate.model.pin_friction.viscous", KEY_REAL, SIM, \
    SIM_MODEL_VISCOUS, REQ_NO, "-", "the controller's viscous pin friction")   \
  X(K_SIM_MODEL_COULOMB, "simulate.model.pin_friction.coulomb", KEY_REAL, SIM, \
    SIM_MODEL_COULOMB, REQ_NO, "-", "the controller's Coulomb pin friction")   \
  X(K_SIM_MODEL_EFFECTS, "simulate.model.effects", KEY_EFFECTS, SIM,           \
    SIM_MODEL_EFFECTS, REQ_NO, "-",                                            \
    "the effects the controller's model computes (pd_gravity: its weights; "   \
    "computed_torque, open_loop: its feedforward)")

#endif /* RPS3_RUNNER_SCENE_SIM_H */
