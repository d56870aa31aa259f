/*
 * design.c - the design keys (SCENE_KEYS, scene.h) against the scene: the
 * checks after the whole file is read (scene_design_check_keys), and each
 * design of a design study built and checked (design.h).
 */
#include "design.h"
#include "scene.h"
#include "scene_int.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int design_wanted(const scene *s) { return s->design.line > 0; }

void design_grid(const scene *s, rps3_design_grid *gr) {
  int ax;
  for (ax = 0; ax < 3; ax++) {
    const double *g = s->base.des.grid[ax];
    gr->lo[ax] = g[0];
    gr->hi[ax] = g[1];
    gr->n[ax] = (size_t)g[2];
  }
}

/* grid key ax (alpha, beta, z_c): lo <= hi, cells a whole number >= 1,
   and the grid at most DESIGN_MAX_POSES poses */
static int check_grid(const scene *s, int ax, double *poses, scene_error *err) {
  int k = K_DES_ALPHA + ax;
  const double *g = s->base.des.grid[ax];
  const char *path = scene_keys[k].path;
  char a[32], b[32];
  scene_format_real(a, sizeof a, g[0]);
  scene_format_real(b, sizeof b, g[1]);
  if (g[2] != floor(g[2]) || g[2] < 1)
    return scene_error_set(
        err, s->mark[k], path,
        "cells = %g: [lo, hi, cells] needs a whole number of cells >= 1", g[2]);
  if (!(g[0] <= g[1]))
    return scene_error_set(
        err, s->mark[k], path,
        "lo = %s is above hi = %s: the range [lo, hi, cells] is inverted", a,
        b);
  *poses *= g[2];
  if (*poses > DESIGN_MAX_POSES)
    return scene_error_set(err, s->mark[k], path,
                           "the grid has more than %.0f poses",
                           DESIGN_MAX_POSES);
  return 0;
}

/* the library field each design field that is not a design key is made
   of (design_of_case) */
static const int model_field[][2] = {
    {RPS3_DF_R, RPS3_F_R},
    {RPS3_DF_RHO, RPS3_F_RHO},
    {RPS3_DF_M, RPS3_F_PLATFORM_MASS},
    {RPS3_DF_PAYLOAD, RPS3_F_PAYLOAD_MASS},
    {RPS3_DF_PAYLOAD_HEIGHT, RPS3_F_PAYLOAD_COM},
    {RPS3_DF_ACTUATOR_MASS, RPS3_F_LINK_MASS},
    {RPS3_DF_ACTUATOR_D, RPS3_F_D},
    {RPS3_DF_G, RPS3_F_G}};
#define NMODEL_FIELD (sizeof model_field / sizeof model_field[0])

/* a design's model is rps3_design_model's: of the manipulator, solver and
   effects keys it reads those that fill a design field, and a design
   study refuses the others rather than ignore them */
int design_key_unread(int k) {
  const scene_key_info *ki = &scene_keys[k];
  size_t i;
  if ((ki->src != SRC_LIB && ki->src != SRC_OWN && ki->src != SRC_LEGS) ||
      strncmp(ki->path, "trajectory.", 11) == 0)
    return 0;
  for (i = 0; i < NMODEL_FIELD; i++)
    if (model_field[i][1] == ki->fills) return 0;
  return 1;
}

int scene_design_check_keys(const scene *s, scene_error *err) {
  int k, ax;
  size_t a;
  double poses = 1;
  if (!design_wanted(s)) {
    /* a design key in a scene that computes no design would be ignored */
    for (k = 0; k < SCENE_NKEY; k++)
      if (SCENE_KEY_IS_DESIGN(&scene_keys[k]) && s->given[k])
        return scene_error_set(
            err, s->mark[k], scene_keys[k].path,
            "only a design study reads this key: add a design section "
            "(docs/runner.md, \"Design studies\")");
    return 0;
  }
  if (s->simulate.line > 0)
    return scene_error_set(err, s->design, "design",
                           "a scene is a design study or a simulation, not "
                           "both (simulate section at %d:%d)",
                           s->simulate.line, s->simulate.column);
  for (k = 0; k < SCENE_NKEY; k++)
    if (s->given[k] && design_key_unread(k))
      return scene_error_set(
          err, s->mark[k], scene_keys[k].path,
          "a design study does not read this key: its model is "
          "rps3_design_model's (the link inertia from the mass model, the "
          "default effects and solver; docs/runner.md, \"Design studies\")");
  /* the design's payload is a point on the platform normal */
  if (s->given[K_PAY_COM] &&
      (s->base.model.payload.com[0] != 0 || s->base.model.payload.com[1] != 0))
    goto off_axis;
  for (a = 0; a < s->naxis; a++)
    if (s->axis[a].key == K_PAY_COM && s->axis[a].comp != 2) goto off_axis;
  for (k = 0; k < SCENE_NKEY; k++)
    if (SCENE_KEY_IS_DESIGN(&scene_keys[k]) && scene_keys[k].req == REQ_YES &&
        !s->given[k])
      return scene_error_set(
          err, scene_keys[k].src == SRC_DES ? s->section[1] : s->design,
          scene_keys[k].path, "missing required key of a design study");
  for (a = 0; a < s->naxis; a++) {
    k = s->axis[a].key;
    if ((k >= K_DES_ALPHA && k <= K_DES_Z_C) || k == K_DES_PER_POSE)
      return scene_error_set(err, s->axis[a].mark[0], s->axis[a].path,
                             "cannot be swept (it decides the shape of the "
                             "file); write one scene per value");
    if (s->section[2].line == 0 &&
        strncmp(scene_keys[k].path, "trajectory.", 11) == 0)
      return scene_error_set(err, s->axis[a].mark[0], s->axis[a].path,
                             "the design study has no trajectory section (no "
                             "task): nothing reads this key");
  }
  for (ax = 0; ax < 3; ax++)
    if (check_grid(s, ax, &poses, err)) return -1;
  /* the volume of a cell in (alpha, beta, z_c): the workspace volume is
     counted in it */
  {
    rps3_design_grid gr;
    double v = 0;
    design_grid(s, &gr);
    if (rps3_design_grid_cell(&gr, &v) != RPS3_OK || !isfinite(v))
      return scene_error_set(
          err, s->design, "design",
          "the volume of a grid cell, (hi - lo) / cells of alpha, beta and z_c "
          "multiplied, is not a finite number: not a grid of poses");
  }
  return 0;
off_axis:
  return scene_error_set(err, s->mark[K_PAY_COM], scene_keys[K_PAY_COM].path,
                         "a design's payload is a point on the platform "
                         "normal: give [0, 0, height] (and sweep only [2])");
}

/* 1 when key k is swept */
static int swept(const scene *s, int k) {
  size_t a;
  for (a = 0; a < s->naxis; a++)
    if (s->axis[a].key == k) return 1;
  return 0;
}

/* the key to point at among a and b: a swept one, else the later in the
   file */
static int blame_of(const scene *s, int a, int b) {
  if (swept(s, a) != swept(s, b)) return swept(s, a) ? a : b;
  if (!s->given[a]) return b;
  if (!s->given[b]) return a;
  return scene_mark_after(s->mark[a], s->mark[b]) ? a : b;
}

/* a range [lo, hi] (keys klo, khi) that must have lo < hi: 0, or -1 with
   err at the key that makes it wrong */
static int check_range(const scene *s, size_t index, int klo, int khi,
                       double lo, double hi, const char *name, const char *unit,
                       scene_error *err) {
  char a[32], b[32], what[256];
  if (lo < hi) return 0;
  scene_format_real(a, sizeof a, lo);
  scene_format_real(b, sizeof b, hi);
  snprintf(what, sizeof what,
           "%s [min, max] = [%s, %s] %s is %s: needs min < max", name, a, b,
           unit, lo == hi ? "empty" : "inverted");
  return scene_case_error(s, index, what, NULL, blame_of(s, klo, khi),
                          &s->design, err);
}

/* the scene key that sets design field id in scene s: its design key, or
   the key (given, if any) that fills its library field */
static int key_of_field(const scene *s, int id) {
  int k, lib = -1, first = -1;
  size_t i;
  for (i = 0; i < NMODEL_FIELD; i++)
    if (model_field[i][0] == id) lib = model_field[i][1];
  for (k = 0; k < SCENE_NKEY; k++) {
    if (scene_keys[k].dfield == id && id >= 0) return k;
    if (lib >= 0 && scene_keys[k].fills == lib && first < 0) first = k;
    if (lib >= 0 && scene_keys[k].fills == lib && s->given[k]) return k;
  }
  return first >= 0 ? first : K_DES_STROKE_MIN;
}

void design_of_case(const scene_case *c, rps3_design *d) {
  *d = c->v.design;
  d->R = c->model.R;
  d->rho = c->model.rho;
  d->M = c->model.M;
  d->payload = c->model.payload.mass;
  d->payload_height = c->model.payload.com[2];
  d->actuator_mass = c->model.m;
  d->actuator_d = c->model.d;
  d->g = c->model.g;
}

int design_case_build(const scene *s, size_t index, scene_case *c,
                      scene_error *err) {
  rps3_design d;
  rps3_model scratch; /* the design's model, not kept */
  rps3_check chk;
  const rps3_design *v;
  if (scene_case_build(s, index, c, err)) return -1;
  v = &c->v.design;
  /* the ranges, named by their keys; then every rule of the library */
  if (check_range(s, index, K_DES_STROKE_MIN, K_DES_STROKE_MAX, v->l_min,
                  v->l_max, "the stroke", "m", err) ||
      check_range(s, index, K_DES_PIN_MIN, K_DES_PIN_MAX, v->theta_min,
                  v->theta_max, "the pin range", "rad", err))
    return -1;
  design_of_case(c, &d);
  if (rps3_design_model(&d, &scratch, &chk) != RPS3_OK) {
    int k = key_of_field(s, chk.field);
    if (chk.related[0] >= 0)
      k = blame_of(s, k, key_of_field(s, chk.related[0]));
    return scene_case_error(s, index, chk.msg, NULL, k, &s->design, err);
  }
  return 0;
}
