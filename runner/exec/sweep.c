/* sweep.c - see sweep.h: the plan, the per-sample pipeline (a case into
   its slot of a block with a workspace of its solver kind) and the jobs,
   each one or more tiles handed to the worker pool. */
#include "sweep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* samples in one tile of output: bounds the memory of a run */
#define SWEEP_TILE_POINTS 16384

/* when the time grid differs between cases, a chunk holds at least this
   many samples (cases x times; along time about a twentieth of the mean
   case): the unwritten tail of a case's last chunk stays small, and so
   does the chunk index (about 64 bytes a chunk) beside the data */
#define SWEEP_CHUNK_MIN 128

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

/* the trajectory could not be evaluated at sample k (time t) */
static int traj_failed(out_block *b, size_t slot, int rc, double t, size_t k,
                       const double pose[3], const double dpose[3],
                       const double ddpose[3], size_t *failed_at) {
  /* rps3_traj_eval has no data to hold a message: name what failed */
  *failed_at = k;
  snprintf(b->msg[slot], sizeof b->msg[slot],
           "t = %.9g s (sample %zu): %s: trajectory pose (%g, %g, %g), "
           "rate (%g, %g, %g), acceleration (%g, %g, %g)",
           t, k, rps3_strerror(rc), pose[0], pose[1], pose[2], dpose[0],
           dpose[1], dpose[2], ddpose[0], ddpose[1], ddpose[2]);
  return rc;
}

/* dst[stride i + c] = src[c n + i]: a [3][n] array of the batch into
   the block's rows of `stride` values */
static void store3(double *dst, const double *src, size_t n, size_t stride) {
  size_t i;
  for (i = 0; i < n; i++) {
    dst[stride * i] = src[i];
    dst[stride * i + 1] = src[n + i];
    dst[stride * i + 2] = src[2 * n + i];
  }
}

/* the batch of n points into samples j .. j + n - 1 of the block, one
   field at a time (each a sequential stream of writes), the fields the
   file gets; the batch wrote condition, transmission, the energy residual
   and scale and the solve residual into the block itself */
static void store_batch(const rps3_batch_in *in, const rps3_batch_out *x,
                        out_block *b, size_t j) {
  const size_t n = in->n;
  /* the [3][n] outputs, and the one-column ones */
  const struct {
    int field;
    const double *src;
  } three[] = {{OUT_force, x->F},        {OUT_length, x->l},
               {OUT_theta, x->theta},    {OUT_lambda, x->lambda},
               {OUT_length_rate, x->dl}, {OUT_length_accel, x->ddl}},
    one[] = {{OUT_alpha, in->pose},
             {OUT_beta, in->pose + n},
             {OUT_z_c, in->pose + 2 * n},
             {OUT_x_c, x->c},
             {OUT_y_c, x->c + n}};
  const size_t ne = (size_t)b->neffect;
  double *fe = (double *)b->buf[OUT_force_by_effect] + j * ne * 3;
  int32_t *niter = (int32_t *)b->buf[OUT_solve_niter] + j,
          *warn = (int32_t *)b->buf[OUT_warn] + j;
  size_t i, e, f;
  for (f = 0; f < sizeof three / sizeof three[0]; f++)
    if (OUT_HAS(b->fields, three[f].field))
      store3((double *)b->buf[three[f].field] + 3 * j, three[f].src, n, 3);
  for (f = 0; f < sizeof one / sizeof one[0]; f++)
    if (OUT_HAS(b->fields, one[f].field))
      memcpy((double *)b->buf[one[f].field] + j, one[f].src,
             n * sizeof(double));
  for (e = 0; e < ne && OUT_HAS(b->fields, OUT_force_by_effect); e++)
    store3(fe + 3 * e, x->F_effect + (size_t)b->effect[e] * 3 * n, n, 3 * ne);
  memcpy(b->t + j, b->bx, n * sizeof(double));
  for (i = 0; i < n; i++) {
    niter[i] = x->niter[i];
    warn[i] = x->warn[i];
  }
}

/* the batch's scratch in b->bx: the times, then OUT_BATCH points of each
   array, structure of arrays */
#define POSE(b) ((b)->bx + OUT_BATCH)
#define DPOSE(b) (POSE(b) + 3 * OUT_BATCH)
#define DDPOSE(b) (DPOSE(b) + 3 * OUT_BATCH)

/* the trajectory at samples k .. k + n - 1 into b's scratch, up to a
   sample it cannot give: returns the samples it gave (the batch, packed
   to their number) and the status of the one after in *trc, its pose and
   rates in p, dp, ddp */
static size_t batch_traj(const scene_case *c, out_block *b, size_t k, size_t n,
                         int *trc, double p[3], double dp[3], double ddp[3]) {
  /* the pose, its rate and acceleration: [3][n] each, 3 OUT_BATCH apart */
  double *t = b->bx, *pose = POSE(b);
  const double *val[3] = {p, dp, ddp};
  size_t i, q, a;
  *trc = RPS3_OK;
  for (i = 0; i < n; i++) {
    t[i] = scene_case_time(c, k + i);
    *trc = rps3_traj_eval(&c->model, &c->traj, t[i], p, dp, ddp);
    if (*trc != RPS3_OK) break;
    for (a = 0; a < 3; a++)
      for (q = 0; q < 3; q++) pose[3 * OUT_BATCH * a + q * n + i] = val[a][q];
  }
  /* the i samples before a failure, packed to a batch of i */
  for (a = 0; i < n && a < 3; a++)
    for (q = 1; q < 3; q++)
      memmove(pose + 3 * OUT_BATCH * a + q * i,
              pose + 3 * OUT_BATCH * a + q * n, i * sizeof(double));
  return i;
}

/* the batch's inputs and outputs: the scratch after the poses, and the
   per-point values of one column straight into the block at row j */
static void batch_io(out_block *b, size_t n, size_t j, rps3_batch_in *in,
                     rps3_batch_out *out) {
  double *p = DDPOSE(b) + 3 * OUT_BATCH;
  memset(in, 0, sizeof *in);
  memset(out, 0, sizeof *out);
  in->n = n;
  in->pose = POSE(b);
  in->dpose = DPOSE(b);
  in->ddpose = DDPOSE(b);
  out->l = p;
  out->theta = p += 3 * OUT_BATCH;
  out->F = p += 3 * OUT_BATCH;
  out->lambda = p += 3 * OUT_BATCH;
  out->F_effect = p += 3 * OUT_BATCH;
  out->dl = p += 3 * RPS3_NEFFECT * OUT_BATCH;
  out->ddl = p += 3 * OUT_BATCH;
  out->c = p + 3 * OUT_BATCH;
  out->status = b->bi;
  out->warn = b->bi + OUT_BATCH;
  out->niter = b->bi + 2 * OUT_BATCH;
  out->cond = (double *)b->buf[OUT_condition] + j;
  out->energy_residual = (double *)b->buf[OUT_energy_residual] + j;
  out->transmission = (double *)b->buf[OUT_transmission] + j;
  out->energy_scale = (double *)b->buf[OUT_energy_scale] + j;
  out->solve_resid = (double *)b->buf[OUT_solve_resid] + j;
}

/* the batch failed with rc at sample k + i: the case's message, without
   the batch's "point I: " */
static int batch_failed(const rps3_data *d, int rc, size_t k, size_t i,
                        out_block *b, size_t slot, size_t *failed_at) {
  const char *msg = d->err.msg, *colon = strstr(msg, ": ");
  if (strncmp(msg, "point ", 6) == 0 && colon) msg = colon + 2;
  *failed_at = k + i;
  snprintf(b->msg[slot], sizeof b->msg[slot], "t = %.9g s (sample %zu): %s: %s",
           b->bx[i], k + i, rps3_strerror(rc), msg);
  return rc;
}

/* case_compute: the samples OUT_BATCH at a time through rps3_inverse_batch,
   which runs the vectorised kernel where it applies (closed-form theta,
   Lagrange, the paper's effects: the numbers agree with rps3_inverse to
   rounding, docs/library.md) and the per-point loop elsewhere (bitwise).  A
   case still stops at its first failing sample, with the same message. */
int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at) {
  size_t k, n;
  if (k0 == 0) rps3_data_reset(d);
  for (k = k0; k < k0 + nk; k += n) {
    rps3_batch_in in;
    rps3_batch_out out;
    double p[3], dp[3], ddp[3];
    const size_t j = slot * b->points + (k - k0);
    int trc, rc;
    /* the trajectory up to a sample it cannot give: the samples before it
       are computed first, and one of them failing is the case's first
       failure */
    n = k0 + nk - k < OUT_BATCH ? k0 + nk - k : OUT_BATCH;
    n = batch_traj(c, b, k, n, &trc, p, dp, ddp);
    if (n == 0)
      return traj_failed(b, slot, trc, b->bx[0], k, p, dp, ddp, failed_at);
    batch_io(b, n, j, &in, &out);
    rc = rps3_inverse_batch(&c->model, d, &in, &out);
    if (rc == RPS3_OK && out.nfail) rc = out.status[out.first_fail];
    if (rc != RPS3_OK)
      return batch_failed(d, rc, k, out.nfail ? out.first_fail : 0, b, slot,
                          failed_at);
    if (trc != RPS3_OK)
      return traj_failed(b, slot, trc, b->bx[n], k + n, p, dp, ddp, failed_at);
    store_batch(&in, &out, b, j);
  }
  return RPS3_OK;
}

rps3_data *case_workspace(rps3_data *ws[RPS3_NSOLVER], const scene_case *c,
                          char *err, size_t errsz) {
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

void case_workspaces_free(rps3_data *ws[RPS3_NSOLVER]) {
  int k;
  for (k = 0; k < RPS3_NSOLVER; k++) rps3_data_free(ws[k]);
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
     thread; on one thread and uncompressed, out_pack (full chunks stored
     from the block's own buffers) costs less than HDF5's filters (two
     copies of the tile); compressed, -j 1 keeps HDF5's filters, as do a
     late failure's blank windows. */
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

/* pool_job.run: job j on worker w, a tile of whole cases or one long case
   in windows (wctx: the workspaces, one per solver kind) */
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
