/*
 * scene_warn.c - values that look like a unit mistake: a length in
 * millimetres, an angle in degrees.  The scene is SI (metres, radians); such
 * a value is valid, so it is not refused, but it is named on stderr with its
 * place in the file, once per key (scene.h, scene_warnings_print).
 */
#include "scene.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* the largest 3-RPS manipulators built are about a metre across: a length
   above 10 m is most likely millimetres */
#define WARN_LENGTH_MAX 10.0
/* beta above 90 degrees tilts the platform past the vertical: most likely
   degrees (the paper's tilts are a few degrees, 0.1 rad) */
#define WARN_BETA_MAX 1.5707963267948966
/* another angle (an azimuth, a phase) beyond a full turn: most likely
   degrees */
#define WARN_ANGLE_MAX 6.283185307179586

/* what kind of quantity component comp of key k is */
enum { Q_NONE, Q_LENGTH, Q_BETA, Q_ANGLE };

static int quantity(const scene_key_info *ki, int comp) {
  if (strcmp(ki->f->unit, "m") == 0) return Q_LENGTH;
  if (strcmp(ki->f->unit, "rad, rad, m") == 0) /* a pose: alpha, beta, z_c */
    return comp == 2 ? Q_LENGTH : comp == 1 ? Q_BETA : Q_NONE;
  if (strcmp(ki->f->unit, "rad") == 0) return Q_ANGLE;
  return Q_NONE;
}

/* the reason x of quantity q looks wrong, or NULL */
static const char *suspect(int q, double x) {
  if (q == Q_LENGTH && fabs(x) > WARN_LENGTH_MAX)
    return "m looks like millimetres (above 10 m); scene lengths are in metres";
  if (q == Q_BETA && fabs(x) > WARN_BETA_MAX)
    return "rad looks like degrees (beta above pi/2 rad = 90 deg); scene "
           "angles are in radians";
  if (q == Q_ANGLE && fabs(x) > WARN_ANGLE_MAX)
    return "rad looks like degrees (above 2 pi rad = 360 deg); scene angles "
           "are in radians";
  return NULL;
}

static void warn(FILE *out, const scene *s, scene_mark mk, const char *key,
                 const char *fmt, ...) __attribute__((format(printf, 5, 6)));
static void warn(FILE *out, const scene *s, scene_mark mk, const char *key,
                 const char *fmt, ...) {
  va_list ap;
  if (mk.line > 0)
    fprintf(out, "%s:%d:%d: warning: %s: ", s->file, mk.line, mk.column, key);
  else
    fprintf(out, "%s: warning: %s: ", s->file, key);
  va_start(ap, fmt);
  vfprintf(out, fmt, ap);
  va_end(ap);
  fputc('\n', out);
}

/* the rows of a table: the first suspect value, named by its line */
static void table_warn(FILE *out, const scene *s, int k, int what) {
  const table_data *t = &s->table[what];
  size_t r;
  int c;
  char where[300];
  for (r = 0; r < t->n; r++)
    for (c = 0; c < 3; c++) {
      int q = what == TABLE_CENTRE || c == 2 ? Q_LENGTH
              : c == 1                       ? Q_BETA
                                             : Q_NONE;
      const char *why = suspect(q, t->value[r][c]);
      if (why == NULL) continue;
      table_where(t, r, where, sizeof where);
      warn(out, s, s->mark[k], scene_key_get(k)->path, "%s: column %s: %.9g %s",
           where, table_col_names[what][1 + c], t->value[r][c], why);
      return;
    }
}

/* a swept key (or one component of it): the first suspect value */
static int axis_warn(FILE *out, const scene *s, int k, int comp) {
  size_t a, i;
  const scene_key_info *ki = scene_key_get(k);
  int swept = 0;
  for (a = 0; a < s->naxis; a++) {
    const scene_axis *ax = &s->axis[a];
    if (ax->key != k || (comp >= 0 && ax->comp != comp && ax->comp >= 0))
      continue;
    swept = 1;
    for (i = 0; i < ax->n; i++) {
      const char *why = suspect(quantity(ki, ax->comp), ax->val[i]);
      if (why != NULL) {
        warn(out, s, ax->mark[i], ax->path, "%.9g %s", ax->val[i], why);
        return 1;
      }
    }
  }
  return swept;
}

void scene_warnings_print(const scene *s, FILE *out) {
  int k, comp;
  size_t r;
  for (k = 0; k < SCENE_NKEY; k++) {
    const scene_key_info *ki = scene_key_get(k);
    if (!s->given[k] || !scene_key_applies(ki, s->base.traj.kind)) continue;
    if (ki->type == KEY_REAL) {
      const char *why;
      if (axis_warn(out, s, k, -1)) continue;
      why = suspect(quantity(ki, 0), scene_value_real(&s->base, k, 0));
      if (why != NULL)
        warn(out, s, s->mark[k], ki->path, "%.9g %s",
             scene_value_real(&s->base, k, 0), why);
    } else if (ki->type == KEY_REAL3) {
      for (comp = 0; comp < 3; comp++) {
        const char *why;
        if (axis_warn(out, s, k, comp)) continue;
        why = suspect(quantity(ki, comp), scene_value_real(&s->base, k, comp));
        if (why != NULL) {
          char key[160];
          snprintf(key, sizeof key, "%s[%d]", ki->path, comp);
          warn(out, s, s->mark[k], key, "%.9g %s",
               scene_value_real(&s->base, k, comp), why);
          break;
        }
      }
    } else if (ki->type == KEY_POSES) {
      for (r = 0; r < s->wp_npose; r++) {
        const char *why = NULL;
        for (comp = 1; comp < 3 && why == NULL; comp++)
          why = suspect(quantity(ki, comp), s->wp_pose[r][comp]);
        if (why != NULL) {
          char key[160];
          snprintf(key, sizeof key, "%s[%zu][%d]", ki->path, r, comp - 1);
          warn(out, s, s->wp_pose_mark[r], key, "%.9g %s",
               s->wp_pose[r][comp - 1], why);
          break;
        }
      }
    } else if (ki->type == KEY_FILE) {
      table_warn(out, s, k, SCENE_TABLE_OF(k));
    }
  }
}
