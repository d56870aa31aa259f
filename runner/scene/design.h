/*
 * design.h - a scene with a `design:` section is a design study: each case
 * of its sweep is one design (the manipulator keys, scene.h), whose
 * indices are computed over the section's grid of poses (alpha, beta, z_c)
 * and, when the scene has a trajectory, along it as the reference task
 * (docs/runner.md, "Design studies").
 */
#ifndef RPS3_RUNNER_DESIGN_H
#define RPS3_RUNNER_DESIGN_H

#include <stddef.h>

#include "scene.h"

/* the most poses of a design grid (an in-memory tile holds every pose of
   its designs) */
#define DESIGN_MAX_POSES 10000000.0

/* 1 when the scene is a design study (it has a design section) */
int design_wanted(const scene *s);

/* 1 when a design study does not read key k (the link inertia, friction,
   effects and solver keys: the design's model is rps3_design_model's) */
int design_key_unread(int k);

/* the grid of poses of the design section (rps3_design_grid: cell
   centres, alpha fastest) */
void design_grid(const scene *s, rps3_design_grid *gr);

/* the rps3_design of a built case: the design keys, and R, rho, M, the
   link's actuator body m and d, the payload (mass, com[2]) and g of its
   model */
void design_of_case(const scene_case *c, rps3_design *d);

/*
 * Build design `index` (< s->ncase): scene_case_build (the model checked
 * by the library, and the task trajectory when the scene has one), then
 * the design's own rules: a stroke with min < max, a pin
 * range with min < max, then rps3_design_model; a failure is located at the
 * swept value or the key that makes the design invalid.  Returns 0, or -1 with
 * err set.
 */
int design_case_build(const scene *s, size_t index, scene_case *c,
                      scene_error *err);

#endif /* RPS3_RUNNER_DESIGN_H */
