/*
 * scene_int.h - what the scene files share: scene.c (key table, names,
 * values, errors), scene_parse.c (YAML nodes, sweep, checks), scene_load.c,
 * scene_case.c (cases), scene_emit.c and design.c; not for the programs
 * (they use scene.h).
 */
#ifndef RPS3_RUNNER_SCENE_INT_H
#define RPS3_RUNNER_SCENE_INT_H

#include <stddef.h>

#include "scene.h"

#include <yaml.h>

/* a value counts as equal to a whole number within this many ulps of its
   size: used for the range expansion and for span / dt */
#define SCENE_WHOLE_RTOL 1e-9

/* ------------------------------------------------------ scene.c: keys */

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

/* ------------------------------------------------------ scene_parse.c */

/* "a mapping", "a list", "nothing", "a quoted string" or "a scalar" */
const char *scene_node_kind(const yaml_node_t *n);

/* the sections of document doc (its root mapping root) into s: their keys,
   the sweep, then the checks of the keys given; 0 or -1 with err set */
int scene_parse_doc(scene *s, yaml_document_t *doc, const yaml_node_t *root,
                    scene_error *err);

/* ------------------------------------------- scene_values and emitting */

/* the path shapes (bits 1 << rps3_path_shape) that use key k, for the
   keys that belong to some shapes only; 0 for any other key */
int scene_shape_mask(int k);

/* where number or int key k's value is stored in v */
double *scene_real_at(scene_values *v, int k);
int *scene_int_at(scene_values *v, int k);

/* the defaults: the library's Table II model, options and helix */
void scene_values_default(scene_values *v);

/* x as the scene's files write it: shortest text that reads back equal */
void scene_format_real(char *buf, size_t sz, double x);

/* ----------------------------------------------------- scene_case.c */

/* err = msg ("case N: msg" in a sweep) at the value case `index` takes of
   a key that sets one of the fields the failed rule chk reads (first_key
   first, then the failing field, then the related ones; a list key's axis
   when it is the failing component or the whole key): its swept value,
   else the key given in the file, else at (path first_key's); without at,
   the first swept value, else the manipulator section */
void scene_case_error(const scene *s, size_t index, const char *msg,
                      const rps3_check *chk, int first_key,
                      const scene_mark *at, scene_error *err);

/* ------------------------------------------------- design.c: design keys */

/* the design keys against the design section: given (or swept) only in a
   scene that has one, its required keys there, no simulate section beside
   it, its grid not swept; 0 or -1 with the error set */
int scene_design_check_keys(const scene *s, scene_error *err);

#endif /* RPS3_RUNNER_SCENE_INT_H */
