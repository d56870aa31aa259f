/*
 * scene_sweep.c - the sweep: section of a scene: its axes, each a scene key
 * or one component [k] of a list key that may be swept, and each axis's
 * values, a list or a {from, to, num} or {from, to, step} range expanded
 * here, every value checked against its key's bounds and the cases counted
 * as the axes are read.
 */
#include "scene.h"
#include "scene_int.h"

#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* the most cases a sweep may expand to: every case is built and checked
   before a run (about 1 us each: 10 s at the limit); more is several runs */
#define MAX_CASES 10000000.0

/* the nodes of a {from, to, num} or {from, to, step} mapping, by R_* */
enum { R_FROM, R_TO, R_NUM, R_STEP };
typedef const yaml_node_t *range_nodes[4];
static const char *const range_names[4] = {"from", "to", "num", "step"};

/* the nodes of range mapping map of axis ax: no other key (none twice:
   scene_mapping_key), from, to and one of num and step; 0 or -1 */
static int range_read(scene_parse_ctx *c, const scene_axis *ax,
                      const yaml_node_t *map, range_nodes r) {
  yaml_node_pair_t *p;
  char sub[160];
  memset(r, 0, sizeof(range_nodes));
  for (p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top;
       p++) {
    const char *name;
    int k;
    if (scene_mapping_key(c, map, p, ax->path, &name)) return -1;
    for (k = 0; k < 4 && strcmp(name, range_names[k]) != 0; k++)
      ;
    if (k == 4) {
      snprintf(sub, sizeof sub, "%s.%s", ax->path, name);
      return scene_error_set(
          c->err, scene_mark_of(&scene_node_get(c, p->key)->start_mark), sub,
          "unknown key; expected from, to and num or step");
    }
    r[k] = scene_node_get(c, p->value);
  }
  if (!r[R_FROM] || !r[R_TO] || (!r[R_NUM] == !r[R_STEP]))
    return scene_error_set(
        c->err, scene_mark_of(&map->start_mark), ax->path,
        "a range needs from, to and exactly one of num and step");
  return 0;
}

/* entry R of axis ax's range r as a number; 0 or -1 */
static int range_number(scene_parse_ctx *c, const scene_axis *ax, range_nodes r,
                        int R, int integer, double *x) {
  char sub[160];
  snprintf(sub, sizeof sub, "%s.%s", ax->path, range_names[R]);
  return scene_parse_number(c, r[R], sub, integer, x);
}

/* the number of values of range r from `from` to `to`, counted before
   anything is allocated; *step is 0 for a range by num.  0 or -1 */
static int range_count(scene_parse_ctx *c, const scene_axis *ax, range_nodes r,
                       int integer, double from, double to, double *step,
                       size_t *n) {
  const yaml_node_t *nd = r[R_NUM] ? r[R_NUM] : r[R_STEP];
  scene_mark mk = scene_mark_of(&nd->start_mark);
  double span = to - from, num, q;
  char sub[160];
  snprintf(sub, sizeof sub, "%s.%s", ax->path,
           range_names[r[R_NUM] ? R_NUM : R_STEP]);
  *step = 0;
  if (r[R_NUM]) {
    if (scene_parse_number(c, nd, sub, 1, &num)) return -1;
    if (num < 1 || (num == 1 && from != to))
      return scene_error_set(c->err, mk, sub,
                             "must be >= 2 (or 1 with from == to), got %.0f",
                             num);
    if (num * c->ncase > MAX_CASES)
      return scene_error_set(c->err, mk, sub,
                             "%.0f values make the sweep more than %.0f cases",
                             num, MAX_CASES);
    *n = (size_t)num;
    return 0;
  }
  if (scene_parse_number(c, nd, sub, integer, step)) return -1;
  q = span / *step;
  if (*step == 0 || q < 0)
    return scene_error_set(
        c->err, mk, sub, "must be non-zero with the sign of to - from, got %s",
        scene_scalar_text(nd));
  if (!(span - span == 0))
    return scene_error_set(
        c->err, mk, sub,
        "to - from overflows (%s to %s): not a range of numbers",
        scene_scalar_text(r[R_FROM]), scene_scalar_text(r[R_TO]));
  if ((q + 1) * c->ncase > MAX_CASES)
    return scene_error_set(
        c->err, mk, sub,
        "gives %.3g values: the sweep would have more than %.0f cases", q + 1,
        MAX_CASES);
  *n = (size_t)floor(q + SCENE_WHOLE_RTOL) + 1;
  return 0;
}

/* value i of n of a range from `from` to `to` by num (step 0) or step */
static double range_value(size_t i, size_t n, double from, double to,
                          double step) {
  double span = to - from, x;
  if (step == 0 && !(span - span == 0))
    /* to - from overflows ({from: -1e308, to: 1e308}): weights instead,
       so that each value is a number and its range check speaks */
    return (i + 1 == n) ? to
                        : from * (1 - (double)i / (double)(n - 1)) +
                              to * ((double)i / (double)(n - 1));
  if (step == 0)
    return (i + 1 == n) ? to : from + span * (double)i / (double)(n - 1);
  x = from + (double)i * step;
  /* the last step lands on `to` up to rounding: take `to` itself */
  if (i + 1 == n && fabs(x - to) <= SCENE_WHOLE_RTOL * fabs(step)) x = to;
  return x;
}

/* room for the n values of axis ax; 0 or -1 */
static int axis_alloc(scene_parse_ctx *c, scene_axis *ax, size_t n,
                      scene_mark mk, const char *what) {
  ax->n = n;
  ax->val = malloc(n * sizeof *ax->val);
  ax->mark = malloc(n * sizeof *ax->mark);
  if (!ax->val || !ax->mark)
    return scene_error_set(c->err, mk, ax->path, what, n);
  return 0;
}

/* expand a {from, to, num} or {from, to, step} mapping into ax */
static int sweep_range(scene_parse_ctx *c, scene_axis *ax,
                       const yaml_node_t *map) {
  const scene_key_info *ki = &scene_keys[ax->key];
  scene_mark mk = scene_mark_of(&map->start_mark);
  range_nodes r;
  double from, to, step;
  int integer = ki->type == KEY_INT;
  size_t i, n = 0;
  if (ki->type != KEY_REAL && scene_key_ncomp(ki) == 0 && !integer)
    return scene_error_set(
        c->err, mk, ax->path,
        "a range needs a numeric key; give a list of values");
  if (range_read(c, ax, map, r) ||
      range_number(c, ax, r, R_FROM, integer, &from) ||
      range_number(c, ax, r, R_TO, integer, &to) ||
      range_count(c, ax, r, integer, from, to, &step, &n) ||
      axis_alloc(c, ax, n, mk, "out of memory for %zu values"))
    return -1;
  for (i = 0; i < n; i++) {
    double x = range_value(i, n, from, to, step);
    if (integer && x != floor(x))
      return scene_error_set(c->err, mk, ax->path,
                             "value %zu of the range, %g, is not an integer", i,
                             x);
    if (scene_check_range(c, ax->key, x, mk, ax->path)) return -1;
    ax->val[i] = x;
    ax->mark[i] = mk;
  }
  return 0;
}

/* the key of sweep entry `name` (at km) into ax: a scene key, or one
   component of a list key, that may be swept, of the scene's kind and not
   swept before; 0 or -1 */
static int sweep_key(scene_parse_ctx *c, scene_axis *ax, const char *name,
                     scene_mark km) {
  scene *s = c->s;
  const scene_key_info *ki;
  const char *br;
  char base[80], comps[40];
  size_t a;
  int nc;
  if (strlen(name) >= sizeof ax->path)
    return scene_error_set(c->err, km, "sweep", "key '%.40s...' is too long",
                           name);
  snprintf(ax->path, sizeof ax->path, "%s", name);
  ax->comp = -1;
  /* "key[k]" picks component k of a list key */
  br = strchr(name, '[');
  snprintf(base, sizeof base, "%.*s",
           (int)(br ? (size_t)(br - name) : strlen(name)), name);
  ax->key = scene_key_find(base);
  if (ax->key < 0) {
    char hint[200];
    scene_key_hint(hint, sizeof hint, base, 0);
    return scene_error_set(c->err, km, name,
                           "not a scene key%s; see rps3-run --keys", hint);
  }
  ki = &scene_keys[ax->key];
  nc = scene_key_ncomp(ki);
  snprintf(comps, sizeof comps, nc == 3 ? "[0], [1] or [2]" : "[0] to [%d]",
           nc - 1);
  if (br) {
    if (nc == 0 || !(br[1] >= '0' && br[1] < '0' + nc) ||
        strcmp(br + 2, "]") != 0)
      return scene_error_set(
          c->err, km, name,
          nc ? "component must be %s" : "only a list key takes a component [k]",
          comps);
    ax->comp = br[1] - '0';
  } else if (nc) {
    return scene_error_set(c->err, km, name,
                           "a list key: sweep one component, as %s[0], %s",
                           name, nc == 3 ? "[1] or [2]" : "[1] ... [5]");
  }
  if (ki->type == KEY_EFFECTS || ki->type == KEY_OUTPUTS ||
      ki->src == SRC_IDS || ki->type == KEY_TIMES || ki->type == KEY_POSES ||
      ki->type == KEY_FILE || ax->key == K_KIND || ax->key == K_PATH_SHAPE ||
      ax->key == K_BODIES)
    return scene_error_set(c->err, km, name,
                           "cannot be swept (it decides what a case computes); "
                           "write one scene per value");
  if (!scene_key_applies(ki, s->base.traj.kind))
    return scene_error_set(c->err, km, name, "not a key of a %s trajectory",
                           scene_enum_name(K_KIND, (int)s->base.traj.kind));
  for (a = 0; a + 1 < s->naxis; a++)
    if (s->axis[a].key == ax->key && s->axis[a].comp == ax->comp)
      return scene_error_set(c->err, km, name, "swept twice (also as %s)",
                             s->axis[a].path);
  return 0;
}

/* the values of axis ax: a list, a range mapping; 0 or -1 */
static int sweep_values(scene_parse_ctx *c, scene_axis *ax,
                        const yaml_node_t *val, scene_mark km) {
  long i, n;
  if (val->type == YAML_MAPPING_NODE) return sweep_range(c, ax, val);
  if (val->type == YAML_SEQUENCE_NODE &&
      val->data.sequence.items.top == val->data.sequence.items.start)
    return scene_error_set(c->err, scene_mark_of(&val->start_mark), ax->path,
                           "empty list of values");
  n = scene_list_len(c, val, ax->path, 1, LONG_MAX,
                     "a list of values, {from, to, num} or {from, to, step}",
                     "");
  if (n < 0 || axis_alloc(c, ax, (size_t)n, km, "out of memory")) return -1;
  for (i = 0; i < n; i++) {
    const yaml_node_t *item = scene_item_of(c, val, i);
    if (scene_parse_scalar(c, ax->key, item, ax->path, &ax->val[i])) return -1;
    ax->mark[i] = scene_mark_of(&item->start_mark);
  }
  return 0;
}

int scene_parse_sweep(scene_parse_ctx *c, const yaml_node_t *map) {
  scene *s = c->s;
  yaml_node_pair_t *pair;
  size_t npair;
  if (map->type != YAML_MAPPING_NODE ||
      map->data.mapping.pairs.top == map->data.mapping.pairs.start)
    return scene_error_set(
        c->err, scene_mark_of(&map->start_mark), "sweep",
        "expected a mapping of dotted keys to values, got %s",
        map->type == YAML_MAPPING_NODE ? "an empty mapping"
                                       : scene_node_kind(map));
  npair = (size_t)(map->data.mapping.pairs.top - map->data.mapping.pairs.start);
  s->axis = calloc(npair, sizeof *s->axis);
  if (!s->axis)
    return scene_error_set(c->err, scene_mark_of(&map->start_mark), "sweep",
                           "out of memory");
  for (pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top;
       pair++) {
    scene_mark km = scene_mark_of(&scene_node_get(c, pair->key)->start_mark);
    /* counted at once, so that scene_free frees a half-built axis */
    scene_axis *ax = &s->axis[s->naxis++];
    const char *name;
    if (scene_mapping_key(c, map, pair, "sweep", &name) ||
        sweep_key(c, ax, name, km) ||
        sweep_values(c, ax, scene_node_get(c, pair->value), km))
      return -1;
    c->ncase *= (double)ax->n;
    if (c->ncase > MAX_CASES)
      return scene_error_set(c->err, km, name,
                             "the sweep has more than %.0f cases", MAX_CASES);
    /* a swept key counts as given; its mark is its first value */
    s->given[ax->key] = 1;
    if (s->mark[ax->key].line == 0) s->mark[ax->key] = ax->mark[0];
  }
  s->ncase = (size_t)c->ncase;
  return 0;
}
