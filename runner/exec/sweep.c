/* sweep.c - see sweep.h: each case computed by case_compute() with a
   workspace of its solver kind into its slot of a block; a job is one or
   more tiles handed to the worker pool. */
#include "sweep.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compute.h"

/* samples in one tile of output: bounds the memory of a run */
#define SWEEP_TILE_POINTS 16384

/* when the time grid differs between cases, a chunk holds at least this
   many samples (cases x times; along time about a twentieth of the mean
   case): the unwritten tail of a case's last chunk stays small, and so
   does the chunk index (about 64 bytes a chunk) beside the data */
#define SWEEP_CHUNK_MIN 128

/* round n up to a multiple of q */
static size_t round_up(size_t n, size_t q) { return (n + q - 1) / q * q; }

/* Cases per job (the rows of a chunk) for at most `most` per job: the
   fewest jobs that share the cases evenly, then more jobs while the last
   chunk row would leave over a twentieth of the rows empty (HDF5 allocates
   an edge chunk whole: 3 cases in jobs of 2 would store 4) */
static size_t plan_tile_cases(size_t ncase, size_t most) {
  size_t njob = (ncase + most - 1) / most, tc;
  for (;; njob++) {
    tc = (ncase + njob - 1) / njob;
    if (tc == 1 || (round_up(ncase, tc) - ncase) * 20 <= ncase) return tc;
  }
}

/* the samples written for a case (or a tile's longest case) of nt
   samples: whole chunks, cut at the time axis */
static size_t plan_extent(const sweep_plan *p, size_t nt) {
  size_t e = round_up(nt, p->chunk_points);
  return e < p->nt ? e : p->nt;
}

/* a candidate layout of a sweep whose cases differ in length, and the
   samples its chunks would store */
typedef struct {
  sweep_plan p;   /* nt, tile_cases, tile_points, chunk_points */
  size_t longest; /* longest case of the current tile */
} layout;

/* tiles of `tc` cases (or windows of `tp` samples) cut into chunks of
   about a twentieth of the mean case along time, and at least
   SWEEP_CHUNK_MIN samples, a whole number per tile */
static void layout_make(layout *l, const sweep_plan *p, size_t tc, size_t tp,
                        size_t mean) {
  size_t target = mean / 20, least = (SWEEP_CHUNK_MIN + tc - 1) / tc, m;
  if (target < least) target = least;
  m = (tp + target - 1) / target;
  l->p = *p;
  l->p.tile_cases = tc;
  l->p.chunk_points = (tp + m - 1) / m;
  l->p.tile_points = m * l->p.chunk_points;
  l->p.stored = 0;
  l->longest = 0;
}

/* add case i of nt samples to the stored samples of layout l */
static void layout_add(layout *l, size_t i, size_t nt, size_t ncase) {
  if (nt > l->longest) l->longest = nt;
  if ((i + 1) % l->p.tile_cases == 0 || i + 1 == ncase) {
    l->p.stored += l->p.tile_cases *
                   round_up(plan_extent(&l->p, l->longest), l->p.chunk_points);
    l->longest = 0;
  }
}

/* The layout of a sweep whose cases differ in length.  A chunk row holds
   tile_cases cases up to the longest of them, so cases of different
   lengths in one tile store the difference: tiles of fewer cases (halving
   down to 1) store less, and more chunks.  Each case is built again (the
   cost of the plan once more, for such sweeps only) to count what each
   layout stores; the first within 5 % of the data is taken, else the one
   that stores least.  0, or -1 with err. */
static int plan_varied(const scene *s, sweep_plan *p, size_t most,
                       scene_error *err) {
  layout l[16];
  size_t nl = 0, i, mean = p->npoint / s->ncase, best = 0;
  scene_case c;
  do {
    size_t tc = plan_tile_cases(s->ncase, most);
    if (nl == 0 || tc < l[nl - 1].p.tile_cases)
      layout_make(&l[nl++], p, tc, p->tile_points, mean);
    most /= 2;
  } while (most >= 1 && nl < 16);
  for (i = 0; i < s->ncase; i++) {
    size_t k;
    if (scene_case_build(s, i, &c, err)) return -1;
    for (k = 0; k < nl; k++) layout_add(&l[k], i, c.nt, s->ncase);
  }
  for (i = 0; i < nl; i++) {
    if (l[i].p.stored <= p->npoint + p->npoint / 20) {
      best = i;
      break;
    }
    if (l[i].p.stored < l[best].p.stored) best = i;
  }
  *p = l[best].p;
  return 0;
}

int sweep_plan_make(const scene *s, sweep_plan *p, scene_error *err) {
  scene_case c;
  size_t i, most = 1;
  memset(p, 0, sizeof *p);
  p->grid_common = 1;
  for (i = 0; i < s->ncase; i++) {
    if (scene_case_build(s, i, i == 0 ? &p->first : &c, err)) return -1;
    if (i == 0) {
      p->nt = p->first.nt;
      p->npoint = p->first.nt;
      continue;
    }
    if (!scene_case_same_grid(&p->first, &c)) p->grid_common = 0;
    if (c.nt > p->nt) p->nt = c.nt;
    p->npoint += c.nt;
  }
  /* whole cases per tile when they fit, else windows of one case; jobs
     share the cases and windows the samples evenly, so that no edge chunk
     is mostly empty (205 cases in tiles of 204 stored 408) */
  if (p->nt <= SWEEP_TILE_POINTS) {
    most = SWEEP_TILE_POINTS / p->nt;
    p->tile_points = p->nt;
    p->tile_cases = plan_tile_cases(s->ncase, most);
  } else {
    size_t nwin = (p->nt + SWEEP_TILE_POINTS - 1) / SWEEP_TILE_POINTS;
    p->tile_points = (p->nt + nwin - 1) / nwin;
    p->tile_cases = 1;
  }
  p->chunk_points = p->tile_points;
  if (!p->grid_common) return plan_varied(s, p, most, err);
  p->stored =
      round_up(s->ncase, p->tile_cases) * round_up(p->nt, p->chunk_points);
  return 0;
}

static int case_begin(const scene *s, size_t index, scene_case *c, char *err,
                      size_t errsz) {
  scene_error e;
  if (scene_case_build(s, index, c, &e)) {
    snprintf(err, errsz, "case %zu became invalid: %s", index, e.what);
    return -1;
  }
  return 0;
}

/* record the outcome of a case in its slot */
static void slot_status(out_block *b, size_t slot, int rc, size_t failed_at) {
  ((int32_t *)b->buf[OUT_status])[slot] = rc;
  ((int32_t *)b->buf[OUT_failed_at])[slot] = rc ? (int32_t)failed_at : -1;
  if (rc) out_block_blank(b, slot, 0);
}

/* set up slot `slot` for case c: its YAML, an empty message, status ok */
static int slot_begin(const scene_case *c, out_block *b, size_t slot, char *err,
                      size_t errsz) {
  if (scene_case_yaml(c, &b->yaml[slot])) {
    snprintf(err, errsz, "case %zu: cannot write its scene as YAML", c->index);
    return -1;
  }
  ((const char **)b->buf[OUT_scene_resolved])[slot] = b->yaml[slot].s;
  ((const char **)b->buf[OUT_message])[slot] = b->msg[slot];
  b->msg[slot][0] = '\0';
  slot_status(b, slot, RPS3_OK, 0);
  return 0;
}

/* "key = value, ..." of case c's swept keys (enums by name), "" without a
   sweep: how messages name a case */
static void sweep_case_label(const scene *s, size_t c, char *buf, size_t sz) {
  size_t a, n = 0;
  buf[0] = '\0';
  for (a = 0; a < s->naxis && n < sz; a++) {
    const scene_axis *ax = &s->axis[a];
    double v = ax->val[scene_case_coord(s, c, a)];
    /* only an enum's values are whole numbers that fit an int */
    const char *name = scene_key_get(ax->key)->type == KEY_ENUM
                           ? scene_enum_name(ax->key, (int)v)
                           : NULL;
    int w = name ? snprintf(buf + n, sz - n, "%s%s = %s", a ? ", " : "",
                            ax->path, name)
                 : snprintf(buf + n, sz - n, "%s%s = %.6g", a ? ", " : "",
                            ax->path, v);
    if (w < 0) break;
    n += (size_t)w;
  }
}

size_t sweep_njob(const scene *s, const sweep_plan *p) {
  return (s->ncase + p->tile_cases - 1) / p->tile_cases;
}

size_t sweep_shard_cases(const scene *s, const sweep_plan *p, size_t shard,
                         size_t nshard) {
  size_t j, n = 0, nj = sweep_njob(s, p);
  for (j = shard; j < nj; j = pool_next(j, nshard, nj))
    n += (j + 1) * p->tile_cases <= s->ncase ? p->tile_cases
                                             : s->ncase - j * p->tile_cases;
  return n;
}

/* a sweep as a job of the pool (pool.h): its items are the jobs of the
   shard, its slots tile blocks */
typedef struct {
  sweep_writer w; /* first: the ctx of sweep_write_tile */
  const sweep_plan *p;
  out_block *b;      /* the caller's block: slot 0 */
  out_layout layout; /* the file's chunks, for out_pack */
} sweep_job;

/* hand the filled tile t of *b to the pool, and take the block to fill
   next into *b: 0, or -1 with err */
static int emit(const sweep_job *J, pool_worker *w, out_block **b,
                const out_tile *t, char *err, size_t errsz) {
  /* on threads, deflate and checksum here, in parallel, not on the writing
     thread.  On one thread and uncompressed, the chunks as the file stores
     them (out_pack: the Fletcher-32 here, full chunks stored from the
     block's own buffers) cost less than HDF5's filter pipeline (a copy of
     the tile into each chunk, another into the filter's buffer);
     compressed, deflate is the cost either way, and -j 1 keeps HDF5's own
     filters.  A late failure's blank windows go through HDF5 too. */
  (*b)->packed = 0;
  if ((pool_threaded(w) || J->layout.gzip == 0) && t->blank_below == 0 &&
      out_pack(&J->layout, *b, t->c0, t->nc, t->k0, t->nk)) {
    snprintf(err, errsz, "cannot pack cases %zu-%zu: out of memory", t->c0,
             t->c0 + t->nc - 1);
    return -1;
  }
  *b = pool_emit(w, t, err, errsz);
  return *b ? 0 : -1;
}

/* job j as a tile of whole cases */
static int job_whole(const sweep_job *J, size_t j, out_block **bp,
                     rps3_data *ws[], pool_worker *w, char *err, size_t errsz) {
  const scene *s = J->w.s;
  out_block *b = *bp;
  out_tile t;
  size_t slot;
  memset(&t, 0, sizeof t);
  t.c0 = j * b->cases;
  t.nc = s->ncase - t.c0 < b->cases ? s->ncase - t.c0 : b->cases;
  t.with_case = 1;
  for (slot = 0; slot < t.nc; slot++) {
    scene_case c;
    rps3_data *d;
    size_t failed_at = 0;
    int rc;
    if (case_begin(s, t.c0 + slot, &c, err, errsz) ||
        slot_begin(&c, b, slot, err, errsz) ||
        !(d = case_workspace(ws, &c, err, errsz)))
      return -1;
    rc = case_compute(&c, d, 0, c.nt, b, slot, &failed_at);
    slot_status(b, slot, rc, failed_at);
    /* samples past the end of a shorter case */
    if (rc == RPS3_OK && c.nt < b->points) out_block_blank(b, slot, c.nt);
    t.points += rc ? failed_at : c.nt;
    /* the samples of the tile's longest case: chunks past it stay
       unallocated (they read as the blanks, the fill values) */
    if (plan_extent(J->p, c.nt) > t.nk) t.nk = plan_extent(J->p, c.nt);
  }
  return emit(J, w, bp, &t, err, errsz);
}

/* job j as one case, in windows of b->points samples; the workspace goes
   from one window to the next (the warm start), the blocks may not */
static int job_windows(const sweep_job *J, size_t j, out_block **bp,
                       rps3_data *ws[], pool_worker *w, char *err,
                       size_t errsz) {
  scene_case c;
  rps3_data *d;
  size_t end;
  int rc = RPS3_OK;
  out_tile t;
  if (case_begin(J->w.s, j, &c, err, errsz) ||
      !(d = case_workspace(ws, &c, err, errsz)))
    return -1;
  /* windows past the case's last chunk are not written */
  end = plan_extent(J->p, c.nt);
  memset(&t, 0, sizeof t);
  t.c0 = j;
  t.nc = 1;
  for (t.k0 = 0; t.k0 < end && rc == RPS3_OK; t.k0 += t.nk) {
    out_block *b = *bp;
    size_t failed_at = 0, ncomp;
    t.nk = end - t.k0 < b->points ? end - t.k0 : b->points;
    ncomp = t.k0 >= c.nt ? 0 : (c.nt - t.k0 < t.nk ? c.nt - t.k0 : t.nk);
    if (slot_begin(&c, b, 0, err, errsz)) return -1;
    if (ncomp > 0) rc = case_compute(&c, d, t.k0, ncomp, b, 0, &failed_at);
    /* a failure: NaN over the windows already written, then stop */
    if (rc != RPS3_OK)
      slot_status(b, 0, rc, failed_at);
    else if (ncomp < t.nk)
      out_block_blank(b, 0, ncomp);
    t.blank_below = rc != RPS3_OK ? t.k0 : 0;
    t.with_case = rc != RPS3_OK || t.k0 + t.nk >= end;
    t.points = rc != RPS3_OK ? failed_at - t.k0 : ncomp;
    if (emit(J, w, bp, &t, err, errsz)) return -1;
  }
  return 0;
}

/* pool_job.run: job j of the sweep on worker w (a tile of whole cases, or
   one long case in windows); ws holds the workspaces, one per solver
   kind, allocated on first use */
static int sweep_item(void *ctx, void *wctx, size_t j, pool_worker *w,
                      char *err, size_t errsz) {
  const sweep_job *J = ctx;
  out_block *b = pool_slot(w);
  return J->p->tile_cases == 1 && J->p->nt > J->p->tile_points
             ? job_windows(J, j, &b, wctx, w, err, errsz)
             : job_whole(J, j, &b, wctx, w, err, errsz);
}

int sweep_write_tile(void *ctx, void *slot, const void *info, char *err,
                     size_t errsz) {
  const sweep_writer *W = ctx;
  const out_block *b = slot;
  const out_tile *t = info;
  size_t k;
  char what[512] = "";
  if (out_write(W->f, b, t, err, errsz)) return -1;
  /* the cases a tile completes are those it writes the per-case fields
     of; the first failure is said once (its label made once) */
  for (k = 0; t->with_case && k < t->nc; k++)
    if (((const int32_t *)b->buf[W->status])[k] != RPS3_OK) {
      if (W->label && !W->pr->failure_shown)
        sweep_case_label(W->s, t->c0 + k, what, sizeof what);
      progress_failure(W->pr, t->c0 + k, what,
                       ((char *const *)b->buf[W->message])[k]);
      W->st->nfailed++;
    }
  W->st->cases_done += t->with_case ? t->nc : 0;
  W->st->points_done += t->points;
  progress_update(W->pr, W->st->cases_done, W->st->points_done);
  return 0;
}

/* a worker's workspaces, one per solver kind, allocated on first use */
static void *workspaces_begin(void *ctx) {
  (void)ctx;
  return calloc(RPS3_NSOLVER, sizeof(rps3_data *));
}

static void workspaces_end(void *ctx, void *wctx) {
  (void)ctx;
  if (wctx) case_workspaces_free(wctx);
  free(wctx);
}

/* pool_job.slot_make: slot 0 is the caller's block, lent for the run; the
   others are allocated like it */
static int block_make(void *ctx, void *slot, size_t i) {
  const sweep_job *J = ctx;
  out_block *b = slot;
  if (i == 0) {
    *b = *J->b;
    return 0;
  }
  if (out_block_alloc(b, OUT_INV, J->b->cases, J->b->points,
                      J->p->first.model.opt.effects))
    return -1;
  b->fields = J->b->fields;
  return 0;
}

/* pool_job.slot_free: the lent block back (with the buffers out_pack grew) */
static void block_free(void *ctx, void *slot, size_t i) {
  const sweep_job *J = ctx;
  if (i == 0)
    *J->b = *(out_block *)slot;
  else
    out_block_free(slot);
}

int sweep_run_opts(const scene *s, const sweep_plan *p, out_file *f,
                   out_block *b, const sweep_opts *o, progress *pr,
                   sweep_stats *st, char *err, size_t errsz) {
  sweep_job J = {{s, f, pr, st, OUT_status, OUT_message, 1}, p, b, f->layout};
  pool_job job = {.ctx = &J,
                  .nitem = sweep_njob(s, p),
                  .first = o->shard,
                  .stride = o->nshard,
                  .info_size = sizeof(out_tile),
                  .slot_size = sizeof(out_block),
                  .slot_make = block_make,
                  .slot_free = block_free,
                  .worker_begin = workspaces_begin,
                  .worker_end = workspaces_end,
                  .run = sweep_item,
                  .write = sweep_write_tile};
  memset(st, 0, sizeof *st);
  if (o->nshard < 1 || o->shard >= o->nshard || o->nthread < 1) {
    snprintf(err, errsz, "bad shard %zu/%zu or thread count %d", o->shard,
             o->nshard, o->nthread);
    return -1;
  }
  snprintf(err, errsz, "out of memory");
  return pool_run(&job, o->nthread, err, errsz);
}
