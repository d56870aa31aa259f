/*
 * sweep.c - see sweep.h.  Each case is computed by case_compute() with a
 * workspace of its own solver kind into its own slot of the block, so the
 * cases of a tile are independent of each other.
 */
#include "sweep.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "compute.h"

int sweep_plan_make(const scene *s, sweep_plan *p, scene_error *err)
{
  scene_case c;
  size_t i;
  memset(p, 0, sizeof *p);
  p->grid_common = 1;
  for (i = 0; i < s->ncase; i++) {
    if (scene_case_build(s, i, i == 0 ? &p->first : &c, err))
      return -1;
    if (i == 0) {
      p->nt = p->first.nt;
      p->npoint = p->first.nt;
      continue;
    }
    if (!scene_case_same_grid(&p->first, &c))
      p->grid_common = 0;
    if (c.nt > p->nt)
      p->nt = c.nt;
    p->npoint += c.nt;
  }
  /* whole cases per tile when they fit, else windows of one case */
  if (p->nt <= SWEEP_TILE_POINTS) {
    p->tile_points = p->nt;
    p->tile_cases = SWEEP_TILE_POINTS / p->nt;
    if (p->tile_cases > s->ncase)
      p->tile_cases = s->ncase;
  } else {
    p->tile_points = SWEEP_TILE_POINTS;
    p->tile_cases = 1;
  }
  return 0;
}

/* the workspace for case c: one per solver kind, allocated on first use */
static rps3_data *workspace(rps3_data *ws[RPS3_NSOLVER], const scene_case *c,
                            char *err, size_t errsz)
{
  int k = (int)c->model.opt.solver;
  if (!ws[k]) {
    int rc = rps3_data_alloc(&c->model, &ws[k]);
    if (rc != RPS3_OK) {
      snprintf(err, errsz, "cannot allocate a workspace: %s",
               rps3_strerror(rc));
      return NULL;
    }
  }
  return ws[k];
}

/* set up slot `slot` for case `index`: build it, its YAML, empty message */
static int slot_begin(const scene *s, size_t index, out_block *b, size_t slot,
                      scene_case *c, char *err, size_t errsz)
{
  scene_error e;
  if (scene_case_build(s, index, c, &e)) {
    snprintf(err, errsz, "case %zu became invalid: %s", index, e.what);
    return -1;
  }
  if (scene_case_yaml(c, &b->yaml[slot])) {
    snprintf(err, errsz, "case %zu: cannot write its scene as YAML", index);
    return -1;
  }
  ((const char **)b->scene_resolved)[slot] = b->yaml[slot].s;
  ((const char **)b->message)[slot] = b->msg[slot];
  b->msg[slot][0] = '\0';
  ((int32_t *)b->status)[slot] = RPS3_OK;
  ((int32_t *)b->failed_at)[slot] = -1;
  return 0;
}

/* record the outcome of a case in its slot */
static void slot_status(out_block *b, size_t slot, int rc, size_t failed_at,
                        sweep_stats *st)
{
  ((int32_t *)b->status)[slot] = rc;
  ((int32_t *)b->failed_at)[slot] = rc ? (int32_t)failed_at : -1;
  if (rc) {
    st->nfailed++;
    out_block_blank(b, slot, 0);
  }
}

/* tiles of whole cases */
static int run_whole(const scene *s, const sweep_plan *p, out_file *f,
                     out_block *b, rps3_data *ws[], progress *pr,
                     sweep_stats *st, char *err, size_t errsz)
{
  size_t c0, nc, slot;
  for (c0 = 0; c0 < s->ncase; c0 += nc) {
    nc = s->ncase - c0 < b->cases ? s->ncase - c0 : b->cases;
    for (slot = 0; slot < nc; slot++) {
      scene_case c;
      rps3_data *d;
      size_t failed_at = 0;
      int rc;
      if (slot_begin(s, c0 + slot, b, slot, &c, err, errsz) ||
          !(d = workspace(ws, &c, err, errsz)))
        return -1;
      rc = case_compute(&c, d, 0, c.nt, b, slot, &failed_at);
      slot_status(b, slot, rc, failed_at, st);
      /* samples past the end of a shorter case */
      if (rc == RPS3_OK && c.nt < b->points)
        out_block_blank(b, slot, c.nt);
      st->points_done += rc ? failed_at : c.nt;
    }
    if (out_write(f, b, c0, nc, 0, p->nt, 1, err, errsz))
      return -1;
    st->cases_done += nc;
    progress_update(pr, st->cases_done, st->points_done);
  }
  return 0;
}

/* one case at a time, in windows of b->points samples */
static int run_windows(const scene *s, const sweep_plan *p, out_file *f,
                       out_block *b, rps3_data *ws[], progress *pr,
                       sweep_stats *st, char *err, size_t errsz)
{
  size_t i, k0, nk, w;
  for (i = 0; i < s->ncase; i++) {
    scene_case c;
    rps3_data *d;
    if (slot_begin(s, i, b, 0, &c, err, errsz) ||
        !(d = workspace(ws, &c, err, errsz)))
      return -1;
    for (k0 = 0; k0 < p->nt; k0 += nk) {
      size_t failed_at = 0, ncomp;
      int rc = RPS3_OK, last;
      nk = p->nt - k0 < b->points ? p->nt - k0 : b->points;
      ncomp = k0 >= c.nt ? 0 : (c.nt - k0 < nk ? c.nt - k0 : nk);
      if (ncomp > 0)
        rc = case_compute(&c, d, k0, ncomp, b, 0, &failed_at);
      if (rc != RPS3_OK) {
        /* NaN over the windows already written, then stop the case */
        slot_status(b, 0, rc, failed_at, st);
        for (w = 0; w < k0; w += b->points)
          if (out_write(f, b, i, 1, w, b->points, 0, err, errsz))
            return -1;
        if (out_write(f, b, i, 1, k0, nk, 1, err, errsz))
          return -1;
        st->points_done += failed_at - k0;
        break;
      }
      if (ncomp < nk)
        out_block_blank(b, 0, ncomp);
      last = k0 + nk >= p->nt;
      if (out_write(f, b, i, 1, k0, nk, last, err, errsz))
        return -1;
      st->points_done += ncomp;
      progress_update(pr, st->cases_done, st->points_done);
    }
    st->cases_done++;
  }
  return 0;
}

int sweep_run(const scene *s, const sweep_plan *p, out_file *f,
              out_block *b, progress *pr, sweep_stats *st, char *err,
              size_t errsz)
{
  rps3_data *ws[RPS3_NSOLVER];
  int k, rc;
  memset(st, 0, sizeof *st);
  memset(ws, 0, sizeof ws);
  rc = b->cases > 1 || p->nt <= b->points
           ? run_whole(s, p, f, b, ws, pr, st, err, errsz)
           : run_windows(s, p, f, b, ws, pr, st, err, errsz);
  for (k = 0; k < RPS3_NSOLVER; k++)
    rps3_data_free(ws[k]);
  return rc;
}
