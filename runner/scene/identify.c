/*
 * identify.c - the identify keys against the scene (scene_ident_check_keys)
 * and the parameters the effects make identifiable (identify.h).
 */
#include "identify.h"
#include "scene_int.h"

#include <stdio.h>

int ident_wanted(const scene *s) { return s->identify.line > 0; }

int ident_data_only(const scene *s) {
  return ident_wanted(s) && s->given[K_ID_DATA];
}

/* the paper columns (rps3_paper_name order) of each effect */
#define P_PAYLOAD (((1 << 7) - 1) << 3) /* payload.m .. payload.Izz */
#define P_FRICTION (3 << 10)            /* pin.fv, pin.fc */

int ident_effect_params(int effects) {
  int p = 0;
  if (effects & (RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA))
    p |= 1 << 0;
  if (effects & RPS3_EFF_LINK_GRAVITY) p |= 1 << 1;
  if (effects & RPS3_EFF_LINK_INERTIA) p |= 1 << 2;
  if (effects & RPS3_EFF_PAYLOAD) p |= P_PAYLOAD;
  if (effects & RPS3_EFF_PIN_FRICTION) p |= P_FRICTION;
  return p;
}

int ident_default_params(int effects) {
  int p = ident_effect_params(effects);
  /* the payload's columns hold the platform's disc as well (rps3.h):
     with them M is not separable */
  if (effects & RPS3_EFF_PAYLOAD) p &= ~1;
  return p;
}

int ident_model(const scene *s) {
  return s->base.ids.model >= 0 ? s->base.ids.model : s->base.model.bodies;
}

/* where the model comes from, for the messages */
static void model_origin(const scene *s, char *buf, size_t sz) {
  if (s->given[K_ID_MODEL])
    snprintf(buf, sz, "identify.model at %d:%d", s->mark[K_ID_MODEL].line,
             s->mark[K_ID_MODEL].column);
  else if (s->given[K_BODIES])
    snprintf(buf, sz, "manipulator.bodies at %d:%d", s->mark[K_BODIES].line,
             s->mark[K_BODIES].column);
  else
    snprintf(buf, sz, "the default manipulator.bodies");
}

int scene_ident_check_keys(const scene *s, scene_error *err) {
  char from[96];
  if (!ident_wanted(s)) return 0;
  model_origin(s, from, sizeof from);
  if (ident_model(s) == RPS3_BODIES_GENERAL && s->given[K_ID_PARAMS])
    return scene_error_set(
        err, s->mark[K_ID_PARAMS], "identify.parameters",
        "the paper model's parameters, but the model is general (%s): it "
        "fits the base parameters of the standard parameters (mass, first "
        "moment, inertia about the origin) of the bodies the effects fill, "
        "the platform and the legs' cylinders and pistons, and the friction "
        "they select (identify.legs: each or identical); remove this key, "
        "or set identify.model: paper",
        from);
  if (ident_model(s) == RPS3_BODIES_PAPER && s->given[K_ID_LEGS])
    return scene_error_set(
        err, s->mark[K_ID_LEGS], "identify.legs",
        "read only with identify.model: general, but the model is paper "
        "(%s): its links are identical by construction (md, Ipin)",
        from);
  if (s->simulate.line > 0)
    return scene_error_set(err, s->identify, "identify",
                           "a scene is an identification or a simulation, not "
                           "both (simulate section at %d:%d); the "
                           "identification's forces are the inverse dynamics "
                           "of the trajectory",
                           s->simulate.line, s->simulate.column);
  if (s->design.line > 0)
    return scene_error_set(err, s->identify, "identify",
                           "a scene is an identification or a design study, "
                           "not both (design section at %d:%d)",
                           s->design.line, s->design.column);
  if (s->given[K_ID_DATA] && s->section[2].line > 0)
    return scene_error_set(err, s->mark[K_ID_DATA], "identify.data",
                           "the data are the motion: remove the trajectory "
                           "section (at %d:%d), or this key to fit the "
                           "trajectory's inverse dynamics",
                           s->section[2].line, s->section[2].column);
  if (s->naxis > 0)
    return scene_error_set(err, s->axis[0].mark[0], s->axis[0].path,
                           "an identification fits one scene: no sweep "
                           "(write one scene per value)");
  return 0;
}
