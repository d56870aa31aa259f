/*
 * scene_emit.c - the resolved YAML of a case and the `--keys` markdown,
 * both row by row of SCENE_KEYS; and the values that look like a unit
 * mistake: valid in SI, so not refused, but named with their place.
 */
#include "design.h"
#include "scene.h"
#include "scene_int.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* ----------------------------------------------------------------- emit */

void scene_text_free(scene_text *t) {
  if (t) {
    free(t->s);
    memset(t, 0, sizeof *t);
  }
}

static int text_write(void *data, unsigned char *buf, size_t size) {
  scene_text *t = data;
  if (t->len + size + 1 > t->cap) {
    size_t cap = t->cap ? t->cap : 1024;
    char *ns;
    while (cap < t->len + size + 1) cap *= 2;
    ns = realloc(t->s, cap);
    if (!ns) {
      t->oom = 1;
      return 0;
    }
    t->s = ns;
    t->cap = cap;
  }
  memcpy(t->s + t->len, buf, size);
  t->len += size;
  t->s[t->len] = '\0';
  return 1;
}

static int emit_scalar(yaml_emitter_t *em, const char *text) {
  yaml_event_t ev;
  yaml_scalar_event_initialize(&ev, NULL, NULL, (const yaml_char_t *)text,
                               (int)strlen(text), 1, 1,
                               YAML_PLAIN_SCALAR_STYLE);
  return yaml_emitter_emit(em, &ev);
}

/* a list (in flow style with flow), or a block mapping */
static int emit_open(yaml_emitter_t *em, int seq, int flow) {
  yaml_event_t ev;
  if (seq)
    yaml_sequence_start_event_initialize(
        &ev, NULL, NULL, 1,
        flow ? YAML_FLOW_SEQUENCE_STYLE : YAML_BLOCK_SEQUENCE_STYLE);
  else
    yaml_mapping_start_event_initialize(&ev, NULL, NULL, 1,
                                        YAML_BLOCK_MAPPING_STYLE);
  return yaml_emitter_emit(em, &ev);
}

static int emit_close(yaml_emitter_t *em, int seq) {
  yaml_event_t ev;
  if (seq)
    yaml_sequence_end_event_initialize(&ev);
  else
    yaml_mapping_end_event_initialize(&ev);
  return yaml_emitter_emit(em, &ev);
}

/* x[0..n) as a flow list of numbers */
static int emit_reals(yaml_emitter_t *em, const double *x, size_t n) {
  char buf[64];
  size_t i;
  int ok = emit_open(em, 1, 1);
  for (i = 0; i < n && ok; i++) {
    scene_format_real(buf, sizeof buf, x[i]);
    ok = emit_scalar(em, buf);
  }
  return ok && emit_close(em, 1);
}

/* the value of key k of v, as YAML events */
static int emit_value(yaml_emitter_t *em, int k, const scene_values *v) {
  char buf[64];
  const char *file;
  int i, ok = 1;
  size_t r;
  switch (scene_key_get(k)->type) {
  case KEY_REAL:
    scene_format_real(buf, sizeof buf, *scene_real_at(v, k));
    return emit_scalar(em, buf);
  case KEY_REAL3:
  case KEY_REAL6:
    return emit_reals(em, scene_real_at(v, k),
                      (size_t)scene_key_ncomp(scene_key_get(k)));
  case KEY_INT:
    snprintf(buf, sizeof buf, "%d", *scene_int_at(v, k));
    return emit_scalar(em, buf);
  case KEY_BOOL: return emit_scalar(em, *scene_int_at(v, k) ? "true" : "false");
  case KEY_ENUM:
    return emit_scalar(em, scene_enum_name(k, *scene_int_at(v, k)));
  case KEY_EFFECTS:
  case KEY_OUTPUTS:
  case KEY_PARAMS:
    ok = emit_open(em, 1, 1);
    for (i = 0; scene_enum_name(k, i) && ok; i++)
      if (*scene_int_at(v, k) & (1 << i))
        ok = emit_scalar(em, scene_enum_name(k, i));
    return ok && emit_close(em, 1);
  case KEY_TIMES: return emit_reals(em, v->traj.wp.time, v->traj.wp.n);
  case KEY_POSES:
    ok = emit_open(em, 1, 0);
    for (r = 0; r < v->traj.wp.n && ok; r++)
      ok = emit_reals(em, v->traj.wp.pose[r], 3);
    return ok && emit_close(em, 1);
  case KEY_FILE:
    file = v->file[SCENE_TABLE_OF(k)];
    return emit_scalar(em, file != NULL ? file : "");
  }
  return 0;
}

/* does case c write key k?  The link mass and the time grid are written
   the way the scene gave them. */
static int case_has_key(const scene_case *c, int k) {
  const scene_key_info *ki = scene_key_get(k);
  if (!scene_key_applies(ki, c->v.traj.kind)) return 0;
  /* the design keys in a design study; no trajectory where it has none */
  if (SCENE_KEY_IS_DESIGN(ki)) return c->design;
  if (c->design && design_key_unread(k)) return 0;
  if (c->no_traj && strncmp(ki->path, "trajectory.", 11) == 0) return 0;
  /* an identification is not swept: its cases are not rerun alone */
  if (ki->src == SRC_IDS) return 0;
  /* the legs' values are written leg by leg; only the keys the bodies
     read */
  if (ki->src == SRC_LEGS || !scene_bodies_read(k, c->v.model.bodies)) return 0;
  if (ki->src == SRC_SIM) {
    /* written when simulated; "not given" (NaN, -1) is not a value */
    if (!c->simulate) return 0;
    return ki->type == KEY_REAL  ? !isnan(*scene_real_at(&c->v, k))
           : scene_key_ncomp(ki) ? 1
                                 : *scene_int_at(&c->v, k) >= 0;
  }
  if (ki->req == REQ_ONE_MASS) return (k == K_M_OVER_M) == (c->by_ratio != 0);
  if (ki->req == REQ_ONE_GRID) return (k == K_DT) == (c->by_dt != 0);
  if (ki->req == REQ_ONE_BLEND)
    return (k == K_BLEND_RATIO) == (c->by_blend_ratio != 0);
  if (scene_shape_mask(k) != 0)
    return (scene_shape_mask(k) & (1 << (int)c->v.traj.path.shape)) != 0;
  return 1;
}

int scene_case_yaml(const scene_case *c, scene_text *out) {
  yaml_emitter_t em;
  yaml_event_t ev;
  char open[4][40]; /* the mapping sections currently open */
  int depth = 0, k, ok;

  out->len = 0;
  out->oom = 0;
  if (!yaml_emitter_initialize(&em)) return -1;
  yaml_emitter_set_output(&em, text_write, out);
  yaml_emitter_set_width(&em, -1);
  yaml_stream_start_event_initialize(&ev, YAML_UTF8_ENCODING);
  ok = yaml_emitter_emit(&em, &ev);
  yaml_document_start_event_initialize(&ev, NULL, NULL, NULL, 1);
  ok = ok && yaml_emitter_emit(&em, &ev);
  ok = ok && emit_open(&em, 0, 0);
  for (k = 0; k < SCENE_NKEY && ok; k++) {
    const char *p = scene_key_get(k)->path, *dot;
    int level = 0;
    if (!case_has_key(c, k)) continue;
    /* keep the sections this key is in, close the others, open the rest */
    for (; level < depth && (dot = strchr(p, '.')) != NULL &&
           strlen(open[level]) == (size_t)(dot - p) &&
           strncmp(open[level], p, (size_t)(dot - p)) == 0;
         level++)
      p = dot + 1;
    while (depth > level && ok) {
      ok = emit_close(&em, 0);
      depth--;
    }
    for (; ok && (dot = strchr(p, '.')) != NULL; p = dot + 1) {
      snprintf(open[depth], sizeof open[depth], "%.*s", (int)(dot - p), p);
      ok = emit_scalar(&em, open[depth++]) && emit_open(&em, 0, 0);
    }
    ok = ok && emit_scalar(&em, p) && emit_value(&em, k, &c->v);
  }
  /* the sections, then the root */
  while (depth-- >= 0 && ok) ok = emit_close(&em, 0);
  yaml_document_end_event_initialize(&ev, 1);
  ok = ok && yaml_emitter_emit(&em, &ev);
  yaml_stream_end_event_initialize(&ev);
  ok = ok && yaml_emitter_emit(&em, &ev);
  ok = ok && yaml_emitter_flush(&em);
  yaml_emitter_delete(&em);
  return ok && !out->oom ? 0 : -1;
}

/* ------------------------------------------------------------- key list */

/* the range of field row f, as the key table shows it */
static void range_text(const rps3_field_info *f, char *buf, size_t sz) {
  char lo[32], hi[32];
  scene_format_real(lo, sizeof lo, f->lo);
  scene_format_real(hi, sizeof hi, f->hi);
  if (f->lo == -HUGE_VAL && f->hi == HUGE_VAL)
    snprintf(buf, sz, "any");
  else if (f->hi == HUGE_VAL)
    snprintf(buf, sz, "%s %s", f->lo_open ? ">" : ">=", lo);
  else if (f->is_int && f->hi >= 2147483647.0)
    snprintf(buf, sz, ">= %s", lo);
  else
    snprintf(buf, sz, "%c%s, %s]", f->lo_open ? '(' : '[', lo, hi);
}

/* the type column of each key_type; an enum lists its names */
static const char *const type_text[] = {[KEY_REAL] = "number",
                                        [KEY_INT] = "integer",
                                        [KEY_BOOL] = "bool",
                                        [KEY_REAL3] = "[3 numbers]",
                                        [KEY_REAL6] = "[6 numbers]",
                                        [KEY_EFFECTS] = "[effect names]",
                                        [KEY_OUTPUTS] = "[output names]",
                                        [KEY_TIMES] = "[numbers]",
                                        [KEY_POSES] = "[[3 numbers], ...]",
                                        [KEY_FILE] = "file name",
                                        [KEY_PARAMS] = "[parameter names]"};

/* x[0..n) as "[a, b, c]" */
static void list_text(char *buf, size_t sz, const double *x, int n) {
  size_t len = 0;
  int i;
  for (i = 0; i < n && len < sz; i++)
    len += (size_t)snprintf(buf + len, sz - len, "%s%g", i ? ", " : "[", x[i]);
  if (len < sz) snprintf(buf + len, sz - len, "]");
}

void scene_keys_print(void) {
  scene_values v;
  char def[64], names[256], range[80];
  int k;
  scene_values_default(&v);
  printf("| key | type | unit | range | paper | default | meaning |\n");
  printf("|---|---|---|---|---|---|---|\n");
  for (k = 0; k < SCENE_NKEY; k++) {
    const scene_key_info *ki = scene_key_get(k);
    const char *type = type_text[ki->type];
    int kind = scene_key_kind(ki);
    if (ki->type == KEY_ENUM) {
      scene_enum_list(k, names, sizeof names);
      type = names;
    }
    if (ki->deftext)
      snprintf(def, sizeof def, "%s", ki->deftext);
    else if (ki->req != REQ_NO)
      snprintf(def, sizeof def, "%s",
               ki->req == REQ_SHAPE      ? "required by its shape"
               : ki->req == REQ_PAPER    ? "required with bodies: paper"
               : ki->req == REQ_GENERAL  ? "required with bodies: general"
               : ki->req != REQ_YES      ? "one of a pair"
               : SCENE_KEY_IS_DESIGN(ki) ? "required in a design study"
                                         : "required");
    else if (ki->type == KEY_REAL)
      snprintf(def, sizeof def, "%g", *scene_real_at(&v, k));
    else if (scene_key_ncomp(ki))
      list_text(def, sizeof def, scene_real_at(&v, k), scene_key_ncomp(ki));
    else if (ki->type == KEY_INT)
      snprintf(def, sizeof def, "%d", *scene_int_at(&v, k));
    else if (ki->type == KEY_BOOL)
      snprintf(def, sizeof def, "%s", *scene_int_at(&v, k) ? "true" : "false");
    else if (ki->type == KEY_ENUM)
      snprintf(def, sizeof def, "%s", scene_enum_name(k, *scene_int_at(&v, k)));
    else
      snprintf(def, sizeof def, "see meaning");
    range_text(ki->f, range, sizeof range);
    printf("| `%s`%s%s%s | %s | %s | %s | %s | %s | %s |\n", ki->path,
           kind != FOR_ALL ? " (" : "",
           kind != FOR_ALL ? scene_enum_name(K_KIND, kind) : "",
           kind != FOR_ALL ? ")" : "", type, ki->f->unit,
           (ki->type == KEY_REAL || scene_key_ncomp(ki) || ki->type == KEY_INT)
               ? range
               : "-",
           ki->symbol, def, ki->doc);
  }
}

/* ------------------------------------------------------------ warnings */

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
    for (comp = 0; comp < (ki->type == KEY_REAL ? 1 : scene_key_ncomp(ki));
         comp++) {
      double x = scene_real_at(&s->base, k)[comp];
      const char *why = suspect(quantity(ki, comp), x);
      char key[160];
      if (axis_warn(out, s, k, ki->type == KEY_REAL ? -1 : comp) || !why)
        continue;
      snprintf(key, sizeof key, "%s", ki->path);
      if (ki->type != KEY_REAL)
        snprintf(key + strlen(key), sizeof key - strlen(key), "[%d]", comp);
      warn(out, s, s->mark[k], key, "%.9g %s", x, why);
      break;
    }
    if (ki->type == KEY_POSES) {
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
