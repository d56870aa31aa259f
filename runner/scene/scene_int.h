/*
 * scene_int.h - what the scene files share: scene.c (key table, names,
 * values, errors), scene_parse.c (YAML nodes, checks), scene_sweep.c,
 * scene_load.c, scene_case.c (cases), scene_emit.c and design.c; not for
 * the programs (they use scene.h).
 */
#ifndef RPS3_RUNNER_SCENE_INT_H
#define RPS3_RUNNER_SCENE_INT_H

#include <stddef.h>

#include "scene.h"

#include <yaml.h>

/* a value counts as equal to a whole number within this many ulps of its
   size: used for the range expansion and for span / dt */
#define SCENE_WHOLE_RTOL 1e-9

/* the rows of SCENE_KEYS with their field's row */
extern const scene_key_info scene_keys[SCENE_NKEY];

/* the value of enum or name list key k named name, or -1 */
int scene_enum_find(int k, const char *name);

/* " (did you mean ...?)" for a value of key k */
void scene_enum_hint(char *buf, size_t sz, int k, const char *word);

/* "a, b or c" (a list key: "a, b, c"): the names of key k into buf */
void scene_enum_list(int k, char *buf, size_t sz);

/* set key k (component comp of a KEY_REAL3) to x */
void scene_value_set(scene_values *v, int k, int comp, double x);

/* libyaml's 0-based mark as the scene's 1-based line and column */
scene_mark scene_mark_of(const yaml_mark_t *m);

/* 1 when a stands later in the file than b */
int scene_mark_after(scene_mark a, scene_mark b);

/* the parse of one scene file */
typedef struct {
  yaml_document_t *doc;
  scene *s;
  scene_error *err;
  int sweep_node; /* node id of the sweep mapping, 0 if none */
  double ncase;   /* cases of the sweep keys read so far */
} scene_parse_ctx;

/* "a mapping", "a list", "nothing", "a quoted string" or "a scalar" */
const char *scene_node_kind(const yaml_node_t *n);

/* node id of the document; the text of scalar node n */
yaml_node_t *scene_node_get(scene_parse_ctx *c, int id);
const char *scene_scalar_text(const yaml_node_t *n);

/* " (did you mean ...?)" for a mistyped dotted key: every key and section
   is a candidate (a key in the wrong section included); sections only when
   with_sections, shallow ones first */
void scene_key_hint(char *buf, size_t sz, const char *word, int with_sections);

/* plain scalar n (of key path) as a finite decimal number, a whole one
   with integer; 0 or -1 with the error set */
int scene_parse_number(scene_parse_ctx *c, const yaml_node_t *n,
                       const char *path, int integer, double *out);

/* x (at mk, path) within the bounds of key k's field; 0 or -1 */
int scene_check_range(scene_parse_ctx *c, int k, double x, scene_mark mk,
                      const char *path);

/* one scalar value of key k as a number: the value itself (a number key,
   or one item of a list of numbers), an integer, 0/1 for a bool, the enum
   value for a name */
int scene_parse_scalar(scene_parse_ctx *c, int k, const yaml_node_t *n,
                       const char *path, double *out);

/* the length of list node n when it holds min to max items, else -1 with
   "expected WHAT, got OTHER" (OTHER for a list of another length, else the
   node's kind) */
long scene_list_len(scene_parse_ctx *c, const yaml_node_t *n, const char *path,
                    long min, long max, const char *what, const char *other);

/* item i of list node n */
const yaml_node_t *scene_item_of(scene_parse_ctx *c, const yaml_node_t *n,
                                 long i);

/* the name of pair's key in mapping map (section prefix) into *name: a
   non-empty name that map has not given before; 0 or -1 */
int scene_mapping_key(scene_parse_ctx *c, const yaml_node_t *map,
                      const yaml_node_pair_t *pair, const char *prefix,
                      const char **name);

/* the keys of section map (prefix "" the root) into c->s, its sections
   walked in turn and the sweep's node kept for later; 0 or -1 */
int scene_walk_section(scene_parse_ctx *c, const yaml_node_t *map,
                       const char *prefix);

/* the keys given, the sweep read: required ones there, each of the scene's
   kind, shape and bodies, one of each pair; 0 or -1 */
int scene_check_keys(scene_parse_ctx *c);

/* the sweep mapping map: its axes into c->s and their cases counted into
   c->ncase and c->s->ncase; 0 or -1 */
int scene_parse_sweep(scene_parse_ctx *c, const yaml_node_t *map);

/* the path shapes (bits 1 << rps3_path_shape) that use key k, for the
   keys that belong to some shapes only; 0 for any other key */
int scene_shape_mask(int k);

/* where number or int key k's value is stored in v */
double *scene_real_at(const scene_values *v, int k);
int *scene_int_at(const scene_values *v, int k);

/* the defaults: the library's Table II model, options and helix */
void scene_values_default(scene_values *v);

/* x as the scene's files write it: shortest text that reads back equal */
void scene_format_real(char *buf, size_t sz, double x);

/* err = msg ("case N: msg" in a sweep) at the value case `index` takes of
   a key that sets one of the fields the failed rule chk reads (first_key
   first, then the failing field, then the related ones; a list key's axis
   when it is the failing component or the whole key): its swept value,
   else the key given in the file, else at (path first_key's); without at,
   the first swept value, else the manipulator section; -1 */
int scene_case_error(const scene *s, size_t index, const char *msg,
                     const rps3_check *chk, int first_key, const scene_mark *at,
                     scene_error *err);

/* the design keys against the design section: given (or swept) only in a
   scene that has one, its required keys there, no simulate section beside
   it, its grid not swept; 0 or -1 with the error set */
int scene_design_check_keys(const scene *s, scene_error *err);

/* the identify keys against the scene (identify.c): the section alone
   with a trajectory (no simulate or design section, no sweep), its
   parameters columns of its effects; 0 or -1 with the error set */
int scene_ident_check_keys(const scene *s, scene_error *err);

/* 1 when the scene is an identification of a data file: it needs no
   trajectory */
int ident_data_only(const scene *s);

/* the bodies (scene_bodies.c): 1 when a model of bodies `bodies`
   (rps3_bodies) reads key k: the paper's do not read the general bodies'
   keys, the general ones not M, m, m_over_M, d, link_Ic, the pins' common
   friction and the controller's overrides of them */
int scene_bodies_read(int k, int bodies);

/* no key given (or swept) that the scene's bodies do not read; 0 or -1
   with the error set */
int scene_bodies_check_keys(const scene *s, scene_error *err);

/* 1 when key k, given, sets library field id in the cases of s: the key
   that fills it, or the key of every leg when the leg's own is not in the
   file */
int scene_key_sets(const scene *s, int k, int id);

/* the key given that sets leg field id (RPS3_F_LEGk_*): the leg's own
   (in the file or swept), else the key of every leg; -1 when neither is
   given */
int scene_leg_key(const scene *s, int id);

/* the values of the keys of every leg into each leg of v whose own key is
   not in the file (a sweep of the leg's own key, applied after, then
   replaces the value or the component it sweeps); the number of keys
   filled */
int scene_legs_fill(const scene *s, scene_values *v);

#endif /* RPS3_RUNNER_SCENE_INT_H */
