/*
 * scene_bodies.c - the keys of the bodies (scene_body_rows.h) against the
 * scene: which keys the paper's and the general bodies read, the keys of
 * every leg filled into each leg, and the key that sets a leg's field.
 */
#include "scene.h"
#include "scene_int.h"

#include <stdio.h>
#include <string.h>

/* the keys of the legs follow RPS3_LEG_FIELDS: the blocks of legs, leg1,
   leg2 and leg3, each of SCENE_LEG_NFIELD keys in the library's order */
typedef char
    leg_keys_in_order[(K_LEG1_CYL_MASS - K_LEGS_CYL_MASS == SCENE_LEG_NFIELD &&
                       K_LEG3_PRISM_VREG - K_LEGS_CYL_MASS ==
                           4 * SCENE_LEG_NFIELD - 1 &&
                       RPS3_F_LEG3_PRISMATIC_VREG - RPS3_F_LEG1_CYLINDER_MASS ==
                           3 * SCENE_LEG_NFIELD - 1)
                          ? 1
                          : -1];

/* the part of a leg (0 to SCENE_LEG_NFIELD - 1) library field id is, or
   -1 for a field of no leg */
static int leg_part(int id) {
  if (id < RPS3_F_LEG1_CYLINDER_MASS || id > RPS3_F_LEG3_PRISMATIC_VREG)
    return -1;
  return (id - RPS3_F_LEG1_CYLINDER_MASS) % SCENE_LEG_NFIELD;
}

/* 1 when key k is read by the general bodies only: the platform's, the
   cylinders', pistons' and pins' (the prismatic joints' are either's) */
static int general_only(int k) {
  int id = scene_keys[k].fills, part = leg_part(id);
  if (id >= RPS3_F_PLATFORM_BODY_MASS && id <= RPS3_F_PLATFORM_BODY_INERTIA)
    return 1;
  return part >= 0 &&
         part < RPS3_F_LEG1_PRISMATIC_VISCOUS - RPS3_F_LEG1_CYLINDER_MASS;
}

/* 1 when key k is read by the paper's bodies only: M, m (or m/M), d,
   link_Ic and the pins' common friction, the controller's too */
static int paper_only(int k) {
  switch (k) {
  case K_SIM_MODEL_M:
  case K_SIM_MODEL_M_OVER_M:
  case K_SIM_MODEL_VISCOUS:
  case K_SIM_MODEL_COULOMB: return 1;
  default: break;
  }
  switch (scene_keys[k].fills) {
  case RPS3_F_PLATFORM_MASS:
  case RPS3_F_LINK_MASS:
  case RPS3_F_D:
  case RPS3_F_LINK_IC:
  case RPS3_F_VISCOUS:
  case RPS3_F_COULOMB:
  case RPS3_F_VREG: return 1;
  default: return 0;
  }
}

int scene_bodies_read(int k, int bodies) {
  return bodies == RPS3_BODIES_GENERAL ? !paper_only(k) : !general_only(k);
}

int scene_bodies_check_keys(const scene *s, scene_error *err) {
  int bodies = s->base.model.bodies, k;
  char at[64] = "the default";
  if (s->given[K_BODIES])
    snprintf(at, sizeof at, "at %d:%d", s->mark[K_BODIES].line,
             s->mark[K_BODIES].column);
  for (k = 0; k < SCENE_NKEY; k++) {
    if (!s->given[k] || scene_bodies_read(k, bodies)) continue;
    if (bodies == RPS3_BODIES_GENERAL)
      return scene_error_set(
          err, s->mark[k], scene_keys[k].path,
          "a key of the paper's bodies, not read with manipulator.bodies: "
          "general (%s); the platform is manipulator.platform, the legs "
          "manipulator.legs (docs/runner.md, \"General bodies\")",
          at);
    return scene_error_set(
        err, s->mark[k], scene_keys[k].path,
        "read only with manipulator.bodies: general, not paper (%s); the "
        "paper's bodies are M, m, d and link_Ic (docs/runner.md, \"General "
        "bodies\")",
        at);
  }
  return 0;
}

int scene_key_sets(const scene *s, int k, int id) {
  int part = leg_part(id), own;
  if (scene_keys[k].src != SRC_LEGS) return scene_keys[k].fills == id;
  if (part < 0 || scene_keys[k].fills != RPS3_F_LEG1_CYLINDER_MASS + part)
    return 0;
  /* a key of every leg sets the legs whose own is not in the file, but
     for the components their own sweep sets: all of a number */
  own = K_LEG1_CYL_MASS + (id - RPS3_F_LEG1_CYLINDER_MASS);
  return !s->in_file[own] && !(s->given[own] && scene_keys[own].f->n == 1);
}

int scene_leg_key(const scene *s, int id) {
  int own = K_LEG1_CYL_MASS + (id - RPS3_F_LEG1_CYLINDER_MASS);
  int all = K_LEGS_CYL_MASS + leg_part(id);
  if (leg_part(id) < 0) return -1;
  return s->given[own] ? own : s->given[all] ? all : -1;
}

int scene_legs_fill(const scene *s, scene_values *v) {
  int part, i, n = 0;
  for (part = 0; part < SCENE_LEG_NFIELD; part++) {
    int all = K_LEGS_CYL_MASS + part;
    if (!s->given[all]) continue;
    for (i = 0; i < 3; i++) {
      int own = K_LEG1_CYL_MASS + i * SCENE_LEG_NFIELD + part;
      if (s->in_file[own]) continue;
      memcpy(scene_real_at(v, own), scene_real_at(v, all),
             (size_t)scene_keys[all].f->n * sizeof(double));
      n++;
    }
  }
  return n;
}
