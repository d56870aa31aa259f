/* design_run.c - see design_run.h. */
#include "design_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "estimate.h"

int design_plan_make(const scene *s, design_plan *p, scene_error *err) {
  scene_case c;
  size_t i, per;
  memset(p, 0, sizeof *p);
  p->ncase = s->ncase;
  design_grid(s, &p->gr);
  p->npose = rps3_design_grid_size(&p->gr);
  p->task = s->section[2].line > 0;
  p->per_pose = s->base.des.per_pose;
  p->files = OUT_DES | (p->task ? OUT_TASK : 0) | (p->per_pose ? OUT_POSE : 0);
  /* every design is checked before anything is written */
  for (i = 0; i < s->ncase; i++) {
    if (design_case_build(s, i, &c, err)) return -1;
    /* the task's samples: one grid for every design (the sweep may not
       change the trajectory's span) */
    if (p->task && c.nt > p->nsample) p->nsample = c.nt;
  }
  /* work units: about DESIGN_UNIT_POSES poses each, the designs shared
     evenly */
  per = DESIGN_UNIT_POSES / (p->npose + p->nsample);
  if (per < 1) per = 1;
  p->nunit = (p->ncase + per - 1) / per;
  p->unit = (p->ncase + p->nunit - 1) / p->nunit;
  return 0;
}

size_t design_shard_cases(const design_plan *p, size_t k, size_t n) {
  size_t j, c = 0;
  for (j = k; j < p->nunit; j = pool_next(j, n, p->nunit))
    c += (j + 1) * p->unit < p->ncase ? p->unit : p->ncase - j * p->unit;
  return c;
}

/* a design study as a job of the pool (pool.h): its items are this
   shard's work units, its slots tiles of one unit's designs */
typedef struct {
  sweep_writer w; /* first: the ctx of sweep_write_tile */
  const design_plan *p;
  size_t *nempty;
} design_job;

/* reset slot j of tile t: the fill values, no strings (a tile's strings
   are its own) */
static void tile_clear(out_block *t, size_t j) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++) {
    size_t n = out_columns(out_field_table[i].shape, t->points);
    if (t->buf[i] && out_field_table[i].type == OUT_STR) {
      free(((char **)t->buf[i])[j]);
      ((char **)t->buf[i])[j] = NULL;
    } else if (t->buf[i])
      out_fill_n(
          (char *)t->buf[i] + j * n * out_type_size(out_field_table[i].type), n,
          i);
  }
}

/* pool_job.slot_make, slot_free: a tile of one unit's designs (of
   p->unit designs of p->npose poses) */
static int tile_make(void *ctx, void *slot, size_t i) {
  const design_plan *p = ((const design_job *)ctx)->p;
  out_block *t = slot;
  if (out_block_alloc(t, p->files, p->unit, p->npose, 0)) return -1;
  for (i = 0; i < p->unit; i++) tile_clear(t, i);
  return 0;
}

static void tile_free(void *ctx, void *slot, size_t i) {
  out_block *t = slot;
  (void)ctx;
  for (i = 0; t->yaml && i < t->cases; i++) tile_clear(t, i);
  out_block_free(t);
}

/* bytes of the file, uncompressed (an upper bound with --gzip): the
   designs' variables (a message about 64 bytes), their scene_resolved
   (about the scene's size), the swept keys, HDF5's metadata (a bound) */
static double design_file_bytes(const scene *s, const design_plan *p) {
  double row = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (out_field_table[i].files & p->files)
      row += (double)out_columns(out_field_table[i].shape, p->npose) *
             (out_field_table[i].type == OUT_STR
                  ? 64.0
                  : (double)out_type_size(out_field_table[i].type));
  return (double)p->ncase *
             (row + (double)s->text_len + 8.0 * (double)(s->naxis + 1)) +
         65536.0;
}

out_file *design_file_open(const char *path, const scene *s,
                           const design_plan *p, const out_meta *meta,
                           char *err, size_t errsz) {
  out_spec sp;
  memset(&sp, 0, sizeof sp);
  sp.files = p->files;
  sp.title =
      "rps3: design study of the Lee & Shah 3-RPS manipulator, indices per "
      "design over a grid of poses";
  sp.content = "design";
  sp.grid_common = 1;
  sp.tile_cases = sp.case_chunk = p->unit < p->ncase ? p->unit : p->ncase;
  return out_open(path, s, &sp, meta, err, errsz);
}

/* what a worker needs: a workspace and the arrays of one design's poses */
typedef struct {
  rps3_design_ws *ws;
  int *flags; /* npose */
  double *c;  /* 3 npose */
  scene_text yaml;
} worker_ws;

/* pool_job.worker_end, worker_begin */
static void worker_free(void *ctx, void *wctx) {
  worker_ws *w = wctx;
  (void)ctx;
  if (!w) return;
  rps3_design_ws_free(w->ws);
  free(w->flags);
  free(w->c);
  scene_text_free(&w->yaml);
  free(w);
}

static void *worker_new(void *ctx) {
  size_t npose = ((const design_job *)ctx)->p->npose;
  worker_ws *w = calloc(1, sizeof *w);
  if (w && (!(w->flags = malloc(npose * sizeof *w->flags)) ||
            !(w->c = malloc(3 * npose * sizeof *w->c)) ||
            rps3_design_ws_alloc(&w->ws) != RPS3_OK)) {
    worker_free(ctx, w);
    w = NULL;
  }
  return w;
}

/* the summaries of rps3_design_summary that are variables of their name,
   the task's per-link statistics of rps3_design_task (task_NAME), and the
   per-pose arrays of rps3_design_out (the variable's id) */
#define SUM_FIELDS(X) \
  X(reach_fraction)   \
  X(volume)           \
  X(gti)              \
  X(good_fraction)    \
  X(lti_min)          \
  X(cond_h_max) X(trans_max) X(xc_max) X(yc_max) X(spin_max) X(l_lo) X(l_hi)
#define TASK_LINK_FIELDS(X) \
  X(F_peak) X(F_rms) X(P_peak) X(v_peak) X(l_lo) X(l_hi)
#define POSE_FIELDS(X) \
  X(lti, lti)          \
  X(oti, oti)          \
  X(cti, cti)          \
  X(cond_h, cond_h)    \
  X(transmission, des_transmission) X(spin, spin) X(clearance, clearance)

/* design slot j failed with status rc: why */
static void design_failed(out_block *t, size_t j, int rc, const char *why) {
  OUT_I(t, des_status)[j] = rc;
  OUT_S(t, des_message)[j] = strdup(why);
}

/* the summary of a design's grid and its model into slot j */
static void store_summary(out_block *t, size_t j,
                          const rps3_design_summary *sum,
                          const rps3_model *model) {
  size_t k;
#define STORE(m) OUT_D(t, m)[j] = sum->m;
  SUM_FIELDS(STORE)
#undef STORE
  OUT_L(t, nreach)[j] = (int64_t)sum->nreach;
  OUT_I(t, flags_any)[j] = sum->flags_any;
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
    OUT_L(t, nflag)[j * RPS3_DESIGN_NFLAG + k] = (int64_t)sum->nflag[k];
  OUT_D(t, link_mass)[j] = model->m;
  OUT_D(t, link_d)[j] = model->d;
  OUT_D(t, link_Ic)[j] = model->link_Ic;
  OUT_I(t, des_status)[j] = 0;
}

/* the task of design d of case c into slot j; the samples evaluated */
static size_t eval_task(worker_ws *w, const rps3_design *d,
                        const rps3_design_opts *o, const scene_case *c,
                        out_block *t, size_t j) {
  rps3_design_task res;
  size_t k;
  int rc = rps3_design_task_eval(w->ws, d, o, &c->traj, c->nt,
                                 RPS3_DESIGN_LINK_MASS, &res);
  if (rc != RPS3_OK && rc != RPS3_EREACH) {
    /* a task this design cannot even be asked: the design failed */
    design_failed(t, j, rc, w->ws->err.msg);
    return 0;
  }
  OUT_I(t, task_status)[j] = rc;
  if (rc != RPS3_OK) OUT_S(t, task_message)[j] = strdup(w->ws->err.msg);
  OUT_D(t, task_fail_time)[j] = res.fail_time;
  OUT_I(t, task_fail_flags)[j] = rc != RPS3_OK ? res.fail_flags : 0;
  /* statistics of no sample (the task leaves the workspace at its start)
     are not numbers: NaN, as the fill */
  if (res.nsamples > 0) OUT_D(t, task_lti_min)[j] = res.lti_min;
  for (k = 0; k < 3 && res.nsamples > 0; k++) {
#define STORE(m) OUT_D(t, task_##m)[3 * j + k] = res.m[k];
    TASK_LINK_FIELDS(STORE)
#undef STORE
  }
  return res.nsamples;
}

/* design `index` into slot j of t; the poses and samples it evaluated */
static size_t eval_design(const scene *s, const design_plan *p, size_t index,
                          worker_ws *w, out_block *t, size_t j) {
  const rps3_design_opts *o = &s->base.des.opts;
  rps3_design_out out;
  rps3_design_summary sum;
  rps3_design d;
  scene_case c;
  scene_error err;
  size_t n = p->npose, k, done = n;
  int rc;
  tile_clear(t, j);
  if (design_case_build(s, index, &c, &err)) {
    /* checked by design_plan_make: only a changed scene gets here */
    design_failed(t, j, RPS3_EINVAL, err.what);
    return 0;
  }
  design_of_case(&c, &d);
  memset(&out, 0, sizeof out);
  out.flags =
      p->per_pose ? (int *)(void *)(OUT_I(t, pose_flags) + j * n) : w->flags;
  out.c = w->c;
#define POSE(m, id) out.m = p->per_pose ? OUT_D(t, id) + j * n : NULL;
  POSE_FIELDS(POSE)
#undef POSE
  rc = rps3_design_eval_grid(w->ws, &d, o, &p->gr, &out, &sum);
  if (rc != RPS3_OK && rc != RPS3_EEMPTY) {
    design_failed(t, j, rc, w->ws->err.msg);
    return 0;
  }
  for (k = 0; p->per_pose && k < n; k++) {
    OUT_D(t, des_x_c)[j * n + k] = w->c[k];
    OUT_D(t, des_y_c)[j * n + k] = w->c[n + k];
  }
  store_summary(t, j, &sum, &w->ws->model);
  if (p->task) done += eval_task(w, &d, o, &c, t, j);
  if (scene_case_yaml(&c, &w->yaml) == 0)
    OUT_S(t, des_scene_resolved)[j] = strdup(w->yaml.s);
  return done;
}

/* pool_job.run: work unit u on worker w, into its slot */
static int design_item(void *ctx, void *wctx, size_t u, pool_worker *w,
                       char *err, size_t errsz) {
  const design_job *J = ctx;
  out_block *t = pool_slot(w);
  out_tile in = {0};
  size_t j;
  in.with_case = 1;
  in.c0 = u * J->p->unit;
  in.nc = in.c0 + J->p->unit <= J->p->ncase ? J->p->unit : J->p->ncase - in.c0;
  for (j = 0; j < in.nc; j++)
    in.points += eval_design(J->w.s, J->p, in.c0 + j, wctx, t, j);
  return pool_emit(w, &in, err, errsz) ? 0 : -1;
}

/* pool_job.write: a unit's designs to the file, counted, the empty
   workspaces too */
static int design_write(void *ctx, void *slot, const void *info, char *err,
                        size_t errsz) {
  design_job *J = ctx;
  const out_block *t = slot;
  const out_tile *in = info;
  size_t j;
  if (sweep_write_tile(ctx, slot, info, err, errsz)) return -1;
  for (j = 0; j < in->nc; j++)
    if (OUT_I(t, des_status)[j] == 0 && OUT_L(t, nreach)[j] == 0)
      (*J->nempty)++;
  return 0;
}

int design_run(const scene *s, const design_plan *p, out_file *f, size_t shard,
               size_t nshard, int nthread, progress *pr, sweep_stats *st,
               size_t *nempty, char *err, size_t errsz) {
  design_job J = {
      {s, f, pr, st, OUT_des_status, OUT_des_message, 0}, p, nempty};
  pool_job job = {.ctx = &J,
                  .nitem = p->nunit,
                  .first = shard,
                  .stride = nshard,
                  .info_size = sizeof(out_tile),
                  .slot_size = sizeof(out_block),
                  .slot_make = tile_make,
                  .slot_free = tile_free,
                  .worker_begin = worker_new,
                  .worker_end = worker_free,
                  .run = design_item,
                  .write = design_write};
  memset(st, 0, sizeof *st);
  *nempty = 0;
  if (nthread < 1) nthread = 1;
  snprintf(err, errsz, "out of memory for the tiles of %d thread%s", nthread,
           nthread == 1 ? "" : "s");
  return pool_run(&job, nthread, err, errsz);
}

/* poses of the coarser grid that times a design of a large grid */
#define DESIGN_TIMED_POSES 8192

/* CPU seconds of eval_design of design i on the plan q */
static double timed_eval(const scene *s, const design_plan *q, size_t i,
                         worker_ws *w, out_block *t) {
  double t0 = est_cpu_now();
  (void)eval_design(s, q, i, w, t, 0);
  return est_cpu_now() - t0;
}

/* CPU seconds of one design, timed on up to 8 designs spread over the
   study (at most about 0.2 s of evaluation), or -1 when none could be
   timed */
static double design_cost_measure(const scene *s, const design_plan *p) {
  design_plan q = *p, q1;
  design_job J = {{0}, &q, NULL};
  worker_ws *w;
  out_block t;
  size_t i, timed = 0, step;
  double spent = 0, used = 0, grid, task;
  int k, big;
  /* the grid on one of at most DESIGN_TIMED_POSES poses of the same box
     (the axis of most cells halved), its time scaled by the poses (a pose
     costs the same wherever it is), and the task on a grid of one pose:
     the estimate's own cost is bounded whatever the grid */
  while (rps3_design_grid_size(&q.gr) > DESIGN_TIMED_POSES) {
    for (big = 0, k = 1; k < 3; k++)
      if (q.gr.n[k] > q.gr.n[big]) big = k;
    q.gr.n[big] = (q.gr.n[big] + 1) / 2;
  }
  q.npose = rps3_design_grid_size(&q.gr);
  q.task = 0;
  q.unit = 1;
  q1 = q;
  q1.gr.n[0] = q1.gr.n[1] = q1.gr.n[2] = q1.npose = 1;
  q1.task = p->task;
  memset(&t, 0, sizeof t);
  if (!(w = worker_new(&J)) || tile_make(&J, &t, 0)) {
    tile_free(NULL, &t, 0);
    worker_free(NULL, w);
    return -1;
  }
  step = p->ncase > 8 ? p->ncase / 8 : 1;
  for (i = 0; i < p->ncase && timed < 8 && used < 0.2; i += step) {
    grid = timed_eval(s, &q, i, w, &t);
    task = p->task ? timed_eval(s, &q1, i, w, &t) : 0;
    spent += grid * (double)p->npose / (double)q.npose + task;
    used += grid + task;
    timed++;
  }
  tile_free(NULL, &t, 0);
  worker_free(NULL, w);
  return timed ? spent / (double)timed : -1;
}

#define PL(n) ((n) == 1 ? "" : "s")

int design_preflight(const char *scene_path, const scene *s,
                     const design_plan *p, size_t shard, size_t nshard,
                     int nrank, int nthread, int gzip, int check, int quiet,
                     const char *out_path) {
  char e1[32], tt[32];
  size_t cases = design_shard_cases(p, shard, nshard);
  size_t units = pool_count(p->nunit, shard, nshard);
  double bytes = design_file_bytes(s, p), per = design_cost_measure(s, p);
  double need = nrank > 1
                    ? bytes
                    : bytes * (double)cases / (double)(p->ncase ? p->ncase : 1);
  int threads = (size_t)nthread < units ? nthread : (int)units;
  if (threads < 1) threads = 1;
  if (nshard > p->nunit && nrank == 1) {
    fprintf(stderr,
            "rps3-run: --shard %zu/%zu: the design study has %zu work "
            "unit%s (of up to %zu design%s), so at most %zu shard%s can "
            "have work: use --shard K/%zu or fewer (rps3-run SCENE --check "
            "counts the work units)\n",
            shard, nshard, p->nunit, PL(p->nunit), p->unit, PL(p->unit),
            p->nunit, PL(p->nunit), p->nunit);
    return -1;
  }
  if (check) {
    printf(
        "%s: design study: %zu design%s x %zu poses%s; output about %s "
        "uncompressed\n",
        scene_path, p->ncase, PL(p->ncase), p->npose,
        p->task ? " and the task" : "", est_human(bytes, e1, sizeof e1));
    if (per >= 0)
      printf(
          "run time about %s on %d thread%s (an estimate: %.3g ms a "
          "design, timed on a few designs)\n",
          est_human_time(per * (double)p->ncase / threads, tt, sizeof tt),
          threads, PL(threads), 1e3 * per);
    printf(
        "%zu work unit%s of up to %zu design%s: at most %zu shard%s, "
        "rank%s or thread%s ha%s work\n",
        p->nunit, PL(p->nunit), p->unit, PL(p->unit), p->nunit, PL(p->nunit),
        PL(p->nunit), PL(p->nunit), p->nunit == 1 ? "s" : "ve");
    return 0;
  }
  if (!quiet)
    fprintf(stderr,
            "rps3-run: design study: %zu design%s x %zu poses: %s about "
            "%s%s, run time about %s on %d thread%s\n",
            cases, PL(cases), p->npose, out_path,
            est_human(need, e1, sizeof e1), gzip ? " before compression" : "",
            per >= 0
                ? est_human_time(per * (double)cases / threads, tt, sizeof tt)
                : "unknown",
            threads, PL(threads));
  return est_fits(out_path, need, gzip);
}
