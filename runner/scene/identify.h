/*
 * identify.h - a scene with an `identify:` section is an identification:
 * the paper model's parameters (include/rps3.h, "identification"), or the
 * general model's base parameters (identify.model), fitted
 * to the forces along the scene's trajectory, and optionally a Monte Carlo
 * of force noise on that fit (docs/identification.md, "Through the
 * runner").
 */
#ifndef RPS3_RUNNER_IDENTIFY_H
#define RPS3_RUNNER_IDENTIFY_H

#include "scene.h"

/* 1 when the scene is an identification (it has an identify section) */
int ident_wanted(const scene *s);

/* the model an identification fits: identify.model, or by default the
   scene's manipulator.bodies (RPS3_BODIES_PAPER or RPS3_BODIES_GENERAL) */
int ident_model(const scene *s);

/* the paper parameters (bits 1 << k) the effects make identifiable: M
   with a platform effect and no payload, md with link gravity, Ipin with
   link inertia, the payload's seven with a payload, pin.fv and pin.fc
   with pin friction */
int ident_default_params(int effects);

/* the paper parameters (bits 1 << k) whose regressor column the effects
   fill (a column of another parameter is zero) */
int ident_effect_params(int effects);

#endif /* RPS3_RUNNER_IDENTIFY_H */
