/*
 * scene.c - the scene's key table, enum names and values, its errors, its
 * values by key, and scene_free.
 *
 * Parsing is table driven: SCENE_KEYS (scene.h) names every leaf key with
 * its type, range and unit.  Each error carries the libyaml mark of the node
 * it is about, so that the runner can print FILE:LINE:COLUMN: key: what.
 * scene_load.c reads a file with libyaml's document API; the YAML nodes
 * are read in scene_parse.c, the sweep and the checks of the
 * given keys are in scene_sweep.c, each case is built in scene_case.c and
 * written back as YAML in scene_emit.c.
 */
#include "scene.h"
#include "core/hint.h"
#include "scene_int.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* ------------------------------------------------------------- key table */

/* the runner's own fields, rows shaped like the library's */
#define OWN_ROW(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME, FILLS) \
  {NAME, IN, offsetof(scene_own, MEMBER), N, IS_INT, LO, LO_OPEN, HI, UNIT},
static const rps3_field_info own_fields[SCENE_NOWN] = {
    SCENE_OWN_FIELDS(OWN_ROW)};
#undef OWN_ROW
#define OWN_FILLS(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME, \
                  FILLS)                                                  \
  FILLS,
static const int own_fills[SCENE_NOWN] = {SCENE_OWN_FIELDS(OWN_FILLS)};
#undef OWN_FILLS

/* the simulate section's fields (scene_sim.h) and their defaults (the key
   table's text for a default that is not a value: scene_emit.c) */
#define SIM_ROW(ID, MEMBER, IS_INT, LO, LO_OPEN, HI, UNIT, DEF, DEFTEXT) \
  {"simulate." #MEMBER,                                                  \
   RPS3_IN_MODEL,                                                        \
   offsetof(scene_sim, MEMBER),                                          \
   1,                                                                    \
   IS_INT,                                                               \
   LO,                                                                   \
   LO_OPEN,                                                              \
   HI,                                                                   \
   UNIT},
static const rps3_field_info sim_fields[SCENE_NSIM] = {
    SCENE_SIM_FIELDS(SIM_ROW)};
#undef SIM_ROW
#define SIM_DEF(ID, MEMBER, IS_INT, LO, LO_OPEN, HI, UNIT, DEF, DEFTEXT) DEF,
static const double sim_default[SCENE_NSIM] = {SCENE_SIM_FIELDS(SIM_DEF)};
#undef SIM_DEF

/* the rows as written; scene_keys[] adds what their field's row says */
#define KEY_ROW(ID, PATH, TYPE, SRC, FIELD, REQ, SYM, DOC) \
  {PATH, TYPE, SRC_##SRC, FIELD, NULL, 0, REQ, NULL, SYM, DOC},
static const scene_key_info key_rows[SCENE_NKEY] = {SCENE_KEYS(KEY_ROW)};
#undef KEY_ROW
scene_key_info scene_keys[SCENE_NKEY];

/* complete scene_keys[] from key_rows[] and the field rows, once; called from
   the entry points, before any thread starts */
void scene_keys_build(void) {
  static int built;
  int k;
  if (built) return;
  for (k = 0; k < SCENE_NKEY; k++) {
    scene_key_info *ki = &scene_keys[k];
    *ki = key_rows[k];
    ki->f = ki->src == SRC_OWN   ? &own_fields[ki->field]
            : ki->src == SRC_SIM ? &sim_fields[ki->field]
                                 : rps3_field(ki->field);
    ki->unit = ki->f->unit;
    ki->kind = ki->f->in >= RPS3_IN_HELIX ? ki->f->in - 1 : FOR_ALL;
  }
  built = 1;
}

/* the path shapes (bits 1 << rps3_path_shape) that use key k, for the
   keys marked REQ_SHAPE; 0 for any other key */
int scene_shape_mask(int k) {
  const int line = 1 << RPS3_PATH_LINE, circle = 1 << RPS3_PATH_CIRCLE,
            helix = 1 << RPS3_PATH_HELIX;
  switch (k) {
  case K_PATH_START:
  case K_PATH_END: return line;
  case K_PATH_DURATION:
  case K_PATH_LAW:
  case K_PATH_BLEND: return line | circle | helix;
  case K_PATH_FILE: return 1 << RPS3_PATH_TABLE;
  case K_PATH_CENTRE:
  case K_PATH_RADIUS:
  case K_PATH_TURNS:
  case K_PATH_ANGLE0: return circle | helix;
  case K_PATH_PITCH: return helix;
  default: return 0;
  }
}

/* the library field key k fills, directly or converted (-1: none) */
int scene_key_fills(int k) {
  if (scene_keys[k].src == SRC_SIM)
    return -1; /* the controller's model and the simulation: not the plant */
  return scene_keys[k].src == SRC_OWN ? own_fills[scene_keys[k].field]
                                      : scene_keys[k].field;
}

const scene_key_info *scene_key_get(int k) {
  scene_keys_build();
  return (k >= 0 && k < SCENE_NKEY) ? &scene_keys[k] : NULL;
}

int scene_key_find(const char *path) {
  int k;
  scene_keys_build();
  for (k = 0; k < SCENE_NKEY; k++)
    if (strcmp(scene_keys[k].path, path) == 0) return k;
  return -1;
}

/* ---------------------------------------------------------- enum names */

static const char *const kind_names[] = {NULL,        "helix", "sine",
                                         "waypoints", "path",  "table"};
static const char *const shape_names[] = {"line", "circle", "helix", "table"};
static const char *const theta_names[] = {"closed_form", "multiroot"};
static const char *const method_names[] = {"lagrange", "newton_euler"};

const char *scene_enum_name(int k, int value) {
  switch (k) {
  case K_KIND:
    return (value >= RPS3_TRAJ_HELIX && value <= RPS3_TRAJ_TABLE)
               ? kind_names[value]
               : NULL;
  case K_THETA: return (value == 0 || value == 1) ? theta_names[value] : NULL;
  case K_METHOD: return (value == 0 || value == 1) ? method_names[value] : NULL;
  case K_SOLVER: return rps3_solver_name(value);
  case K_WP_LAW:
  case K_PATH_LAW: return rps3_time_law_name(value);
  case K_PATH_SHAPE:
    return (value >= 0 && value <= RPS3_PATH_TABLE) ? shape_names[value] : NULL;
  case K_SIM_CONTROLLER: return rps3_ctrl_name(value);
  case K_SIM_INTEGRATOR: return rps3_integrator_name(value);
  default: return NULL;
  }
}

/* range of enum values of key k: [*lo, *hi] */
static void enum_range(int k, int *lo, int *hi) {
  /* the library's range of the field */
  *lo = (int)scene_keys[k].f->lo;
  *hi = (int)scene_keys[k].f->hi;
}

int scene_enum_find(int k, const char *name) {
  int v, lo, hi;
  enum_range(k, &lo, &hi);
  for (v = lo; v <= hi; v++) {
    const char *n = scene_enum_name(k, v);
    if (n && strcmp(n, name) == 0) return v;
  }
  return -1;
}

/* "a, b or c" list of the names of key k into buf */
void scene_enum_list(int k, char *buf, size_t sz) {
  int v, lo, hi;
  size_t len = 0;
  enum_range(k, &lo, &hi);
  buf[0] = '\0';
  for (v = lo; v <= hi && len < sz; v++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s",
                            v == lo ? "" : (v == hi ? " or " : ", "),
                            scene_enum_name(k, v));
}

void scene_effect_list(char *buf, size_t sz) {
  int e;
  size_t len = 0;
  buf[0] = '\0';
  for (e = 0; e < RPS3_NEFFECT && len < sz; e++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s", e ? ", " : "",
                            rps3_effect_name(e));
}

void scene_output_list(char *buf, size_t sz) {
  int e;
  size_t len = 0;
  buf[0] = '\0';
  for (e = 0; e < RPS3_NOUTPUT && len < sz; e++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s", e ? ", " : "",
                            rps3_output_name(e));
}

/* -------------------------------------------------------------- values */

/* where key k's value is stored in v */
static char *value_at(scene_values *v, int k) {
  char *base = scene_keys[k].src == SRC_OWN           ? (char *)&v->own
               : scene_keys[k].src == SRC_SIM         ? (char *)&v->sim
               : scene_keys[k].f->in == RPS3_IN_MODEL ? (char *)&v->model
                                                      : (char *)&v->traj;
  return base + scene_keys[k].f->offset;
}

double *scene_real_at(scene_values *v, int k) {
  return (double *)(void *)value_at(v, k);
}

int *scene_int_at(scene_values *v, int k) {
  return (int *)(void *)value_at(v, k);
}

double scene_value_real(const scene_values *v, int k, int comp) {
  double x;
  scene_keys_build();
  memcpy(&x,
         value_at((scene_values *)(void *)v, k) +
             (size_t)(comp < 0 ? 0 : comp) * sizeof x,
         sizeof x);
  return x;
}

/* set key k (component comp of a KEY_REAL3) to x */
void scene_value_set(scene_values *v, int k, int comp, double x) {
  switch (scene_keys[k].type) {
  case KEY_REAL: *scene_real_at(v, k) = x; break;
  case KEY_REAL3: scene_real_at(v, k)[comp] = x; break;
  default: *scene_int_at(v, k) = (int)x; break;
  }
}

/* defaults: the library's Table II model, options and helix; the runner's
   own values are those the library's defaults imply */
void scene_values_default(scene_values *v) {
  int i;
  memset(v, 0, sizeof *v);
  for (i = 0; i < SCENE_NSIM; i++) {
    char *p = (char *)&v->sim + sim_fields[i].offset;
    if (sim_fields[i].is_int)
      *(int *)(void *)p = (int)sim_default[i];
    else
      *(double *)(void *)p = sim_default[i];
  }
  rps3_model_default(&v->model);
  rps3_traj_default(&v->traj);
  v->own.m_over_M = v->model.M > 0 ? v->model.m / v->model.M : 0;
  v->own.blend_ratio = v->traj.helix.blend / v->traj.helix.period;
}

/* " (did you mean ...?)" for an enum value of key k */
void scene_enum_hint(char *buf, size_t sz, int k, const char *word) {
  const char *cand[64];
  int v, lo, hi;
  size_t n = 0;
  enum_range(k, &lo, &hi);
  for (v = lo; v <= hi && n < 64; v++) cand[n++] = scene_enum_name(k, v);
  hint_text(buf, sz, word, cand, n);
}

/* ---------------------------------------------------------------- errors */

void scene_error_set(scene_error *err, scene_mark mark, const char *path,
                     const char *fmt, ...) {
  va_list ap;
  err->mark = mark;
  snprintf(err->path, sizeof err->path, "%s", path);
  va_start(ap, fmt);
  vsnprintf(err->what, sizeof err->what, fmt, ap);
  va_end(ap);
}

void scene_error_print(const char *file, const scene_error *err) {
  if (err->mark.line > 0)
    fprintf(stderr, "%s:%d:%d: %s: %s\n", file, err->mark.line,
            err->mark.column, err->path, err->what);
  else
    fprintf(stderr, "%s: %s: %s\n", file, err->path, err->what);
}

scene_mark scene_mark_of(const yaml_mark_t *m) {
  scene_mark r;
  r.line = (int)m->line + 1;
  r.column = (int)m->column + 1;
  return r;
}

void scene_free(scene *s) {
  size_t a;
  if (!s) return;
  for (a = 0; a < s->naxis; a++) {
    free(s->axis[a].val);
    free(s->axis[a].mark);
  }
  free(s->axis);
  free(s->wp_time);
  free(s->wp_pose);
  free(s->wp_time_mark);
  free(s->wp_pose_mark);
  table_free(&s->table);
  table_free(&s->path_table);
  free(s->path_psi);
  free(s->text);
  free(s->file);
  memset(s, 0, sizeof *s);
}
