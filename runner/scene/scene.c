/*
 * scene.c - the key table (each SCENE_KEYS row joined to its field's row),
 * the names of enums and lists, values by key, errors, and scene_free.
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

/* the library's rows (RPS3_FIELDS, RPS3_DESIGN_FIELDS) relocated into
   scene_values; a design field is of every trajectory kind */
#define OFF_RPS3_IN_MODEL(MEMBER) offsetof(scene_values, model.MEMBER)
#define OFF_RPS3_IN_TRAJ(MEMBER) offsetof(scene_values, traj.MEMBER)
#define OFF_RPS3_IN_HELIX OFF_RPS3_IN_TRAJ
#define OFF_RPS3_IN_SINE OFF_RPS3_IN_TRAJ
#define OFF_RPS3_IN_WAYPOINTS OFF_RPS3_IN_TRAJ
#define OFF_RPS3_IN_PATH OFF_RPS3_IN_TRAJ
#define OFF_RPS3_IN_TABLE OFF_RPS3_IN_TRAJ
/* a braced initializer, as a macro so that rows pack like calls */
#define ROW(...) \
  { __VA_ARGS__ }
#define LIB_ROW(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME) \
  ROW(NAME, IN, OFF_##IN(MEMBER), N, IS_INT, LO, LO_OPEN, HI, UNIT),
static const rps3_field_info lib_fields[RPS3_NFIELD] = {RPS3_FIELDS(LIB_ROW)};
#define DES_ROW(ID, MEMBER, LO, LO_OPEN, HI, UNIT, NAME)                    \
  ROW(NAME, RPS3_IN_MODEL, offsetof(scene_values, design.MEMBER), 1, 0, LO, \
      LO_OPEN, HI, UNIT),
static const rps3_field_info design_fields[RPS3_NDESIGN_FIELD] = {
    RPS3_DESIGN_FIELDS(DES_ROW)};
/* leg 1's rows relocated into scene_own.legs, for the keys of every leg */
#define LEGS_ROW(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME) \
  ROW(NULL, IN,                                                          \
      offsetof(scene_values, own.legs) + offsetof(rps3_model, MEMBER) -  \
          offsetof(rps3_model, leg),                                     \
      N, IS_INT, LO, LO_OPEN, HI, UNIT),
static const rps3_field_info legs_fields[SCENE_LEG_NFIELD] = {
    RPS3_LEG_FIELDS(LEGS_ROW, 1)};

/* each SRC's FIELD as the tail of a scene_key_info: f, fills, dfield, def,
   deftext, and the own row (MEMBER, IN, LO, LO_OPEN, HI, UNIT; an int
   unless a number key) */
#define ROW_OWN(K, T, M, IN, LO, LO_OPEN, HI, UNIT, FILLS, DEF, DEFTEXT)      \
  &scene_keys[K].own, FILLS, -1, DEF, DEFTEXT,                                \
      ROW(NULL, IN, offsetof(scene_values, M), 1,                             \
          T != KEY_REAL && T != KEY_REAL3 && T != KEY_REAL6, LO, LO_OPEN, HI, \
          UNIT)
#define NO_ROW ROW(NULL, 0, 0, 0, 0, 0, 0, 0, NULL)
#define INFO_LIB(K, T, ID) &lib_fields[ID], ID, -1, 0, NULL, NO_ROW
#define INFO_DES(K, T, ID) &design_fields[ID], -1, ID, 0, NULL, NO_ROW
#define INFO_LEGS(K, T, ID) \
  &legs_fields[ID - RPS3_F_LEG1_CYLINDER_MASS], ID, -1, 0, NULL, NO_ROW
#define INFO_OWN(K, T, M, IN, LO, LO_OPEN, HI, UNIT, FILLS) \
  ROW_OWN(K, T, M, IN, LO, LO_OPEN, HI, UNIT, FILLS, 0, NULL)
#define INFO_SIM(K, T, M, LO, LO_OPEN, HI, UNIT, DEF, DEFTEXT) \
  ROW_OWN(K, T, M, RPS3_IN_MODEL, LO, LO_OPEN, HI, UNIT, -1, DEF, DEFTEXT)
#define INFO_IDS INFO_SIM
#define INFO_DSEC(K, T, M, LO, LO_OPEN, HI, UNIT) \
  ROW_OWN(K, T, M, RPS3_IN_MODEL, LO, LO_OPEN, HI, UNIT, -1, 0, NULL)
#define APPLY(M, ...) M(__VA_ARGS__)
#define ARGS(...) __VA_ARGS__
#define UNPACK_LIB(FIELD) FIELD
#define UNPACK_DES(FIELD) FIELD
#define UNPACK_LEGS(FIELD) FIELD
#define UNPACK_OWN(FIELD) ARGS FIELD
#define UNPACK_SIM(FIELD) ARGS FIELD
#define UNPACK_DSEC(FIELD) ARGS FIELD
#define UNPACK_IDS(FIELD) ARGS FIELD
#define KEY_ROW(ID, PATH, TYPE, SRC, FIELD, REQ, SYM, DOC) \
  ROW(PATH, TYPE, SRC_##SRC, REQ, SYM, DOC,                \
      APPLY(INFO_##SRC, ID, TYPE, UNPACK_##SRC(FIELD))),
const scene_key_info scene_keys[SCENE_NKEY] = {SCENE_KEYS(KEY_ROW)};

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

const scene_key_info *scene_key_get(int k) {
  return (k >= 0 && k < SCENE_NKEY) ? &scene_keys[k] : NULL;
}

int scene_key_kind(const scene_key_info *ki) {
  return ki->f->in >= RPS3_IN_HELIX ? ki->f->in - 1 : FOR_ALL;
}

int scene_key_applies(const scene_key_info *ki, int kind) {
  return scene_key_kind(ki) == FOR_ALL || scene_key_kind(ki) == kind;
}

int scene_key_ncomp(const scene_key_info *ki) {
  return ki->type == KEY_REAL3 ? 3 : ki->type == KEY_REAL6 ? 6 : 0;
}

int scene_key_find(const char *path) {
  int k;
  for (k = 0; k < SCENE_NKEY; k++)
    if (strcmp(scene_keys[k].path, path) == 0) return k;
  return -1;
}

/* ------------------------------------------- names of enums and lists */

static const char *const kind_names[] = {NULL,        "helix", "sine",
                                         "waypoints", "path",  "table"};
static const char *const shape_names[] = {"line", "circle", "helix", "table"};
static const char *const theta_names[] = {"closed_form", "multiroot"};
static const char *const method_names[] = {"lagrange", "newton_euler"};
static const char *const ident_method_names[] = {"ols", "wls"};
static const char *const bodies_names[] = {"paper", "general"};
static const char *const ident_legs_names[] = {"each", "identical"};

/* the values of key k that have names: [*lo, *hi] (an enum: the library's
   range of the field; a list: its bits) */
static void name_range(int k, int *lo, int *hi) {
  *lo = scene_keys[k].type == KEY_ENUM ? (int)scene_keys[k].f->lo : 0;
  *hi = scene_keys[k].type == KEY_EFFECTS   ? RPS3_NEFFECT - 1
        : scene_keys[k].type == KEY_OUTPUTS ? RPS3_NOUTPUT - 1
        : scene_keys[k].type == KEY_PARAMS  ? RPS3_NPAPER - 1
                                            : (int)scene_keys[k].f->hi;
}

const char *scene_enum_name(int k, int value) {
  int lo, hi;
  name_range(k, &lo, &hi);
  if (value < lo || value > hi) return NULL;
  if (scene_keys[k].type == KEY_EFFECTS) return rps3_effect_name(value);
  if (scene_keys[k].type == KEY_OUTPUTS) return rps3_output_name(value);
  if (scene_keys[k].type == KEY_PARAMS) return rps3_paper_name(value);
  switch (k) {
  case K_KIND: return kind_names[value];
  case K_THETA: return theta_names[value];
  case K_METHOD: return method_names[value];
  case K_BODIES: return bodies_names[value];
  case K_SOLVER: return rps3_solver_name(value);
  case K_WP_LAW:
  case K_PATH_LAW: return rps3_time_law_name(value);
  case K_PATH_SHAPE: return shape_names[value];
  case K_SIM_CONTROLLER: return rps3_ctrl_name(value);
  case K_SIM_INTEGRATOR: return rps3_integrator_name(value);
  case K_ID_METHOD: return ident_method_names[value];
  case K_ID_MODEL: return bodies_names[value];
  case K_ID_LEGS: return ident_legs_names[value];
  default: return NULL;
  }
}

int scene_enum_find(int k, const char *name) {
  int v, lo, hi;
  name_range(k, &lo, &hi);
  for (v = lo; v <= hi; v++) {
    const char *n = scene_enum_name(k, v);
    if (n && strcmp(n, name) == 0) return v;
  }
  return -1;
}

void scene_enum_list(int k, char *buf, size_t sz) {
  int v, lo, hi;
  size_t len = 0;
  const char *last = scene_keys[k].type == KEY_ENUM ? " or " : ", ";
  name_range(k, &lo, &hi);
  buf[0] = '\0';
  for (v = lo; v <= hi && len < sz; v++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s",
                            v == lo ? "" : (v == hi ? last : ", "),
                            scene_enum_name(k, v));
}

void scene_enum_hint(char *buf, size_t sz, int k, const char *word) {
  const char *cand[64];
  int v, lo, hi;
  size_t n = 0;
  name_range(k, &lo, &hi);
  for (v = lo; v <= hi && n < 64; v++) cand[n++] = scene_enum_name(k, v);
  hint_text(buf, sz, word, cand, n);
}

/* -------------------------------------------------------------- values */

/* where key k's value is stored in v (writable when v is, as strchr) */
static char *value_at(const scene_values *v, int k) {
  return (char *)(void *)v + scene_keys[k].f->offset;
}

double *scene_real_at(const scene_values *v, int k) {
  return (double *)(void *)value_at(v, k);
}

int *scene_int_at(const scene_values *v, int k) {
  return (int *)(void *)value_at(v, k);
}

void scene_value_set(scene_values *v, int k, int comp, double x) {
  switch (scene_keys[k].type) {
  case KEY_REAL: *scene_real_at(v, k) = x; break;
  case KEY_REAL3:
  case KEY_REAL6: scene_real_at(v, k)[comp] = x; break;
  default: *scene_int_at(v, k) = (int)x; break;
  }
}

/* the runner's own values are those the library's defaults imply */
void scene_values_default(scene_values *v) {
  int k;
  memset(v, 0, sizeof *v);
  for (k = 0; k < SCENE_NKEY; k++) {
    int src = scene_keys[k].src;
    if ((src == SRC_SIM || src == SRC_IDS) && scene_keys[k].f->is_int)
      *scene_int_at(v, k) = (int)scene_keys[k].def;
    else if (src == SRC_SIM || src == SRC_IDS) /* a list: 0, the rest too */
      *scene_real_at(v, k) = scene_keys[k].def;
  }
  rps3_design_opts_default(&v->des.opts);
  rps3_design_default(&v->design);
  rps3_model_default(&v->model);
  rps3_traj_default(&v->traj);
  v->own.m_over_M = v->model.M > 0 ? v->model.m / v->model.M : 0;
  v->own.blend_ratio = v->traj.helix.blend / v->traj.helix.period;
}

void scene_format_real(char *buf, size_t sz, double x) {
  int prec;
  for (prec = 15; prec <= 17; prec++) {
    snprintf(buf, sz, "%.*g", prec, x);
    if (strtod(buf, NULL) == x) return;
  }
}

/* ---------------------------------------------------------------- errors */

int scene_error_set(scene_error *err, scene_mark mark, const char *path,
                    const char *fmt, ...) {
  va_list ap;
  err->mark = mark;
  snprintf(err->path, sizeof err->path, "%s", path);
  va_start(ap, fmt);
  vsnprintf(err->what, sizeof err->what, fmt, ap);
  va_end(ap);
  return -1;
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

int scene_mark_after(scene_mark a, scene_mark b) {
  return a.line > b.line || (a.line == b.line && a.column > b.column);
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
  table_free(&s->table[TABLE_POSE]);
  table_free(&s->table[TABLE_CENTRE]);
  table_free(&s->table[TABLE_MEASURED]);
  free(s->path_psi);
  free(s->text);
  free(s->file);
  memset(s, 0, sizeof *s);
}
