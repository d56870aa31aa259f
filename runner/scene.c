/*
 * scene.c - parse a scene file with libyaml's document API, expand its
 * sweep, build each case and write it back as YAML.
 *
 * Parsing is table driven: SCENE_KEYS (scene.h) names every leaf key with
 * its type, range and unit.  Each error carries the libyaml mark of the node
 * it is about, so that the runner can print FILE:LINE:COLUMN: key: what.
 */
#include "scene.h"
#include "scene_int.h"
#include "hint.h"
#include "scene_guard.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
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
#define OWN_FILLS(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME,     \
                  FILLS)                                                      \
  FILLS,
static const int own_fills[SCENE_NOWN] = {SCENE_OWN_FIELDS(OWN_FILLS)};
#undef OWN_FILLS

/* the simulate section's fields (scene_sim.h) and their defaults (the key
   table's text for a default that is not a value: scene_emit.c) */
#define SIM_ROW(ID, MEMBER, IS_INT, LO, LO_OPEN, HI, UNIT, DEF, DEFTEXT)      \
  {"simulate." #MEMBER, RPS3_IN_MODEL, offsetof(scene_sim, MEMBER), 1,        \
   IS_INT, LO, LO_OPEN, HI, UNIT},
static const rps3_field_info sim_fields[SCENE_NSIM] = {
    SCENE_SIM_FIELDS(SIM_ROW)};
#undef SIM_ROW
#define SIM_DEF(ID, MEMBER, IS_INT, LO, LO_OPEN, HI, UNIT, DEF, DEFTEXT) DEF,
static const double sim_default[SCENE_NSIM] = {SCENE_SIM_FIELDS(SIM_DEF)};
#undef SIM_DEF

/* the rows as written; keys[] adds what their field's row says */
#define KEY_ROW(ID, PATH, TYPE, SRC, FIELD, REQ, SYM, DOC)                    \
  {PATH, TYPE, SRC_##SRC, FIELD, NULL, 0, REQ, NULL, SYM, DOC},
static const scene_key_info key_rows[SCENE_NKEY] = {SCENE_KEYS(KEY_ROW)};
#undef KEY_ROW
static scene_key_info keys[SCENE_NKEY];

/* complete keys[] from key_rows[] and the field rows, once; called from
   the entry points, before any thread starts */
static void keys_build(void)
{
  static int built;
  int k;
  if (built)
    return;
  for (k = 0; k < SCENE_NKEY; k++) {
    scene_key_info *ki = &keys[k];
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
int scene_shape_mask(int k)
{
  const int line = 1 << RPS3_PATH_LINE, circle = 1 << RPS3_PATH_CIRCLE,
            helix = 1 << RPS3_PATH_HELIX;
  switch (k) {
  case K_PATH_START:
  case K_PATH_END:
    return line;
  case K_PATH_DURATION:
  case K_PATH_LAW:
  case K_PATH_BLEND:
    return line | circle | helix;
  case K_PATH_FILE:
    return 1 << RPS3_PATH_TABLE;
  case K_PATH_CENTRE:
  case K_PATH_RADIUS:
  case K_PATH_TURNS:
  case K_PATH_ANGLE0:
    return circle | helix;
  case K_PATH_PITCH:
    return helix;
  default:
    return 0;
  }
}

/* the library field key k fills, directly or converted (-1: none) */
static int key_fills(int k)
{
  if (keys[k].src == SRC_SIM)
    return -1; /* the controller's model and the simulation: not the plant */
  return keys[k].src == SRC_OWN ? own_fills[keys[k].field] : keys[k].field;
}

/* mapping sections; the index is the slot in scene.section */
static const char *const sections[] = {"", "manipulator", "trajectory",
                                       "solver", "manipulator.payload",
                                       "manipulator.pin_friction",
                                       "trajectory.waypoints",
                                       "trajectory.path", "trajectory.table",
                                       "simulate",
                                       "simulate.model",
                                       "simulate.model.payload",
                                       "simulate.model.pin_friction"};
#define NSECTION (sizeof sections / sizeof sections[0])

/* a value counts as equal to a whole number within this many ulps of its
   size: used for the range expansion and for span / dt */
#define WHOLE_RTOL 1e-9

/* the most cases a sweep may expand to: every case is built and checked
   before a run (about 1 us each: 10 s at the limit); more is several runs */
#define MAX_CASES 10000000.0

const scene_key_info *scene_key_get(int k)
{
  keys_build();
  return (k >= 0 && k < SCENE_NKEY) ? &keys[k] : NULL;
}

int scene_key_find(const char *path)
{
  int k;
  keys_build();
  for (k = 0; k < SCENE_NKEY; k++)
    if (strcmp(keys[k].path, path) == 0)
      return k;
  return -1;
}

static int section_find(const char *path)
{
  size_t i;
  for (i = 1; i < NSECTION; i++)
    if (strcmp(sections[i], path) == 0)
      return (int)i;
  return -1;
}

/* last component of a dotted path */
static const char *leaf(const char *path)
{
  const char *p = strrchr(path, '.');
  return p ? p + 1 : path;
}

/* ---------------------------------------------------------- enum names */

static const char *const kind_names[] = {NULL,        "helix", "sine",
                                         "waypoints", "path",  "table"};
static const char *const shape_names[] = {"line", "circle", "helix",
                                          "table"};
static const char *const theta_names[] = {"closed_form", "multiroot"};
static const char *const method_names[] = {"lagrange", "newton_euler"};

const char *scene_enum_name(int k, int value)
{
  switch (k) {
  case K_KIND:
    return (value >= RPS3_TRAJ_HELIX && value <= RPS3_TRAJ_TABLE)
               ? kind_names[value]
               : NULL;
  case K_THETA:
    return (value == 0 || value == 1) ? theta_names[value] : NULL;
  case K_METHOD:
    return (value == 0 || value == 1) ? method_names[value] : NULL;
  case K_SOLVER:
    return rps3_solver_name(value);
  case K_WP_LAW:
  case K_PATH_LAW:
    return rps3_time_law_name(value);
  case K_PATH_SHAPE:
    return (value >= 0 && value <= RPS3_PATH_TABLE) ? shape_names[value]
                                                    : NULL;
  case K_SIM_CONTROLLER:
    return rps3_ctrl_name(value);
  case K_SIM_INTEGRATOR:
    return rps3_integrator_name(value);
  default:
    return NULL;
  }
}

/* range of enum values of key k: [*lo, *hi] */
static void enum_range(int k, int *lo, int *hi)
{
  /* the library's range of the field */
  *lo = (int)keys[k].f->lo;
  *hi = (int)keys[k].f->hi;
}

static int enum_find(int k, const char *name)
{
  int v, lo, hi;
  enum_range(k, &lo, &hi);
  for (v = lo; v <= hi; v++) {
    const char *n = scene_enum_name(k, v);
    if (n && strcmp(n, name) == 0)
      return v;
  }
  return -1;
}

/* "a, b or c" list of the names of key k into buf */
void scene_enum_list(int k, char *buf, size_t sz)
{
  int v, lo, hi;
  size_t len = 0;
  enum_range(k, &lo, &hi);
  buf[0] = '\0';
  for (v = lo; v <= hi && len < sz; v++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s",
                            v == lo ? "" : (v == hi ? " or " : ", "),
                            scene_enum_name(k, v));
}

static void effect_list(char *buf, size_t sz)
{
  int e;
  size_t len = 0;
  buf[0] = '\0';
  for (e = 0; e < RPS3_NEFFECT && len < sz; e++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s", e ? ", " : "",
                            rps3_effect_name(e));
}

/* -------------------------------------------------------------- values */

/* where key k's value is stored in v */
static char *value_at(scene_values *v, int k)
{
  char *base = keys[k].src == SRC_OWN        ? (char *)&v->own
               : keys[k].src == SRC_SIM       ? (char *)&v->sim
               : keys[k].f->in == RPS3_IN_MODEL ? (char *)&v->model
                                                : (char *)&v->traj;
  return base + keys[k].f->offset;
}

double *scene_real_at(scene_values *v, int k)
{
  return (double *)(void *)value_at(v, k);
}

int *scene_int_at(scene_values *v, int k)
{
  return (int *)(void *)value_at(v, k);
}

double scene_value_real(const scene_values *v, int k, int comp)
{
  double x;
  keys_build();
  memcpy(&x, value_at((scene_values *)(void *)v, k) +
                 (size_t)(comp < 0 ? 0 : comp) * sizeof x,
         sizeof x);
  return x;
}

/* set key k (component comp of a KEY_REAL3) to x */
static void value_set(scene_values *v, int k, int comp, double x)
{
  switch (keys[k].type) {
  case KEY_REAL:
    *scene_real_at(v, k) = x;
    break;
  case KEY_REAL3:
    scene_real_at(v, k)[comp] = x;
    break;
  default:
    *scene_int_at(v, k) = (int)x;
    break;
  }
}

/* defaults: the library's Table II model, options and helix; the runner's
   own values are those the library's defaults imply */
void scene_values_default(scene_values *v)
{
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

/* " (did you mean ...?)" for a mistyped dotted key: every key and section
   is a candidate (a key in the wrong section included); sections only when
   with_sections */
static void key_hint(char *buf, size_t sz, const char *word, int with_sections)
{
  const char *cand[SCENE_NKEY + NSECTION + 1];
  size_t n = 0, i;
  int k;
  for (k = 0; k < SCENE_NKEY; k++)
    cand[n++] = keys[k].path;
  for (i = 1; i < NSECTION && with_sections; i++)
    cand[n++] = sections[i];
  if (with_sections)
    cand[n++] = "sweep";
  hint_text(buf, sz, word, cand, n);
}

/* the same for an enum value of key k */
static void enum_hint(char *buf, size_t sz, int k, const char *word)
{
  const char *cand[64];
  int v, lo, hi;
  size_t n = 0;
  enum_range(k, &lo, &hi);
  for (v = lo; v <= hi && n < 64; v++)
    cand[n++] = scene_enum_name(k, v);
  hint_text(buf, sz, word, cand, n);
}

/* ---------------------------------------------------------------- errors */

static void error_set(scene_error *err, scene_mark mark, const char *path,
                      const char *fmt, ...)
{
  va_list ap;
  err->mark = mark;
  snprintf(err->path, sizeof err->path, "%s", path);
  va_start(ap, fmt);
  vsnprintf(err->what, sizeof err->what, fmt, ap);
  va_end(ap);
}

void scene_error_print(const char *file, const scene_error *err)
{
  if (err->mark.line > 0)
    fprintf(stderr, "%s:%d:%d: %s: %s\n", file, err->mark.line,
            err->mark.column, err->path, err->what);
  else
    fprintf(stderr, "%s: %s: %s\n", file, err->path, err->what);
}

static scene_mark mark_of(const yaml_mark_t *m)
{
  scene_mark r;
  r.line = (int)m->line + 1;
  r.column = (int)m->column + 1;
  return r;
}

/* ---------------------------------------------------------------- parse */

typedef struct {
  yaml_document_t *doc;
  scene *s;
  scene_error *err;
  int sweep_node; /* node id of the sweep mapping, 0 if none */
  double ncase;   /* cases of the sweep keys read so far */
} parse_ctx;

static yaml_node_t *node_get(parse_ctx *c, int id)
{
  return yaml_document_get_node(c->doc, id);
}

static const char *scalar_text(const yaml_node_t *n)
{
  return (const char *)n->data.scalar.value;
}

/* a null scalar: empty plain, "~" or "null" */
static int is_null(const yaml_node_t *n)
{
  const char *t;
  if (n->type != YAML_SCALAR_NODE ||
      n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
    return 0;
  t = scalar_text(n);
  return t[0] == '\0' || strcmp(t, "~") == 0 || strcmp(t, "null") == 0;
}

static const char *node_kind(const yaml_node_t *n)
{
  if (n->type == YAML_MAPPING_NODE)
    return "a mapping";
  if (n->type == YAML_SEQUENCE_NODE)
    return "a list";
  if (is_null(n))
    return "nothing";
  if (n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
    return "a quoted string";
  return "a scalar";
}

/* a plain scalar as a number; 0 or -1 with the error set */
static int parse_number(parse_ctx *c, const yaml_node_t *n, const char *path,
                        int integer, double *out)
{
  const char *t, *p;
  char *end;
  scene_mark mk = mark_of(&n->start_mark);
  if (n->type != YAML_SCALAR_NODE || is_null(n) ||
      n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE) {
    error_set(c->err, mk, path, "expected %s, got %s",
              integer ? "an integer" : "a number", node_kind(n));
    return -1;
  }
  t = scalar_text(n);
  /* only decimal notation: strtod would also take hex, inf and nan */
  for (p = t; *p; p++)
    if (!(isdigit((unsigned char)*p) || *p == '+' || *p == '-' ||
          (!integer && (*p == '.' || *p == 'e' || *p == 'E')))) {
      error_set(c->err, mk, path, "expected %s, got '%s'",
                integer ? "an integer" : "a finite number", t);
      return -1;
    }
  errno = 0;
  *out = integer ? (double)strtol(t, &end, 10) : strtod(t, &end);
  if (end == t || *end != '\0') {
    error_set(c->err, mk, path, "expected %s, got '%s'",
              integer ? "an integer" : "a number", t);
    return -1;
  }
  if (errno == ERANGE || !isfinite(*out)) {
    error_set(c->err, mk, path, "'%s' is out of range", t);
    return -1;
  }
  return 0;
}

/* shortest %g form of x that reads back as x */
void scene_format_real(char *buf, size_t sz, double x)
{
  int prec;
  for (prec = 15; prec <= 17; prec++) {
    snprintf(buf, sz, "%.*g", prec, x);
    if (strtod(buf, NULL) == x)
      return;
  }
}

/* x against the range of key k */
static int check_range(parse_ctx *c, int k, double x, scene_mark mk,
                       const char *path)
{
  const rps3_field_info *f = keys[k].f;
  char lo[32], hi[32], got[32];
  scene_format_real(lo, sizeof lo, f->lo);
  scene_format_real(hi, sizeof hi, f->hi);
  scene_format_real(got, sizeof got, x);
  if (f->lo_open ? !(x > f->lo) : !(x >= f->lo)) {
    error_set(c->err, mk, path, "must be %s %s, got %s",
              f->lo_open ? ">" : ">=", lo, got);
    return -1;
  }
  if (!(x <= f->hi)) {
    error_set(c->err, mk, path, "must be <= %s, got %s", hi, got);
    return -1;
  }
  return 0;
}

/* one scalar value of key k (not a list key) as a number: the value itself,
   an integer, 0/1 for a bool, the enum value for a name */
static int parse_scalar(parse_ctx *c, int k, const yaml_node_t *n,
                        const char *path, double *out)
{
  char list[256];
  scene_mark mk = mark_of(&n->start_mark);
  const char *t;
  int v;
  switch (keys[k].type) {
  case KEY_REAL:
  case KEY_REAL3:
    if (parse_number(c, n, path, 0, out))
      return -1;
    return check_range(c, k, *out, mk, path);
  case KEY_INT:
    if (parse_number(c, n, path, 1, out))
      return -1;
    return check_range(c, k, *out, mk, path);
  case KEY_BOOL:
    if (n->type == YAML_SCALAR_NODE &&
        n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE) {
      t = scalar_text(n);
      if (strcmp(t, "true") == 0 || strcmp(t, "false") == 0) {
        *out = t[0] == 't';
        return 0;
      }
    }
    error_set(c->err, mk, path, "expected true or false, got %s%s%s%s",
              n->type == YAML_SCALAR_NODE ? "'" : "",
              n->type == YAML_SCALAR_NODE ? scalar_text(n) : node_kind(n),
              n->type == YAML_SCALAR_NODE ? "'" : "", "");
    return -1;
  case KEY_ENUM:
    scene_enum_list(k, list, sizeof list);
    if (n->type != YAML_SCALAR_NODE || is_null(n)) {
      error_set(c->err, mk, path, "expected one of %s, got %s", list,
                node_kind(n));
      return -1;
    }
    v = enum_find(k, scalar_text(n));
    if (v < 0) {
      char hint[160];
      enum_hint(hint, sizeof hint, k, scalar_text(n));
      error_set(c->err, mk, path, "unknown value '%s'%s; expected %s",
                scalar_text(n), hint, list);
      return -1;
    }
    *out = v;
    return 0;
  case KEY_EFFECTS:
  default:
    error_set(c->err, mk, path, "not a scalar key");
    return -1;
  }
}

/* the rows of a waypoints list key: times (numbers) or poses (lists of 3
   numbers), into arrays the scene owns; base.traj.wp points to them */
static int parse_rows(parse_ctx *c, int k, const yaml_node_t *n,
                      scene_values *v)
{
  const char *path = keys[k].path;
  int poses = keys[k].type == KEY_POSES;
  scene *s = c->s;
  yaml_node_item_t *it;
  size_t i, rows;
  double *dst;
  scene_mark *marks;
  char sub[160];
  if (n->type != YAML_SEQUENCE_NODE ||
      n->data.sequence.items.top - n->data.sequence.items.start < 2) {
    error_set(c->err, mark_of(&n->start_mark), path,
              "expected a list of at least 2 %s, got %s",
              poses ? "poses [alpha, beta, z_c]" : "numbers",
              n->type == YAML_SEQUENCE_NODE ? "a shorter list" : node_kind(n));
    return -1;
  }
  rows = (size_t)(n->data.sequence.items.top - n->data.sequence.items.start);
  dst = malloc(rows * (poses ? 3 : 1) * sizeof *dst);
  marks = malloc(rows * sizeof *marks);
  if (!dst || !marks) {
    free(dst);
    free(marks);
    error_set(c->err, mark_of(&n->start_mark), path, "out of memory");
    return -1;
  }
  if (poses) {
    s->wp_pose = (double(*)[3])(void *)dst;
    s->wp_npose = rows;
    s->wp_pose_mark = marks;
    v->traj.wp.pose = (const double(*)[3])s->wp_pose;
  } else {
    s->wp_time = dst;
    s->wp_ntime = rows;
    s->wp_time_mark = marks;
    v->traj.wp.time = dst;
  }
  for (i = 0, it = n->data.sequence.items.start; i < rows; i++, it++) {
    const yaml_node_t *item = node_get(c, *it);
    marks[i] = mark_of(&item->start_mark);
    snprintf(sub, sizeof sub, "%s[%zu]", path, i);
    if (!poses) {
      if (parse_number(c, item, sub, 0, &dst[i]) ||
          check_range(c, k, dst[i], marks[i], sub))
        return -1;
      continue;
    }
    if (item->type != YAML_SEQUENCE_NODE ||
        item->data.sequence.items.top - item->data.sequence.items.start != 3) {
      error_set(c->err, marks[i], sub,
                "expected a pose [alpha, beta, z_c], got %s",
                item->type == YAML_SEQUENCE_NODE ? "a list of another length"
                                                 : node_kind(item));
      return -1;
    }
    {
      yaml_node_item_t *jt = item->data.sequence.items.start;
      int j;
      for (j = 0; j < 3; j++, jt++)
        if (parse_number(c, node_get(c, *jt), sub, 0, &dst[3 * i + (size_t)j]))
          return -1;
    }
  }
  return 0;
}

/* a table file: read at once (its rows are checked as they are read), the
   rates it lacks from the spline; base.traj.table views the arrays */
static int parse_file(parse_ctx *c, int k, const yaml_node_t *n,
                      scene_values *v)
{
  scene *s = c->s;
  int path = k == K_PATH_FILE;
  table_data *t = path ? &s->path_table : &s->table;
  char msg[sizeof c->err->what];
  if (n->type != YAML_SCALAR_NODE || is_null(n)) {
    error_set(c->err, mark_of(&n->start_mark), keys[k].path,
              "expected a file name, got %s", node_kind(n));
    return -1;
  }
  if (table_read(t, s->file, scalar_text(n), path ? TABLE_CENTRE : TABLE_POSE,
                 msg, sizeof msg)) {
    error_set(c->err, mark_of(&n->start_mark), keys[k].path, "%s", msg);
    return -1;
  }
  if (!path) {
    v->traj.table = table_view(t);
    v->table_file = t->abs;
    return 0;
  }
  /* a path: the polar angles of the rows, followed continuously */
  s->path_psi = malloc(t->n * sizeof *s->path_psi);
  if (!s->path_psi) {
    error_set(c->err, mark_of(&n->start_mark), keys[k].path, "out of memory");
    return -1;
  }
  rps3_table_unwrap(t->n, (const double(*)[3])t->value, s->path_psi);
  v->traj.path.table = table_view(t);
  v->traj.path.table_psi = s->path_psi;
  v->path_file = t->abs;
  return 0;
}

/* the value node n of key k into v (the whole key, lists included) */
static int parse_value(parse_ctx *c, int k, const yaml_node_t *n,
                       scene_values *v)
{
  const char *path = keys[k].path;
  scene_mark mk = mark_of(&n->start_mark);
  char sub[160], list[256];
  yaml_node_item_t *it;
  double x;
  int i, e, bits;

  if (keys[k].type == KEY_REAL3) {
    if (n->type != YAML_SEQUENCE_NODE ||
        n->data.sequence.items.top - n->data.sequence.items.start != 3) {
      error_set(c->err, mk, path, "expected a list of 3 numbers, got %s",
                n->type == YAML_SEQUENCE_NODE ? "a list of another length"
                                              : node_kind(n));
      return -1;
    }
    for (i = 0, it = n->data.sequence.items.start; i < 3; i++, it++) {
      snprintf(sub, sizeof sub, "%s[%d]", path, i);
      if (parse_scalar(c, k, node_get(c, *it), sub, &x))
        return -1;
      scene_real_at(v, k)[i] = x;
    }
    return 0;
  }
  if (keys[k].type == KEY_TIMES || keys[k].type == KEY_POSES)
    return parse_rows(c, k, n, v);
  if (keys[k].type == KEY_FILE)
    return parse_file(c, k, n, v);
  if (keys[k].type == KEY_EFFECTS) {
    effect_list(list, sizeof list);
    if (n->type != YAML_SEQUENCE_NODE ||
        n->data.sequence.items.top == n->data.sequence.items.start) {
      error_set(c->err, mk, path, "expected a non-empty list of %s, got %s",
                list,
                n->type == YAML_SEQUENCE_NODE ? "an empty list"
                                              : node_kind(n));
      return -1;
    }
    bits = 0;
    for (it = n->data.sequence.items.start; it < n->data.sequence.items.top;
         it++) {
      const yaml_node_t *item = node_get(c, *it);
      scene_mark im = mark_of(&item->start_mark);
      e = (item->type == YAML_SCALAR_NODE && !is_null(item))
              ? rps3_effect_index(scalar_text(item))
              : -1;
      if (e < 0) {
        const char *cand[RPS3_NEFFECT];
        char hint[160] = "";
        int j;
        for (j = 0; j < RPS3_NEFFECT; j++)
          cand[j] = rps3_effect_name(j);
        if (item->type == YAML_SCALAR_NODE)
          hint_text(hint, sizeof hint, scalar_text(item), cand, RPS3_NEFFECT);
        error_set(c->err, im, path, "unknown effect %s%s%s%s; expected %s",
                  item->type == YAML_SCALAR_NODE ? "'" : "",
                  item->type == YAML_SCALAR_NODE ? scalar_text(item)
                                                 : node_kind(item),
                  item->type == YAML_SCALAR_NODE ? "'" : "", hint, list);
        return -1;
      }
      if (bits & (1 << e)) {
        error_set(c->err, im, path, "effect '%s' listed twice",
                  rps3_effect_name(e));
        return -1;
      }
      bits |= 1 << e;
    }
    *scene_int_at(v, k) = bits;
    return 0;
  }
  if (parse_scalar(c, k, n, path, &x))
    return -1;
  value_set(v, k, -1, x);
  return 0;
}

/* "a, b, c" of the keys and sections directly under prefix */
static void keys_under(const char *prefix, char *buf, size_t sz)
{
  size_t plen = strlen(prefix), len = 0, i;
  int k;
  buf[0] = '\0';
  if (plen == 0) {
    snprintf(buf, sz,
             "manipulator, trajectory, effects, solver, simulate, sweep");
    return;
  }
  for (k = 0; k < SCENE_NKEY && len < sz; k++) {
    const char *p = keys[k].path;
    if (strncmp(p, prefix, plen) == 0 && p[plen] == '.' &&
        !strchr(p + plen + 1, '.'))
      len += (size_t)snprintf(buf + len, sz - len, "%s%s", len ? ", " : "",
                              p + plen + 1);
  }
  for (i = 1; i < NSECTION && len < sz; i++) {
    const char *p = sections[i];
    if (strncmp(p, prefix, plen) == 0 && p[plen] == '.' &&
        !strchr(p + plen + 1, '.'))
      len += (size_t)snprintf(buf + len, sz - len, "%s%s", len ? ", " : "",
                              p + plen + 1);
  }
}

/* the keys of a mapping must be plain scalars and appear once */
static int mapping_key(parse_ctx *c, const yaml_node_t *map,
                       const yaml_node_pair_t *pair, const char *prefix,
                       const char **name)
{
  const yaml_node_t *kn = node_get(c, pair->key);
  const yaml_node_pair_t *q;
  scene_mark mk = mark_of(&kn->start_mark);
  if (kn->type != YAML_SCALAR_NODE || is_null(kn)) {
    error_set(c->err, mk, prefix[0] ? prefix : "(root)",
              "a key must be a name, got %s", node_kind(kn));
    return -1;
  }
  *name = scalar_text(kn);
  /* an empty name ("" or "? >") would leave the key path blank in the
     message, naming nothing: say what it is and where it stands */
  if ((*name)[0] == '\0') {
    error_set(c->err, mk, prefix[0] ? prefix : "(root)",
              "a key must be a name, got an empty string");
    return -1;
  }
  for (q = map->data.mapping.pairs.start; q < pair; q++) {
    const yaml_node_t *other = node_get(c, q->key);
    if (other->type == YAML_SCALAR_NODE &&
        strcmp(scalar_text(other), *name) == 0) {
      scene_mark om = mark_of(&other->start_mark);
      char full[160];
      snprintf(full, sizeof full, "%s%s%s", prefix, prefix[0] ? "." : "",
               *name);
      error_set(c->err, mk, full, "duplicate key (first given at %d:%d)",
                om.line, om.column);
      return -1;
    }
  }
  return 0;
}

/* walk a mapping section, storing each key it holds into the base values */
static int walk_section(parse_ctx *c, const yaml_node_t *map,
                        const char *prefix)
{
  yaml_node_pair_t *pair;
  char full[160], list[512];
  scene *s = c->s;
  for (pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top;
       pair++) {
    const char *name;
    const yaml_node_t *val = node_get(c, pair->value);
    int k, sec;
    if (mapping_key(c, map, pair, prefix, &name))
      return -1;
    snprintf(full, sizeof full, "%s%s%s", prefix, prefix[0] ? "." : "",
             name);
    if (prefix[0] == '\0' && strcmp(name, "sweep") == 0) {
      c->sweep_node = pair->value;
      continue;
    }
    sec = section_find(full);
    if (sec > 0) {
      if (val->type != YAML_MAPPING_NODE) {
        error_set(c->err, mark_of(&val->start_mark), full,
                  "expected a mapping of keys, got %s", node_kind(val));
        return -1;
      }
      if (sec < 4)
        s->section[sec] = mark_of(&val->start_mark);
      if (strcmp(full, "simulate") == 0)
        s->simulate = mark_of(&val->start_mark);
      if (walk_section(c, val, full))
        return -1;
      continue;
    }
    k = scene_key_find(full);
    if (k < 0) {
      char hint[200];
      key_hint(hint, sizeof hint, full, 1);
      keys_under(prefix, list, sizeof list);
      error_set(c->err, mark_of(&node_get(c, pair->key)->start_mark), full,
                "unknown key%s; expected one of %s", hint, list);
      return -1;
    }
    if (parse_value(c, k, val, &s->base))
      return -1;
    s->given[k] = 1;
    s->mark[k] = mark_of(&val->start_mark);
  }
  return 0;
}

/* ---------------------------------------------------------------- sweep */

/* one value of a {from, to, ...} range mapping, or NULL */
static const yaml_node_t *range_get(parse_ctx *c, const yaml_node_t *map,
                                    const char *name)
{
  yaml_node_pair_t *p;
  for (p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top;
       p++) {
    const yaml_node_t *kn = node_get(c, p->key);
    if (kn->type == YAML_SCALAR_NODE && strcmp(scalar_text(kn), name) == 0)
      return node_get(c, p->value);
  }
  return NULL;
}

/* expand a {from, to, num} or {from, to, step} mapping into ax */
static int sweep_range(parse_ctx *c, scene_axis *ax, const yaml_node_t *map)
{
  const scene_key_info *ki = &keys[ax->key];
  scene_mark mk = mark_of(&map->start_mark);
  const yaml_node_t *nf, *nt, *nn, *ns;
  yaml_node_pair_t *p;
  double from, to, num = 0, step = 0, span;
  int integer = ki->type == KEY_INT;
  size_t i, n;
  char sub[160];

  if (ki->type != KEY_REAL && ki->type != KEY_REAL3 && !integer) {
    error_set(c->err, mk, ax->path,
              "a range needs a numeric key; give a list of values");
    return -1;
  }
  for (p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top;
       p++) {
    const char *name;
    if (mapping_key(c, map, p, ax->path, &name))
      return -1;
    if (strcmp(name, "from") && strcmp(name, "to") && strcmp(name, "num") &&
        strcmp(name, "step")) {
      snprintf(sub, sizeof sub, "%s.%s", ax->path, name);
      error_set(c->err, mark_of(&node_get(c, p->key)->start_mark), sub,
                "unknown key; expected from, to and num or step");
      return -1;
    }
  }
  nf = range_get(c, map, "from");
  nt = range_get(c, map, "to");
  nn = range_get(c, map, "num");
  ns = range_get(c, map, "step");
  if (!nf || !nt || (!nn == !ns)) {
    error_set(c->err, mk, ax->path,
              "a range needs from, to and exactly one of num and step");
    return -1;
  }
  snprintf(sub, sizeof sub, "%s.from", ax->path);
  if (parse_number(c, nf, sub, integer, &from))
    return -1;
  snprintf(sub, sizeof sub, "%s.to", ax->path);
  if (parse_number(c, nt, sub, integer, &to))
    return -1;
  span = to - from;
  if (nn) {
    snprintf(sub, sizeof sub, "%s.num", ax->path);
    if (parse_number(c, nn, sub, 1, &num))
      return -1;
    if (num < 1 || (num == 1 && from != to)) {
      error_set(c->err, mark_of(&nn->start_mark), sub,
                "must be >= 2 (or 1 with from == to), got %.0f", num);
      return -1;
    }
    /* counted before anything is allocated for the values */
    if (num * c->ncase > MAX_CASES) {
      error_set(c->err, mark_of(&nn->start_mark), sub,
                "%.0f values make the sweep more than %.0f cases", num,
                MAX_CASES);
      return -1;
    }
    n = (size_t)num;
  } else {
    double q;
    snprintf(sub, sizeof sub, "%s.step", ax->path);
    if (parse_number(c, ns, sub, integer, &step))
      return -1;
    q = span / step;
    if (step == 0 || q < 0) {
      error_set(c->err, mark_of(&ns->start_mark), sub,
                "must be non-zero with the sign of to - from, got %s",
                scalar_text(ns));
      return -1;
    }
    if (!(span - span == 0)) {
      error_set(c->err, mark_of(&ns->start_mark), sub,
                "to - from overflows (%s to %s): not a range of numbers",
                scalar_text(nf), scalar_text(nt));
      return -1;
    }
    if ((q + 1) * c->ncase > MAX_CASES) {
      error_set(c->err, mark_of(&ns->start_mark), sub,
                "gives %.3g values: the sweep would have more than %.0f "
                "cases",
                q + 1, MAX_CASES);
      return -1;
    }
    n = (size_t)floor(q + WHOLE_RTOL) + 1;
  }
  ax->n = n;
  ax->val = malloc(n * sizeof *ax->val);
  ax->mark = malloc(n * sizeof *ax->mark);
  if (!ax->val || !ax->mark) {
    error_set(c->err, mk, ax->path, "out of memory for %zu values", n);
    return -1;
  }
  for (i = 0; i < n; i++) {
    double x;
    if (nn && !(span - span == 0))
      /* to - from overflows ({from: -1e308, to: 1e308}): weights instead,
         so that each value is a number and its range check speaks */
      x = (i + 1 == n) ? to
                       : from * (1 - (double)i / (double)(n - 1)) +
                             to * ((double)i / (double)(n - 1));
    else if (nn)
      x = (i + 1 == n) ? to : from + span * (double)i / (double)(n - 1);
    else
      x = from + (double)i * step;
    /* the last step lands on `to` up to rounding: take `to` itself */
    if (!nn && i + 1 == n && fabs(x - to) <= WHOLE_RTOL * fabs(step))
      x = to;
    if (integer && x != floor(x)) {
      error_set(c->err, mk, ax->path,
                "value %zu of the range, %g, is not an integer", i, x);
      return -1;
    }
    if (check_range(c, ax->key, x, mk, ax->path))
      return -1;
    ax->val[i] = x;
    ax->mark[i] = mk;
  }
  return 0;
}

/* parse the sweep mapping into s->axis */
static int parse_sweep(parse_ctx *c, const yaml_node_t *map)
{
  scene *s = c->s;
  yaml_node_pair_t *pair;
  size_t a, npair;
  double ncase = 1;

  if (map->type != YAML_MAPPING_NODE ||
      map->data.mapping.pairs.top == map->data.mapping.pairs.start) {
    error_set(c->err, mark_of(&map->start_mark), "sweep",
              "expected a mapping of dotted keys to values, got %s",
              map->type == YAML_MAPPING_NODE ? "an empty mapping"
                                             : node_kind(map));
    return -1;
  }
  npair = (size_t)(map->data.mapping.pairs.top - map->data.mapping.pairs.start);
  s->axis = calloc(npair, sizeof *s->axis);
  if (!s->axis) {
    error_set(c->err, mark_of(&map->start_mark), "sweep", "out of memory");
    return -1;
  }
  for (pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top;
       pair++) {
    const yaml_node_t *kn = node_get(c, pair->key);
    const yaml_node_t *val = node_get(c, pair->value);
    scene_mark km = mark_of(&kn->start_mark);
    /* counted at once, so that scene_free frees a half-built axis */
    scene_axis *ax = &s->axis[s->naxis++];
    const scene_key_info *ki;
    const char *name, *br;
    char base[80];
    if (mapping_key(c, map, pair, "sweep", &name))
      return -1;
    if (strlen(name) >= sizeof ax->path) {
      error_set(c->err, km, "sweep", "key '%.40s...' is too long", name);
      return -1;
    }
    snprintf(ax->path, sizeof ax->path, "%s", name);
    ax->comp = -1;
    /* "key[k]" picks component k of a list key */
    br = strchr(name, '[');
    snprintf(base, sizeof base, "%.*s",
             (int)(br ? (size_t)(br - name) : strlen(name)), name);
    ax->key = scene_key_find(base);
    if (ax->key < 0) {
      char hint[200];
      key_hint(hint, sizeof hint, base, 0);
      error_set(c->err, km, name, "not a scene key%s; see rps3-run --keys",
                hint);
      return -1;
    }
    ki = &keys[ax->key];
    if (br) {
      if (ki->type != KEY_REAL3 || !(br[1] >= '0' && br[1] <= '2') ||
          strcmp(br + 2, "]") != 0) {
        error_set(c->err, km, name,
                  ki->type == KEY_REAL3
                      ? "component must be [0], [1] or [2]"
                      : "only a list key takes a component [k]");
        return -1;
      }
      ax->comp = br[1] - '0';
    } else if (ki->type == KEY_REAL3) {
      error_set(c->err, km, name,
                "a list key: sweep one component, as %s[0], [1] or [2]",
                name);
      return -1;
    }
    if (ki->type == KEY_EFFECTS || ki->type == KEY_TIMES ||
        ki->type == KEY_POSES || ki->type == KEY_FILE || ax->key == K_KIND ||
        ax->key == K_PATH_SHAPE) {
      error_set(c->err, km, name,
                "cannot be swept (it decides what a case computes); write "
                "one scene per value");
      return -1;
    }
    if (ki->kind != FOR_ALL && ki->kind != (int)s->base.traj.kind) {
      error_set(c->err, km, name, "not a key of a %s trajectory",
                kind_names[s->base.traj.kind]);
      return -1;
    }
    for (a = 0; a + 1 < s->naxis; a++)
      if (s->axis[a].key == ax->key && s->axis[a].comp == ax->comp) {
        error_set(c->err, km, name, "swept twice (also as %s)",
                  s->axis[a].path);
        return -1;
      }
    if (val->type == YAML_SEQUENCE_NODE) {
      yaml_node_item_t *it;
      size_t i, n = (size_t)(val->data.sequence.items.top -
                             val->data.sequence.items.start);
      if (n == 0) {
        error_set(c->err, mark_of(&val->start_mark), name,
                  "empty list of values");
        return -1;
      }
      ax->n = n;
      ax->val = malloc(n * sizeof *ax->val);
      ax->mark = malloc(n * sizeof *ax->mark);
      if (!ax->val || !ax->mark) {
        error_set(c->err, km, name, "out of memory");
        return -1;
      }
      for (i = 0, it = val->data.sequence.items.start; i < n; i++, it++) {
        const yaml_node_t *item = node_get(c, *it);
        if (parse_scalar(c, ax->key, item, name, &ax->val[i]))
          return -1;
        ax->mark[i] = mark_of(&item->start_mark);
      }
    } else if (val->type == YAML_MAPPING_NODE) {
      if (sweep_range(c, ax, val))
        return -1;
    } else {
      error_set(c->err, mark_of(&val->start_mark), name,
                "expected a list of values, {from, to, num} or "
                "{from, to, step}, got %s",
                node_kind(val));
      return -1;
    }
    ncase *= (double)ax->n;
    c->ncase = ncase;
    if (ncase > MAX_CASES) {
      error_set(c->err, km, name, "the sweep has more than %.0f cases",
                MAX_CASES);
      return -1;
    }
    /* a swept key counts as given; its mark is its first value */
    s->given[ax->key] = 1;
    if (s->mark[ax->key].line == 0)
      s->mark[ax->key] = ax->mark[0];
  }
  s->ncase = (size_t)ncase;
  return 0;
}

/* a waypoints scene has as many poses as times */
static int check_waypoints(parse_ctx *c)
{
  scene *s = c->s;
  if (s->base.traj.kind != RPS3_TRAJ_WAYPOINTS)
    return 0;
  if (s->wp_ntime != s->wp_npose) {
    error_set(c->err, s->mark[K_WP_POSES], keys[K_WP_POSES].path,
              "%zu poses for %zu times (trajectory.waypoints.times at "
              "%d:%d); give one pose per time",
              s->wp_npose, s->wp_ntime, s->mark[K_WP_TIMES].line,
              s->mark[K_WP_TIMES].column);
    return -1;
  }
  s->base.traj.wp.n = s->wp_ntime;
  return 0;
}

/* a path scene gives the keys of its shape, and no others */
static int check_shape(parse_ctx *c)
{
  scene *s = c->s;
  int k, shape = (int)s->base.traj.path.shape;
  if (s->base.traj.kind != RPS3_TRAJ_PATH)
    return 0;
  for (k = 0; k < SCENE_NKEY; k++) {
    int mask = scene_shape_mask(k);
    if (mask == 0)
      continue;
    if (s->given[k] && !(mask & (1 << shape))) {
      error_set(c->err, s->mark[k], keys[k].path, "not a key of a %s path",
                shape_names[shape]);
      return -1;
    }
    if (!s->given[k] && keys[k].req == REQ_SHAPE && (mask & (1 << shape))) {
      error_set(c->err, s->mark[K_PATH_SHAPE], keys[k].path,
                "missing required key of a %s path", shape_names[shape]);
      return -1;
    }
  }
  return 0;
}

/* required keys, keys of the other trajectory kind, one-of pairs */
static int check_keys(parse_ctx *c)
{
  scene *s = c->s;
  int k, pair;
  if (s->section[1].line == 0 || s->section[2].line == 0) {
    error_set(c->err, s->section[0],
              s->section[1].line == 0 ? "manipulator" : "trajectory",
              "missing required section");
    return -1;
  }
  for (k = 0; k < SCENE_NKEY; k++) {
    const scene_key_info *ki = &keys[k];
    int applies = ki->kind == FOR_ALL || ki->kind == (int)s->base.traj.kind;
    int sec = strncmp(ki->path, "manipulator", 11) == 0 ? 1 : 2;
    if (!applies && s->given[k]) {
      error_set(c->err, s->mark[k], ki->path, "not a key of a %s trajectory",
                kind_names[s->base.traj.kind]);
      return -1;
    }
    if (applies && ki->req == REQ_YES && !s->given[k]) {
      error_set(c->err, s->section[sec], ki->path, "missing required key");
      return -1;
    }
  }
  if (check_waypoints(c) || check_shape(c))
    return -1;
  for (pair = 0; pair < 3; pair++) {
    static const int one_of[3][2] = {
        {K_M_OVER_M, K_MASS}, {K_SAMPLES, K_DT}, {K_BLEND, K_BLEND_RATIO}};
    int a = one_of[pair][0], b = one_of[pair][1];
    if (keys[a].kind != FOR_ALL && keys[a].kind != (int)s->base.traj.kind)
      continue;
    if (!s->given[a] && !s->given[b]) {
      error_set(c->err, s->section[pair ? 2 : 1], keys[a].path,
                "missing: give %s or %s", leaf(keys[a].path),
                leaf(keys[b].path));
      return -1;
    }
    if (s->given[a] && s->given[b]) {
      int later = (s->mark[a].line > s->mark[b].line ||
                   (s->mark[a].line == s->mark[b].line &&
                    s->mark[a].column > s->mark[b].column))
                      ? a
                      : b;
      int other = later == a ? b : a;
      error_set(c->err, s->mark[later], keys[later].path,
                "give either %s or %s, not both (%s is at %d:%d)",
                leaf(keys[a].path), leaf(keys[b].path), keys[other].path,
                s->mark[other].line, s->mark[other].column);
      return -1;
    }
  }
  return 0;
}

/* the file, checked before libyaml sees it (scene_guard.h) */
static int read_file(scene *s, const char *path, scene_error *err)
{
  if (scene_read_guarded(path, &s->text, &s->text_len, err))
    return -1;
  return scene_text_guard(s->text, s->text_len, err);
}

int scene_load(scene *s, const char *path, scene_error *err)
{
  yaml_parser_t parser;
  yaml_document_t doc, extra;
  yaml_node_t *root;
  parse_ctx c;
  int rc = -1;

  keys_build();
  memset(s, 0, sizeof *s);
  memset(err, 0, sizeof *err);
  scene_values_default(&s->base);
  s->ncase = 1;
  s->file = malloc(strlen(path) + 1);
  if (!s->file) {
    error_set(err, s->section[0], "(file)", "out of memory");
    return -1;
  }
  strcpy(s->file, path);
  if (read_file(s, path, err))
    goto fail;

  if (!yaml_parser_initialize(&parser)) {
    error_set(err, s->section[0], "yaml", "cannot initialise libyaml");
    goto fail;
  }
  yaml_parser_set_input_string(&parser, (const unsigned char *)s->text,
                               s->text_len);
  if (!yaml_parser_load(&parser, &doc)) {
    error_set(err, mark_of(&parser.problem_mark), "yaml", "%s%s%s",
              parser.problem ? parser.problem : "syntax error",
              parser.context ? " " : "", parser.context ? parser.context : "");
    yaml_parser_delete(&parser);
    goto fail;
  }
  root = yaml_document_get_root_node(&doc);
  memset(&c, 0, sizeof c);
  c.ncase = 1;
  c.doc = &doc;
  c.s = s;
  c.err = err;
  s->section[0].line = 1;
  s->section[0].column = 1;
  if (!root) {
    error_set(err, s->section[0], "(root)", "empty scene");
  } else if (root->type != YAML_MAPPING_NODE) {
    error_set(err, mark_of(&root->start_mark), "(root)",
              "expected a mapping of sections, got %s", node_kind(root));
  } else {
    /* a second document would be silently ignored: refuse it */
    if (!yaml_parser_load(&parser, &extra)) {
      error_set(err, mark_of(&parser.problem_mark), "yaml", "%s",
                parser.problem ? parser.problem : "syntax error");
    } else {
      yaml_node_t *r2 = yaml_document_get_root_node(&extra);
      if (r2)
        error_set(err, mark_of(&r2->start_mark), "(root)",
                  "a second YAML document; a scene is one document");
      else {
        s->section[0] = mark_of(&root->start_mark);
        if (walk_section(&c, root, "") == 0 &&
            (c.sweep_node == 0 ||
             parse_sweep(&c, node_get(&c, c.sweep_node)) == 0) &&
            check_keys(&c) == 0)
          rc = 0;
      }
      yaml_document_delete(&extra);
    }
  }
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  if (rc == 0)
    return 0;
fail:
  scene_free(s);
  return -1;
}

void scene_free(scene *s)
{
  size_t a;
  if (!s)
    return;
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

/* ----------------------------------------------------------------- cases */

size_t scene_case_coord(const scene *s, size_t index, size_t a)
{
  size_t b;
  /* row-major: the last axis varies fastest */
  for (b = s->naxis; b-- > a + 1;)
    index /= s->axis[b].n;
  return index % s->axis[a].n;
}

/* the keys that set library field id in scene s (a converted key such as
   m_over_M when the scene gave it): up to max into out */
static int keys_filling(const scene *s, int id, int *out, int max)
{
  int k, n = 0;
  for (k = 0; k < SCENE_NKEY && n < max; k++)
    if (id >= 0 && key_fills(k) == id && s->given[k])
      out[n++] = k;
  return n;
}

/* where to point an error about case `index`: a swept value of a key that
   sets one of the fields the failed rule reads (the failing field first,
   then the related ones; a list key's axis when it is the failing
   component or the whole key), else such a key given in the file, else the
   first swept value, else the manipulator section */
static void case_error(const scene *s, size_t index, const char *msg,
                       const rps3_check *chk, int first_key, scene_error *err)
{
  int named[16], comp[16], n = 0, i, j, m;
  size_t a;
  char what[sizeof err->what];
  if (s->naxis > 0)
    snprintf(what, sizeof what, "case %zu: %s", index, msg);
  else
    snprintf(what, sizeof what, "%s", msg);
  if (first_key >= 0) {
    comp[n] = -1;
    named[n++] = first_key;
  }
  if (chk != NULL) {
    int ids[3];
    ids[0] = chk->field;
    ids[1] = chk->related[0];
    ids[2] = chk->related[1];
    for (j = 0; j < 3; j++) {
      m = keys_filling(s, ids[j], named + n, 16 - n);
      for (i = n; i < n + m; i++)
        comp[i] = j == 0 ? chk->comp : -1;
      n += m;
    }
  }
  /* a waypoint row: point at the row itself */
  if (chk != NULL && chk->comp >= 0 &&
      ((chk->field == RPS3_F_WP_TIME && (size_t)chk->comp < s->wp_ntime) ||
       (chk->field == RPS3_F_WP_POSE && (size_t)chk->comp < s->wp_npose))) {
    int key = chk->field == RPS3_F_WP_TIME ? K_WP_TIMES : K_WP_POSES;
    char row[96];
    snprintf(row, sizeof row, "%s[%d]", keys[key].path, chk->comp);
    error_set(err,
              chk->field == RPS3_F_WP_TIME ? s->wp_time_mark[chk->comp]
                                           : s->wp_pose_mark[chk->comp],
              row, "%s", what);
    return;
  }
  /* a table row: point at the file key, and name the file's line */
  for (j = 0; j < 2 && chk != NULL && chk->comp >= 0; j++) {
    int lo = j ? RPS3_F_PATH_TABLE_TIME : RPS3_F_TABLE_TIME;
    int key = j ? K_PATH_FILE : K_TABLE_FILE;
    const table_data *t = j ? &s->path_table : &s->table;
    char where[300];
    if (chk->field < lo || chk->field > lo + 3 || (size_t)chk->comp >= t->n)
      continue;
    table_where(t, (size_t)chk->comp, where, sizeof where);
    error_set(err, s->mark[key], keys[key].path, "%s: %s", where, what);
    return;
  }
  for (i = 0; i < n; i++)
    for (a = 0; a < s->naxis; a++)
      if (s->axis[a].key == named[i] &&
          (s->axis[a].comp < 0 || comp[i] < 0 || s->axis[a].comp == comp[i])) {
        error_set(err, s->axis[a].mark[scene_case_coord(s, index, a)],
                  s->axis[a].path, "%s", what);
        return;
      }
  for (i = 0; i < n; i++)
    if (s->given[named[i]]) {
      error_set(err, s->mark[named[i]], keys[named[i]].path, "%s", what);
      return;
    }
  if (s->naxis > 0) {
    error_set(err, s->axis[0].mark[scene_case_coord(s, index, 0)],
              s->axis[0].path, "%s", what);
    return;
  }
  error_set(err, s->section[1], "manipulator", "%s", what);
}

/*
 * The rule for configured effects.  A payload (mass or a moment of inertia
 * above 0) or pin friction (a coefficient above 0) is configured in the
 * manipulator section; the effects list selects what is computed.  An
 * omitted list selects the paper's four effects plus whatever is
 * configured.  An explicit list that leaves out a configured payload or
 * friction would silently drop it: refused, naming both keys.  Returns 0,
 * or -1 with err set.
 */
static int effects_rule(const scene *s, size_t index, scene_case *c,
                        scene_error *err)
{
  const rps3_model *m = &c->model;
  int pay = m->payload.mass > 0 || m->payload.inertia[0] > 0 ||
            m->payload.inertia[1] > 0 || m->payload.inertia[2] > 0;
  int fric = m->friction.viscous > 0 || m->friction.coulomb > 0;
  int eff = m->opt.effects, j;
  char msg[256];
  if (!s->given[K_EFFECTS]) {
    eff = RPS3_EFF_DEFAULT | (pay ? RPS3_EFF_PAYLOAD : 0) |
          (fric ? RPS3_EFF_PIN_FRICTION : 0);
    c->model.opt.effects = c->v.model.opt.effects = eff;
    return 0;
  }
  for (j = 0; j < 2; j++) {
    int bit = j ? RPS3_EFF_PIN_FRICTION : RPS3_EFF_PAYLOAD;
    /* the key that configures it (every default is 0, so it is given) */
    int k = j ? (m->friction.viscous > 0 ? K_VISCOUS : K_COULOMB)
              : (m->payload.mass > 0 ? K_PAY_MASS : K_PAY_INERTIA);
    if (!(j ? fric : pay) || (eff & bit))
      continue;
    snprintf(msg, sizeof msg,
             "leaves out %s, but %s is configured (%d:%d); add %s to the "
             "list, or remove the %s",
             j ? "pin_friction" : "payload", keys[k].path, s->mark[k].line,
             s->mark[k].column, j ? "pin_friction" : "payload",
             j ? "friction" : "payload");
    case_error(s, index, msg, NULL, K_EFFECTS, err);
    return -1;
  }
  return 0;
}

int scene_case_build(const scene *s, size_t index, scene_case *c,
                     scene_error *err)
{
  rps3_check chk;
  char msg[256];
  size_t a;
  memset(c, 0, sizeof *c);
  c->index = index;
  c->by_ratio = s->given[K_M_OVER_M];
  c->by_dt = s->given[K_DT];
  c->by_blend_ratio = s->given[K_BLEND_RATIO];
  c->simulate = s->simulate.line > 0;
  c->v = s->base;
  for (a = 0; a < s->naxis; a++)
    value_set(&c->v, s->axis[a].key, s->axis[a].comp,
              s->axis[a].val[scene_case_coord(s, index, a)]);
  /* the values are the library's structures; only the runner's own keys
     are converted */
  c->model = c->v.model;
  c->traj = c->v.traj;
  if (c->by_ratio)
    c->model.m = c->v.own.m_over_M * c->model.M;
  if (c->by_blend_ratio)
    c->traj.helix.blend = c->v.own.blend_ratio * c->traj.helix.period;
  if (effects_rule(s, index, c, err))
    return -1;

  if (rps3_model_validate(&c->model, &chk) != RPS3_OK ||
      rps3_traj_validate(&c->model, &c->traj, &chk) != RPS3_OK) {
    case_error(s, index, chk.msg, &chk, -1, err);
    return -1;
  }
  c->span = rps3_traj_duration(&c->traj);
  if (s->given[K_SAMPLES]) {
    c->nt = (size_t)c->v.own.samples;
    c->step = c->span / (double)(c->nt - 1);
  } else {
    double q = c->span / c->v.own.dt, n = floor(q + 0.5);
    if (q >= 2147483646.0) {
      char sa[32], sb[32];
      scene_format_real(sa, sizeof sa, c->span);
      scene_format_real(sb, sizeof sb, c->v.own.dt);
      snprintf(msg, sizeof msg,
               "dt = %s s over the span %s s is %.6g steps: at most "
               "2147483646 samples per case",
               sb, sa, q);
      case_error(s, index, msg, NULL, K_DT, err);
      return -1;
    }
    if (fabs(q - n) > WHOLE_RTOL * (q > 1 ? q : 1) || n < 1) {
      char sa[32], sb[32];
      scene_format_real(sa, sizeof sa, c->span);
      scene_format_real(sb, sizeof sb, c->v.own.dt);
      snprintf(msg, sizeof msg,
               "the span %s s is not a whole number of steps dt = %s s "
               "(%.6g steps)",
               sa, sb, q);
      case_error(s, index, msg, NULL, K_DT, err);
      return -1;
    }
    c->nt = (size_t)n + 1;
    c->step = c->v.own.dt;
  }
  return 0;
}

double scene_case_time(const scene_case *c, size_t k)
{
  if (k + 1 >= c->nt)
    return c->span;
  if (c->by_dt)
    return (double)k * c->step;
  return c->span * (double)k / (double)(c->nt - 1);
}

int scene_case_same_grid(const scene_case *a, const scene_case *b)
{
  return a->nt == b->nt && a->span == b->span && a->step == b->step;
}
