/*
 * scene_int.h - what scene.c shares with scene_emit.c; not for the
 * programs (they use scene.h).
 */
#ifndef RPS3_RUNNER_SCENE_INT_H
#define RPS3_RUNNER_SCENE_INT_H

#include <stddef.h>

#include "scene.h"

/* the path shapes (bits 1 << rps3_path_shape) that use key k, for the
   keys that belong to some shapes only; 0 for any other key */
int scene_shape_mask(int k);

/* "a, b or c": the names of enum key k into buf */
void scene_enum_list(int k, char *buf, size_t sz);

/* where number or int key k's value is stored in v */
double *scene_real_at(scene_values *v, int k);
int *scene_int_at(scene_values *v, int k);

/* the defaults: the library's Table II model, options and helix */
void scene_values_default(scene_values *v);

/* x as the scene's files write it: shortest text that reads back equal */
void scene_format_real(char *buf, size_t sz, double x);

#endif /* RPS3_RUNNER_SCENE_INT_H */
