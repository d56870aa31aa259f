/*
 * scene_sim.h - the values of a scene's `simulate:` section (its keys are
 * rows of SCENE_KEYS in scene.h): the controller, its gains and its own
 * model of the mechanism, the control rate, the integrator, the duration,
 * the measurement and the actuators.  The plant is the scene's manipulator
 * with its effects.
 *
 * A value NaN (an int -1) in the defaults means "not given": for the gains
 * the controller kind's default, for the duration the trajectory's span,
 * for the controller's model the plant's value.  Scene files cannot hold
 * NaN (the parser takes finite numbers only), so the sentinel never
 * collides with a value.
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

#endif /* RPS3_RUNNER_SCENE_SIM_H */
