/*
 * scene_guard.h - what a scene file must be before it is parsed: a regular
 * file of at most SCENE_MAX_BYTES, UTF-8 text without NUL bytes, nested at
 * most SCENE_MAX_DEPTH deep, with no YAML tags but the core numeric ones.
 * Each refusal names its place (LINE:COL, and the key for a tag) and says
 * why; all of it costs one pass over the text.
 */
#ifndef RPS3_RUNNER_SCENE_GUARD_H
#define RPS3_RUNNER_SCENE_GUARD_H

#include <stddef.h>

#include "scene.h"

/* the largest scene file: the configs are a few kB, a scene with long
   sweep lists a few hundred */
#define SCENE_MAX_BYTES (1u << 20)

/* the deepest nesting of mappings and lists (a scene needs 3: section,
   key, value list); libyaml's time grows with the square of the depth */
#define SCENE_MAX_DEPTH 64

/*
 * Read the scene file at path into *text (malloc'd, NUL-terminated) and
 * *len.  Refuses what is not a regular file (a FIFO, /dev/zero, a
 * directory) and files over SCENE_MAX_BYTES, before reading them.  Returns
 * 0, or -1 with err set.
 */
int scene_read_guarded(const char *path, char **text, size_t *len,
                       scene_error *err);

/*
 * Check the text: UTF-16 and UTF-32 are named as such (save as UTF-8), a
 * NUL byte and invalid UTF-8 are reported at their LINE:COL, nesting
 * deeper than SCENE_MAX_DEPTH is refused, and so is any tag but !!int and
 * !!float on a scalar (a tag changes what a value means: `R: !!str 0.2`,
 * `!!python/object/apply:...`), naming the key.  Returns 0, or -1 with err
 * set.
 */
int scene_text_guard(const char *text, size_t len, scene_error *err);

#endif /* RPS3_RUNNER_SCENE_GUARD_H */
