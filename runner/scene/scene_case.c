/*
 * scene_case.c - case `index` of a loaded scene: its swept values applied to
 * the base values, converted to the library's model and trajectory and
 * validated by the library, its time grid; an error points at the swept
 * value or the key that made the case wrong.
 */
#include "scene.h"
#include "scene_int.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* ----------------------------------------------------------------- cases */

size_t scene_case_coord(const scene *s, size_t index, size_t a) {
  size_t b;
  /* row-major: the last axis varies fastest */
  for (b = s->naxis; b-- > a + 1;) index /= s->axis[b].n;
  return index % s->axis[a].n;
}

/* the keys that set library field id in scene s (a converted key such as
   m_over_M when the scene gave it, a key of every leg): up to max into
   out */
static int keys_filling(const scene *s, int id, int *out, int max) {
  int k, n = 0;
  for (k = 0; k < SCENE_NKEY && n < max; k++)
    if (id >= 0 && s->given[k] && scene_key_sets(s, k, id)) out[n++] = k;
  return n;
}

void scene_case_what(const scene *s, size_t index, const char *msg, char *buf,
                     size_t sz) {
  if (s->naxis > 0)
    snprintf(buf, sz, "case %zu: %s", index, msg);
  else
    snprintf(buf, sz, "%s", msg);
}

int scene_case_error(const scene *s, size_t index, const char *msg,
                     const rps3_check *chk, int first_key, const scene_mark *at,
                     scene_error *err) {
  int named[16], comp[16], n = 0, i, j, m;
  size_t a;
  char what[sizeof err->what];
  scene_case_what(s, index, msg, what, sizeof what);
  if (first_key >= 0) {
    comp[n] = -1;
    named[n++] = first_key;
  }
  if (chk != NULL) {
    int ids[3] = {chk->field, chk->related[0], chk->related[1]};
    /* the rules of an inertia tensor read all of it: any component */
    const rps3_field_info *f = rps3_field(chk->field);
    int fcomp = f != NULL && f->n == 6 ? -1 : chk->comp;
    for (j = 0; j < 3; j++) {
      m = keys_filling(s, ids[j], named + n, 16 - n);
      for (i = n; i < n + m; i++) comp[i] = j == 0 ? fcomp : -1;
      n += m;
    }
  }
  /* a waypoint row: point at the row itself */
  if (chk != NULL && chk->comp >= 0 &&
      ((chk->field == RPS3_F_WP_TIME && (size_t)chk->comp < s->wp_ntime) ||
       (chk->field == RPS3_F_WP_POSE && (size_t)chk->comp < s->wp_npose))) {
    int key = chk->field == RPS3_F_WP_TIME ? K_WP_TIMES : K_WP_POSES;
    char row[96];
    snprintf(row, sizeof row, "%s[%d]", scene_keys[key].path, chk->comp);
    return scene_error_set(err,
                           chk->field == RPS3_F_WP_TIME
                               ? s->wp_time_mark[chk->comp]
                               : s->wp_pose_mark[chk->comp],
                           row, "%s", what);
  }
  /* a table row: point at the file key, and name the file's line */
  for (j = 0; j < 2 && chk != NULL && chk->comp >= 0; j++) {
    int lo = j ? RPS3_F_PATH_TABLE_TIME : RPS3_F_TABLE_TIME;
    int key = j ? K_PATH_FILE : K_TABLE_FILE;
    const table_data *t = &s->table[SCENE_TABLE_OF(key)];
    char where[300];
    if (chk->field < lo || chk->field > lo + 3 || (size_t)chk->comp >= t->n)
      continue;
    table_where(t, (size_t)chk->comp, where, sizeof where);
    return scene_error_set(err, s->mark[key], scene_keys[key].path, "%s: %s",
                           where, what);
  }
  for (i = 0; i < n; i++)
    for (a = 0; a < s->naxis; a++)
      if (s->axis[a].key == named[i] &&
          (s->axis[a].comp < 0 || comp[i] < 0 || s->axis[a].comp == comp[i]))
        return scene_error_set(err,
                               s->axis[a].mark[scene_case_coord(s, index, a)],
                               s->axis[a].path, "%s", what);
  for (i = 0; i < n; i++)
    if (s->given[named[i]])
      return scene_error_set(err, s->mark[named[i]], scene_keys[named[i]].path,
                             "%s", what);
  if (at != NULL)
    return scene_error_set(err, *at, scene_keys[first_key].path, "%s", what);
  if (s->naxis > 0)
    return scene_error_set(err, s->axis[0].mark[scene_case_coord(s, index, 0)],
                           s->axis[0].path, "%s", what);
  return scene_error_set(err, s->section[1], "manipulator", "%s", what);
}

/* the effects the manipulator section configures */
#define CONFIGURABLE \
  (RPS3_EFF_PAYLOAD | RPS3_EFF_PIN_FRICTION | RPS3_EFF_PRISMATIC_FRICTION)

/* the key that configures friction law f of leg i, viscous the leg 1
   field of its viscous coefficient (coulomb follows it), or -1 */
static int leg_friction_key(const scene *s, const rps3_friction *f, int i,
                            int viscous) {
  int id = viscous + i * SCENE_LEG_NFIELD, k;
  if (!(f->viscous > 0 || f->coulomb > 0)) return -1;
  k = scene_leg_key(s, f->viscous > 0 ? id : id + 1);
  return k >= 0 ? k : K_LEGS_CYL_MASS + (viscous - RPS3_F_LEG1_CYLINDER_MASS);
}

/* the key that configures effect `bit` (CONFIGURABLE) in model m: one
   whose value is above 0 (every default is 0, so it is given), or -1 */
static int configured_by(const scene *s, const rps3_model *m, int bit) {
  int i, k = -1;
  if (bit == RPS3_EFF_PAYLOAD)
    return m->payload.mass > 0 ? K_PAY_MASS
           : m->payload.inertia[0] > 0 || m->payload.inertia[1] > 0 ||
                   m->payload.inertia[2] > 0
               ? K_PAY_INERTIA
               : -1;
  if (bit == RPS3_EFF_PIN_FRICTION && m->bodies != RPS3_BODIES_GENERAL)
    return m->friction.viscous > 0   ? K_VISCOUS
           : m->friction.coulomb > 0 ? K_COULOMB
                                     : -1;
  for (i = 0; i < 3 && k < 0; i++)
    k = bit == RPS3_EFF_PIN_FRICTION
            ? leg_friction_key(s, &m->leg[i].pin, i, RPS3_F_LEG1_PIN_VISCOUS)
            : leg_friction_key(s, &m->leg[i].prismatic, i,
                               RPS3_F_LEG1_PRISMATIC_VISCOUS);
  return k;
}

/*
 * The rule for configured effects.  A payload (mass or a moment of inertia
 * above 0), pin friction or prismatic friction (a coefficient above 0) is
 * configured in the manipulator section; the effects list selects what is
 * computed.  An omitted list selects the paper's four effects plus
 * whatever is configured.  An explicit list that leaves out a configured
 * effect would silently drop it: refused, naming both keys.  Returns 0,
 * or -1 with err set.
 */
static int effects_rule(const scene *s, size_t index, scene_case *c,
                        scene_error *err) {
  int eff = c->model.opt.effects, e, k;
  char msg[320];
  if (!s->given[K_EFFECTS]) {
    eff = RPS3_EFF_DEFAULT;
    for (e = 0; e < RPS3_NEFFECT; e++)
      if (((1 << e) & CONFIGURABLE) && configured_by(s, &c->model, 1 << e) >= 0)
        eff |= 1 << e;
    c->model.opt.effects = c->v.model.opt.effects = eff;
    return 0;
  }
  for (e = 0; e < RPS3_NEFFECT; e++) {
    const char *name = rps3_effect_name(e);
    if (!((1 << e) & CONFIGURABLE) || (eff & (1 << e))) continue;
    k = configured_by(s, &c->model, 1 << e);
    if (k < 0) continue;
    snprintf(msg, sizeof msg,
             "leaves out %s, but %s is configured (%d:%d); add %s to the list, "
             "or remove the %s",
             name, scene_keys[k].path, s->mark[k].line, s->mark[k].column, name,
             (1 << e) == RPS3_EFF_PAYLOAD ? "payload" : "friction");
    return scene_case_error(s, index, msg, NULL, K_EFFECTS, NULL, err);
  }
  return 0;
}

/* err for a dt that does not fit the span of case `index`: q = span / dt
   steps, too many for one case or not a whole number of them */
static int dt_error(const scene *s, size_t index, const scene_case *c, double q,
                    scene_error *err) {
  char msg[256], sa[32], sb[32];
  scene_format_real(sa, sizeof sa, c->span);
  scene_format_real(sb, sizeof sb, c->v.own.dt);
  if (q >= 2147483646.0)
    snprintf(msg, sizeof msg,
             "dt = %s s over the span %s s is %.6g steps: at most 2147483646 "
             "samples per case",
             sb, sa, q);
  else
    snprintf(
        msg, sizeof msg,
        "the span %s s is not a whole number of steps dt = %s s (%.6g steps)",
        sa, sb, q);
  return scene_case_error(s, index, msg, NULL, K_DT, NULL, err);
}

/* the values case `index` takes of the swept keys into v */
static void sweep_apply(const scene *s, size_t index, scene_values *v) {
  size_t a;
  for (a = 0; a < s->naxis; a++)
    scene_value_set(v, s->axis[a].key, s->axis[a].comp,
                    s->axis[a].val[scene_case_coord(s, index, a)]);
}

int scene_case_build(const scene *s, size_t index, scene_case *c,
                     scene_error *err) {
  rps3_check chk;
  memset(c, 0, sizeof *c);
  c->index = index;
  c->by_ratio = s->given[K_M_OVER_M];
  c->by_dt = s->given[K_DT];
  c->by_blend_ratio = s->given[K_BLEND_RATIO];
  c->simulate = s->simulate.line > 0;
  c->design = s->design.line > 0;
  c->no_traj = (c->design || ident_data_only(s)) && s->section[2].line == 0;
  c->v = s->base;
  sweep_apply(s, index, &c->v);
  /* the values of every leg into each leg, then the sweep again: a swept
     component of a leg's own key stays */
  if (scene_legs_fill(s, &c->v) > 0) sweep_apply(s, index, &c->v);
  /* the values are the library's structures; only the runner's own keys
     are converted */
  c->model = c->v.model;
  c->traj = c->v.traj;
  if (c->by_ratio) c->model.m = c->v.own.m_over_M * c->model.M;
  if (c->by_blend_ratio)
    c->traj.helix.blend = c->v.own.blend_ratio * c->traj.helix.period;
  if (effects_rule(s, index, c, err)) return -1;

  if (rps3_model_init(&c->model, &chk) != RPS3_OK ||
      (!c->no_traj && rps3_traj_check(&c->model, &c->traj, &chk) != RPS3_OK))
    return scene_case_error(s, index, chk.msg, &chk, -1, NULL, err);
  /* a design study without a task: no trajectory, no time grid */
  if (c->no_traj) return 0;
  c->span = rps3_traj_duration(&c->traj);
  if (s->given[K_SAMPLES]) {
    c->nt = (size_t)c->v.own.samples;
    c->step = c->span / (double)(c->nt - 1);
  } else {
    double q = c->span / c->v.own.dt, n = floor(q + 0.5);
    if (q >= 2147483646.0 || fabs(q - n) > SCENE_WHOLE_RTOL * (q > 1 ? q : 1) ||
        n < 1)
      return dt_error(s, index, c, q, err);
    c->nt = (size_t)n + 1;
    c->step = c->v.own.dt;
  }
  return 0;
}

double scene_case_time(const scene_case *c, size_t k) {
  if (k + 1 >= c->nt) return c->span;
  if (c->by_dt) return (double)k * c->step;
  return c->span * (double)k / (double)(c->nt - 1);
}

int scene_case_same_grid(const scene_case *a, const scene_case *b) {
  return a->nt == b->nt && a->span == b->span && a->step == b->step;
}
