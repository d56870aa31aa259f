/*
 * scene_parse.c - read the YAML nodes of a scene: each section's keys, each
 * key's value against its row of the key table (scene.c), with the libyaml
 * mark of the node an error is about; and the checks, after the whole file
 * and its sweep (scene_sweep.c) are read, of the keys it gives (required, of
 * its kind, shape and bodies, one of a pair).
 */
#include "core/hint.h"
#include "scene.h"
#include "scene_int.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* ---------------------------------------------------------------- parse */

/* the sections are the dotted prefixes of the key table's paths: a key
   added to the table brings its section */

/* the most sections, and the longest section path */
#define NSECTION (2 * SCENE_NKEY)
#define SECTION_LEN 80

/* 1 when path is a section: some key's path goes on under it */
static int is_section(const char *path) {
  size_t len = strlen(path);
  int k;
  for (k = 0; k < SCENE_NKEY; k++)
    if (strncmp(scene_keys[k].path, path, len) == 0 &&
        scene_keys[k].path[len] == '.')
      return 1;
  return 0;
}

/* the names directly under prefix ("" the root), each once, in the order
   of the key table; with sub, "b" of a key a.b.c becomes "a.b" (the
   sections), else only the names of keys count.  Their number. */
static size_t names_under(const char *prefix, int sub,
                          char (*name)[SECTION_LEN], size_t max) {
  size_t plen = strlen(prefix), n = 0, i;
  int k;
  for (k = 0; k < SCENE_NKEY && n < max; k++) {
    const char *p = scene_keys[k].path, *rest, *dot;
    size_t len;
    if (plen && (strncmp(p, prefix, plen) != 0 || p[plen] != '.')) continue;
    rest = plen ? p + plen + 1 : p;
    dot = strchr(rest, '.');
    if (sub != (dot != NULL)) continue;
    len = dot ? (size_t)(dot - p) : strlen(p);
    for (i = 0; i < n; i++)
      if (strncmp(name[i], p, len) == 0 && name[i][len] == '\0') break;
    if (i < n) continue;
    snprintf(name[n++], SECTION_LEN, "%.*s", (int)len, p);
  }
  return n;
}

void scene_key_hint(char *buf, size_t sz, const char *word, int with_sections) {
  const char *cand[SCENE_NKEY + NSECTION + 1];
  char sec[NSECTION][SECTION_LEN];
  size_t n = 0, nsec = 0, i;
  int k;
  for (k = 0; k < SCENE_NKEY; k++) cand[n++] = scene_keys[k].path;
  /* the sections by depth: those under the root, then under each of them */
  for (i = 0; with_sections && i <= nsec && nsec < NSECTION; i++)
    nsec += names_under(i ? sec[i - 1] : "", 1, sec + nsec, NSECTION - nsec);
  for (i = 0; i < nsec; i++) cand[n++] = sec[i];
  if (with_sections) cand[n++] = "sweep";
  hint_text(buf, sz, word, cand, n);
}

/* "a, b, c" of the keys and sections directly under prefix */
static void keys_under(const char *prefix, char *buf, size_t sz) {
  char name[NSECTION][SECTION_LEN];
  size_t n = names_under(prefix, 0, name, NSECTION), len = 0, i, plen;
  n += names_under(prefix, 1, name + n, NSECTION - n);
  plen = prefix[0] ? strlen(prefix) + 1 : 0;
  buf[0] = '\0';
  for (i = 0; i < n && len < sz; i++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%s", len ? ", " : "",
                            name[i] + plen);
  if (!prefix[0] && len < sz) snprintf(buf + len, sz - len, ", sweep");
}

yaml_node_t *scene_node_get(scene_parse_ctx *c, int id) {
  return yaml_document_get_node(c->doc, id);
}

const char *scene_scalar_text(const yaml_node_t *n) {
  return (const char *)n->data.scalar.value;
}

/* a null scalar: empty plain, "~" or "null" */
static int is_null(const yaml_node_t *n) {
  const char *t;
  if (n->type != YAML_SCALAR_NODE ||
      n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
    return 0;
  t = scene_scalar_text(n);
  return t[0] == '\0' || strcmp(t, "~") == 0 || strcmp(t, "null") == 0;
}

const char *scene_node_kind(const yaml_node_t *n) {
  if (n->type == YAML_MAPPING_NODE) return "a mapping";
  if (n->type == YAML_SEQUENCE_NODE) return "a list";
  if (is_null(n)) return "nothing";
  if (n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE) return "a quoted string";
  return "a scalar";
}

int scene_parse_number(scene_parse_ctx *c, const yaml_node_t *n,
                       const char *path, int integer, double *out) {
  const char *t, *p;
  char *end;
  scene_mark mk = scene_mark_of(&n->start_mark);
  if (n->type != YAML_SCALAR_NODE || is_null(n) ||
      n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
    return scene_error_set(c->err, mk, path, "expected %s, got %s",
                           integer ? "an integer" : "a number",
                           scene_node_kind(n));
  t = scene_scalar_text(n);
  /* only decimal notation: strtod would also take hex, inf and nan */
  for (p = t; *p; p++)
    if (!(isdigit((unsigned char)*p) || *p == '+' || *p == '-' ||
          (!integer && (*p == '.' || *p == 'e' || *p == 'E'))))
      return scene_error_set(c->err, mk, path, "expected %s, got '%s'",
                             integer ? "an integer" : "a finite number", t);
  errno = 0;
  *out = integer ? (double)strtol(t, &end, 10) : strtod(t, &end);
  if (end == t || *end != '\0')
    return scene_error_set(c->err, mk, path, "expected %s, got '%s'",
                           integer ? "an integer" : "a number", t);
  if (errno == ERANGE || !isfinite(*out))
    return scene_error_set(c->err, mk, path, "'%s' is out of range", t);
  return 0;
}

int scene_check_range(scene_parse_ctx *c, int k, double x, scene_mark mk,
                      const char *path) {
  const rps3_field_info *f = scene_keys[k].f;
  char lo[32], hi[32], got[32];
  scene_format_real(lo, sizeof lo, f->lo);
  scene_format_real(hi, sizeof hi, f->hi);
  scene_format_real(got, sizeof got, x);
  if (f->lo_open ? !(x > f->lo) : !(x >= f->lo))
    return scene_error_set(c->err, mk, path, "must be %s %s, got %s",
                           f->lo_open ? ">" : ">=", lo, got);
  if (!(x <= f->hi))
    return scene_error_set(c->err, mk, path, "must be <= %s, got %s", hi, got);
  return 0;
}

int scene_parse_scalar(scene_parse_ctx *c, int k, const yaml_node_t *n,
                       const char *path, double *out) {
  char list[256], hint[160];
  scene_mark mk = scene_mark_of(&n->start_mark);
  int scalar = n->type == YAML_SCALAR_NODE, v;
  const char *t = scalar ? scene_scalar_text(n) : scene_node_kind(n);
  switch (scene_keys[k].type) {
  case KEY_REAL:
  case KEY_REAL3:
  case KEY_REAL6:
  case KEY_TIMES:
  case KEY_INT:
    if (scene_parse_number(c, n, path, scene_keys[k].type == KEY_INT, out))
      return -1;
    return scene_check_range(c, k, *out, mk, path);
  case KEY_BOOL:
    if (scalar && n->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
        (strcmp(t, "true") == 0 || strcmp(t, "false") == 0)) {
      *out = t[0] == 't';
      return 0;
    }
    return scene_error_set(c->err, mk, path,
                           "expected true or false, got %s%s%s",
                           scalar ? "'" : "", t, scalar ? "'" : "");
  case KEY_ENUM:
    scene_enum_list(k, list, sizeof list);
    if (!scalar || is_null(n))
      return scene_error_set(c->err, mk, path, "expected one of %s, got %s",
                             list, scene_node_kind(n));
    v = scene_enum_find(k, t);
    if (v < 0) {
      scene_enum_hint(hint, sizeof hint, k, t);
      return scene_error_set(
          c->err, mk, path, "unknown value '%s'%s; expected %s", t, hint, list);
    }
    *out = v;
    return 0;
  default: scene_error_set(c->err, mk, path, "not a scalar key"); return -1;
  }
}

long scene_list_len(scene_parse_ctx *c, const yaml_node_t *n, const char *path,
                    long min, long max, const char *what, const char *other) {
  long len =
      n->type != YAML_SEQUENCE_NODE
          ? -1
          : (long)(n->data.sequence.items.top - n->data.sequence.items.start);
  if (len >= min && len <= max) return len;
  return scene_error_set(c->err, scene_mark_of(&n->start_mark), path,
                         "expected %s, got %s", what,
                         len >= 0 ? other : scene_node_kind(n));
}

const yaml_node_t *scene_item_of(scene_parse_ctx *c, const yaml_node_t *n,
                                 long i) {
  return scene_node_get(c, n->data.sequence.items.start[i]);
}

/* the rows of a waypoints list key: times (numbers) or poses (lists of 3
   numbers), into arrays the scene owns; base.traj.wp points to them */
static int parse_rows(scene_parse_ctx *c, int k, const yaml_node_t *n,
                      scene_values *v) {
  const char *path = scene_keys[k].path;
  int poses = scene_keys[k].type == KEY_POSES;
  scene *s = c->s;
  long i, j,
      rows =
          scene_list_len(c, n, path, 2, LONG_MAX,
                         poses ? "a list of at least 2 poses [alpha, beta, z_c]"
                               : "a list of at least 2 numbers",
                         "a shorter list");
  double *dst;
  scene_mark *marks;
  char sub[160];
  if (rows < 0) return -1;
  dst = malloc((size_t)rows * (poses ? 3 : 1) * sizeof *dst);
  marks = malloc((size_t)rows * sizeof *marks);
  if (!dst || !marks) {
    free(dst);
    free(marks);
    return scene_error_set(c->err, scene_mark_of(&n->start_mark), path,
                           "out of memory");
  }
  if (poses) {
    s->wp_pose = (double(*)[3])(void *)dst;
    s->wp_npose = (size_t)rows;
    s->wp_pose_mark = marks;
    v->traj.wp.pose = (const double(*)[3])s->wp_pose;
  } else {
    v->traj.wp.time = s->wp_time = dst;
    s->wp_ntime = (size_t)rows;
    s->wp_time_mark = marks;
  }
  for (i = 0; i < rows; i++) {
    const yaml_node_t *item = scene_item_of(c, n, i);
    marks[i] = scene_mark_of(&item->start_mark);
    snprintf(sub, sizeof sub, "%s[%ld]", path, i);
    if (poses ? scene_list_len(c, item, sub, 3, 3, "a pose [alpha, beta, z_c]",
                               "a list of another length") < 0
              : scene_parse_scalar(c, k, item, sub, &dst[i]))
      return -1;
    for (j = 0; poses && j < 3; j++)
      if (scene_parse_number(c, scene_item_of(c, item, j), sub, 0,
                             &dst[3 * i + j]))
        return -1;
  }
  return 0;
}

/* a table file: read at once (its rows are checked as they are read), the
   rates it lacks from the spline; base.traj.table views the arrays */
static int parse_file(scene_parse_ctx *c, int k, const yaml_node_t *n,
                      scene_values *v) {
  scene *s = c->s;
  int what = SCENE_TABLE_OF(k);
  table_data *t = &s->table[what];
  char msg[sizeof c->err->what];
  scene_mark mk = scene_mark_of(&n->start_mark);
  if (n->type != YAML_SCALAR_NODE || is_null(n))
    return scene_error_set(c->err, mk, scene_keys[k].path,
                           "expected a file name, got %s", scene_node_kind(n));
  if (table_read(t, s->file, scene_scalar_text(n), what, msg, sizeof msg))
    return scene_error_set(c->err, mk, scene_keys[k].path, "%s", msg);
  v->file[what] = t->abs;
  if (what == TABLE_MEASURED) return 0; /* an identification's data */
  if (what == TABLE_POSE) {
    v->traj.table = table_view(t);
    return 0;
  }
  /* a path: the polar angles of the rows, followed continuously */
  s->path_psi = malloc(t->n * sizeof *s->path_psi);
  if (!s->path_psi)
    return scene_error_set(c->err, mk, scene_keys[k].path, "out of memory");
  rps3_table_unwrap(t->n, (const double(*)[3])t->value, s->path_psi);
  v->traj.path.table = table_view(t);
  v->traj.path.table_psi = s->path_psi;
  return 0;
}

/* 1 when t names a standard parameter of the general model (rps3_std_name,
   or a layout's shared name: the leg's digit left out, "cylinder.m") */
static int general_param_name(const char *t) {
  int k;
  for (k = 0; k < RPS3_NSTD; k++) {
    const char *n = rps3_std_name(k), *dot = strchr(n, '.');
    size_t head = dot ? (size_t)(dot - n) : 0;
    if (strcmp(n, t) == 0) return 1;
    /* "cylinder1.m" -> "cylinder.m" */
    if (head > 1 && n[head - 1] >= '1' && n[head - 1] <= '3' &&
        strncmp(n, t, head - 1) == 0 && strcmp(t + head - 1, dot) == 0)
      return 1;
  }
  return 0;
}

/* a list of names, each one bit: the effects, or the outputs */
static int parse_names(scene_parse_ctx *c, int k, const yaml_node_t *n,
                       scene_values *v) {
  const char *path = scene_keys[k].path;
  const char *what = scene_keys[k].type == KEY_OUTPUTS  ? "output"
                     : scene_keys[k].type == KEY_PARAMS ? "parameter"
                                                        : "effect";
  char list[256], expected[300];
  long i, len;
  int e, bits = 0;
  scene_enum_list(k, list, sizeof list);
  snprintf(expected, sizeof expected, "a non-empty list of %s", list);
  len = scene_list_len(c, n, path, 1, LONG_MAX, expected, "an empty list");
  for (i = 0; i < len; i++) {
    const yaml_node_t *item = scene_item_of(c, n, i);
    scene_mark im = scene_mark_of(&item->start_mark);
    int scalar = item->type == YAML_SCALAR_NODE;
    const char *t = scalar ? scene_scalar_text(item) : scene_node_kind(item);
    char hint[160] = "";
    e = scalar && !is_null(item) ? scene_enum_find(k, t) : -1;
    if (e < 0) {
      if (scalar && scene_keys[k].type == KEY_PARAMS &&
          general_param_name(t))
        return scene_error_set(
            c->err, im, path,
            "'%s' is a parameter of the general model, which takes no "
            "names: identify.model: general fits every parameter its "
            "effects fill; identify.parameters lists the paper model's "
            "(%s)",
            t, list);
      if (scalar) scene_enum_hint(hint, sizeof hint, k, t);
      return scene_error_set(
          c->err, im, path, "unknown %s %s%s%s%s; expected %s", what,
          scalar ? "'" : "", t, scalar ? "'" : "", hint, list);
    }
    if (bits & (1 << e))
      return scene_error_set(c->err, im, path, "%s '%s' listed twice", what,
                             scene_enum_name(k, e));
    bits |= 1 << e;
  }
  *scene_int_at(v, k) = bits;
  return len < 0 ? -1 : 0;
}

/* the value node n of key k into v (the whole key, lists included) */
static int parse_value(scene_parse_ctx *c, int k, const yaml_node_t *n,
                       scene_values *v) {
  const char *path = scene_keys[k].path;
  char sub[160], what[32];
  double x;
  int i, nc = scene_key_ncomp(&scene_keys[k]);
  switch (scene_keys[k].type) {
  case KEY_REAL3:
  case KEY_REAL6:
    snprintf(what, sizeof what, "a list of %d numbers", nc);
    if (scene_list_len(c, n, path, nc, nc, what, "a list of another length") <
        0)
      return -1;
    for (i = 0; i < nc; i++) {
      snprintf(sub, sizeof sub, "%s[%d]", path, i);
      if (scene_parse_scalar(c, k, scene_item_of(c, n, i), sub,
                             &scene_real_at(v, k)[i]))
        return -1;
    }
    return 0;
  case KEY_TIMES:
  case KEY_POSES: return parse_rows(c, k, n, v);
  case KEY_FILE: return parse_file(c, k, n, v);
  case KEY_EFFECTS:
  case KEY_OUTPUTS:
  case KEY_PARAMS: return parse_names(c, k, n, v);
  default:
    if (scene_parse_scalar(c, k, n, path, &x)) return -1;
    scene_value_set(v, k, -1, x);
    return 0;
  }
}

int scene_mapping_key(scene_parse_ctx *c, const yaml_node_t *map,
                      const yaml_node_pair_t *pair, const char *prefix,
                      const char **name) {
  const yaml_node_t *kn = scene_node_get(c, pair->key);
  const yaml_node_pair_t *q;
  scene_mark mk = scene_mark_of(&kn->start_mark);
  int named = kn->type == YAML_SCALAR_NODE && !is_null(kn);
  *name = named ? scene_scalar_text(kn) : "";
  /* an empty name ("" or "? >") would leave the key path blank in the
     message, naming nothing: say what it is and where it stands */
  if ((*name)[0] == '\0')
    return scene_error_set(c->err, mk, prefix[0] ? prefix : "(root)",
                           "a key must be a name, got %s",
                           named ? "an empty string" : scene_node_kind(kn));
  for (q = map->data.mapping.pairs.start; q < pair; q++) {
    const yaml_node_t *other = scene_node_get(c, q->key);
    if (other->type == YAML_SCALAR_NODE &&
        strcmp(scene_scalar_text(other), *name) == 0) {
      scene_mark om = scene_mark_of(&other->start_mark);
      char full[160];
      snprintf(full, sizeof full, "%s%s%s", prefix, prefix[0] ? "." : "",
               *name);
      return scene_error_set(c->err, mk, full,
                             "duplicate key (first given at %d:%d)", om.line,
                             om.column);
    }
  }
  return 0;
}

/* the sections whose marks scene.section keeps, by slot */
static const char *const top_sections[4] = {"", "manipulator", "trajectory",
                                            "solver"};

int scene_walk_section(scene_parse_ctx *c, const yaml_node_t *map,
                       const char *prefix) {
  yaml_node_pair_t *pair;
  char full[160], list[512];
  scene *s = c->s;
  for (pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top;
       pair++) {
    const char *name;
    const yaml_node_t *val = scene_node_get(c, pair->value);
    int k, sec;
    if (scene_mapping_key(c, map, pair, prefix, &name)) return -1;
    snprintf(full, sizeof full, "%s%s%s", prefix, prefix[0] ? "." : "", name);
    if (prefix[0] == '\0' && strcmp(name, "sweep") == 0) {
      c->sweep_node = pair->value;
      continue;
    }
    if (is_section(full)) {
      if (val->type != YAML_MAPPING_NODE)
        return scene_error_set(c->err, scene_mark_of(&val->start_mark), full,
                               "expected a mapping of keys, got %s",
                               scene_node_kind(val));
      for (sec = 1; sec < 4; sec++)
        if (strcmp(full, top_sections[sec]) == 0)
          s->section[sec] = scene_mark_of(&val->start_mark);
      if (strcmp(full, "simulate") == 0)
        s->simulate = scene_mark_of(&val->start_mark);
      if (strcmp(full, "design") == 0)
        s->design = scene_mark_of(&val->start_mark);
      if (strcmp(full, "identify") == 0)
        s->identify = scene_mark_of(&val->start_mark);
      if (scene_walk_section(c, val, full)) return -1;
      continue;
    }
    k = scene_key_find(full);
    if (k < 0) {
      char hint[200];
      scene_key_hint(hint, sizeof hint, full, 1);
      keys_under(prefix, list, sizeof list);
      return scene_error_set(
          c->err, scene_mark_of(&scene_node_get(c, pair->key)->start_mark),
          full, "unknown key%s; expected one of %s", hint, list);
    }
    if (parse_value(c, k, val, &s->base)) return -1;
    s->given[k] = s->in_file[k] = 1;
    s->mark[k] = scene_mark_of(&val->start_mark);
  }
  return 0;
}

/* ---------------------------------------------------------------- checks */

/* a waypoints scene has as many poses as times */
static int check_waypoints(scene_parse_ctx *c) {
  scene *s = c->s;
  if (s->base.traj.kind != RPS3_TRAJ_WAYPOINTS) return 0;
  if (s->wp_ntime != s->wp_npose)
    return scene_error_set(
        c->err, s->mark[K_WP_POSES], scene_keys[K_WP_POSES].path,
        "%zu poses for %zu times (trajectory.waypoints.times at %d:%d); give "
        "one pose per time",
        s->wp_npose, s->wp_ntime, s->mark[K_WP_TIMES].line,
        s->mark[K_WP_TIMES].column);
  s->base.traj.wp.n = s->wp_ntime;
  return 0;
}

/* a path scene gives the keys of its shape, and no others */
static int check_shape(scene_parse_ctx *c) {
  scene *s = c->s;
  int k, shape = (int)s->base.traj.path.shape;
  if (s->base.traj.kind != RPS3_TRAJ_PATH) return 0;
  for (k = 0; k < SCENE_NKEY; k++) {
    int mask = scene_shape_mask(k);
    if (mask == 0) continue;
    if (s->given[k] && !(mask & (1 << shape)))
      return scene_error_set(c->err, s->mark[k], scene_keys[k].path,
                             "not a key of a %s path",
                             scene_enum_name(K_PATH_SHAPE, shape));
    if (!s->given[k] && scene_keys[k].req == REQ_SHAPE && (mask & (1 << shape)))
      return scene_error_set(c->err, s->mark[K_PATH_SHAPE], scene_keys[k].path,
                             "missing required key of a %s path",
                             scene_enum_name(K_PATH_SHAPE, shape));
  }
  return 0;
}

int scene_check_keys(scene_parse_ctx *c) {
  scene *s = c->s;
  int k, pair;
  /* a design study needs no trajectory (it is the optional task) */
  int design = s->design.line > 0 || ident_data_only(s),
      no_traj = design && s->section[2].line == 0;
  /* the bodies decide which of M, d and the platform's keys are required */
  int general = s->base.model.bodies == RPS3_BODIES_GENERAL;
  int req_bodies = general ? REQ_GENERAL : REQ_PAPER;
  if (s->section[1].line == 0 || (s->section[2].line == 0 && !design))
    return scene_error_set(
        c->err, s->section[0],
        s->section[1].line == 0 ? "manipulator" : "trajectory",
        "missing required section");
  if (scene_design_check_keys(s, c->err) || scene_ident_check_keys(s, c->err) ||
      scene_bodies_check_keys(s, c->err))
    return -1;
  for (k = 0; k < SCENE_NKEY; k++) {
    const scene_key_info *ki = &scene_keys[k];
    int applies = scene_key_applies(ki, s->base.traj.kind);
    int sec = strncmp(ki->path, "manipulator", 11) == 0 ? 1 : 2;
    if (SCENE_KEY_IS_DESIGN(ki) || (no_traj && sec == 2)) continue;
    if (!applies && s->given[k])
      return scene_error_set(c->err, s->mark[k], ki->path,
                             "not a key of a %s trajectory",
                             scene_enum_name(K_KIND, (int)s->base.traj.kind));
    if (applies && (ki->req == REQ_YES || ki->req == req_bodies) &&
        !s->given[k])
      return scene_error_set(
          c->err, s->section[sec], ki->path, "missing required key%s",
          ki->req == REQ_GENERAL ? " with manipulator.bodies: general" : "");
  }
  if (check_waypoints(c) || check_shape(c)) return -1;
  for (pair = 0; pair < 3; pair++) {
    static const int one_of[3][2] = {
        {K_M_OVER_M, K_MASS}, {K_SAMPLES, K_DT}, {K_BLEND, K_BLEND_RATIO}};
    int a = one_of[pair][0], b = one_of[pair][1];
    if (!scene_key_applies(&scene_keys[a], s->base.traj.kind) ||
        (no_traj && pair > 0) || (general && pair == 0))
      continue;
    if (!s->given[a] && !s->given[b])
      return scene_error_set(c->err, s->section[pair ? 2 : 1],
                             scene_keys[a].path, "missing: give %s or %s",
                             hint_last_part(scene_keys[a].path),
                             hint_last_part(scene_keys[b].path));
    if (s->given[a] && s->given[b]) {
      int later = scene_mark_after(s->mark[a], s->mark[b]) ? a : b;
      int other = later == a ? b : a;
      return scene_error_set(c->err, s->mark[later], scene_keys[later].path,
                             "give either %s or %s, not both (%s is at %d:%d)",
                             hint_last_part(scene_keys[a].path),
                             hint_last_part(scene_keys[b].path),
                             scene_keys[other].path, s->mark[other].line,
                             s->mark[other].column);
    }
  }
  return 0;
}
