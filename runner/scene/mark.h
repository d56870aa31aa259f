/*
 * mark.h - where in a scene file something is, and an error there: the
 * types that scene.h and the checks before parsing (scene_guard.h) share.
 */
#ifndef RPS3_RUNNER_MARK_H
#define RPS3_RUNNER_MARK_H

/* a position in the scene file, both 1-based; 0:0 when not known */
typedef struct {
  int line;
  int column;
} scene_mark;

/* one error, printed as FILE:LINE:COLUMN: path: what */
typedef struct {
  scene_mark mark;
  char path[128]; /* dotted key path, "yaml" for a syntax error */
  char what[512]; /* what is wrong, with the offending value */
} scene_error;

#endif /* RPS3_RUNNER_MARK_H */
