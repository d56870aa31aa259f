/*
 * identify.c - the identify keys against the scene (scene_ident_check_keys)
 * and the parameters the effects make identifiable (identify.h).
 */
#include "identify.h"
#include "scene_int.h"

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

int scene_ident_check_keys(const scene *s, scene_error *err) {
  if (!ident_wanted(s)) return 0;
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
