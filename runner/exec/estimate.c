/* estimate.c - see estimate.h. */
#include "estimate.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "core/safeio.h"
#include "output/output.h"

/* HDF5's global heap: a variable-length string is a 16-byte reference in
   the dataset and an object of 16 bytes of header plus its text, rounded up
   to 8 bytes, in the heap */
#define VLEN_REF 16.0
#define VLEN_OBJ 16.0
/* per chunk and chunked dataset: its B-tree entry (measured: 40-60 bytes) */
#define CHUNK_INDEX 64.0
/* superblock, object headers, attributes, dimension scales: measured at
   30-60 kB for the configs */
#define FIXED 131072.0

/* samples est_cost_measure computes, from up to EST_CASES cases spread
   over the sweep (the first and the last included), their first samples:
   enough to average over the start of a case (the multiroot cold start)
   and the sweep's range, few enough to take milliseconds */
#define EST_SAMPLES 6000
#define EST_CASES 16

/* CPU seconds to write one byte of chunks, uncompressed: packing them
   (out_pack's checksum), the HDF5 calls and the kernel's copy into the
   page cache.  Measured with the bench sweep of
   tests/bench/runner_bench.py (1000 cases of 1000 samples, 331 MB): the
   run's CPU time (0.29 s) less the computation est_cost_measure times
   (0.09-0.13 us a sample), over the bytes written (docs/performance.md) */
#define EST_WRITE_S_PER_BYTE 0.5e-9
/* CPU seconds to deflate one byte, by --gzip level: the same sweep, the
   CPU time of --gzip 1, 4 and 9 less that of no compression, over its
   bytes (docs/hdf5.md, "File size"); levels between are interpolated */
static double gzip_s_per_byte(int level) {
  if (level <= 0) return 0;
  if (level <= 1) return 10.5e-9;
  if (level <= 4) return 10.5e-9 + (15.0e-9 - 10.5e-9) * (level - 1) / 3.0;
  return 15.0e-9 + (24.0e-9 - 15.0e-9) * (level - 4) / 5.0;
}

/* Bytes of the file rps3-run writes for the plan p of s, uncompressed (an
   upper bound with --gzip): the fields of `fields` in every chunk the run
   allocates (p->stored samples per sample field: a partial edge chunk
   counts whole), the per-case strings, the swept keys and the
   coordinates, plus a bound on HDF5's metadata.  A double: absurd sweeps
   exceed any size_t. */
static double est_file_bytes(const scene *s, const sweep_plan *p,
                             out_mask fields) {
  /* the chunks the plan allocates (sweep.h): per sample field, `stored`
     samples in chunks of tile_cases x chunk_points; per case, whole rows */
  const double tc = (double)p->tile_cases, nt = (double)p->nt;
  const double stored = (double)p->stored;
  const double chunks = stored / (tc * (double)p->chunk_points);
  /* rows of the per-case chunks: ncase rounded up to whole chunks */
  const double rows =
      (double)((s->ncase + p->tile_cases - 1) / p->tile_cases * p->tile_cases);
  double per_sample = 0, per_case = 0, nds = 0, yaml = 600, total;
  scene_text t = {0};
  size_t a, neff = 0;
  int i;
  for (i = 0; i < RPS3_NEFFECT; i++)
    if (p->first.model.opt.effects & (1 << i)) neff++;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    double size =
        fi->type == OUT_STR ? VLEN_REF : (double)out_type_size(fi->type);
    if (!OUT_HAS(fields, i)) continue;
    if (fi->shape == OUT_C)
      per_case += size;
    else
      per_sample += (double)out_columns(fi->shape, neff) * size;
    nds += 1;
  }
  if (!p->grid_common) {
    per_sample += 8; /* case_time */
    nds += 1;
  }
  /* the heap objects: scene_resolved (the first case's YAML as the
     typical one) and an empty message per case */
  if (scene_case_yaml(&p->first, &t) == 0) yaml = (double)t.len;
  scene_text_free(&t);
  per_case += 2 * VLEN_OBJ + 8.0 * (double)(size_t)((yaml + 7) / 8);
  /* the case scale and the swept keys */
  per_case += 8;
  for (a = 0; a < s->naxis; a++) per_case += 8;
  total = stored * per_sample + rows * per_case + 8 * nt +
          chunks * nds * CHUNK_INDEX + (double)s->text_len + FIXED;
  return total;
}

const char *est_human(double bytes, char *buf, size_t sz) {
  static const char *const unit[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) {
    bytes /= 1000;
    u++;
  }
  snprintf(buf, sz, u ? "%.3g %s" : "%.0f %s", bytes, unit[u]);
  return buf;
}

double est_cpu_now(void) {
  struct timespec t;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0;
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* compute the first samples of case i into b with its workspace of ws;
   adds to the CPU seconds and counts of c */
static void time_case(const scene *s, size_t i, out_block *b,
                      rps3_data *ws[RPS3_NSOLVER], est_cost *c) {
  scene_case sc;
  scene_error e;
  scene_text yaml = {0};
  size_t n, failed_at = 0;
  double t0 = est_cpu_now(), t1;
  rps3_data *d;
  char err[128];
  int rc;
  if (scene_case_build(s, i, &sc, &e) || scene_case_yaml(&sc, &yaml)) return;
  scene_text_free(&yaml);
  if (!(d = case_workspace(ws, &sc, err, sizeof err))) return;
  t1 = est_cpu_now();
  c->per_case += t1 - t0;
  c->cases++;
  n = sc.nt < b->points ? sc.nt : b->points;
  rc = case_compute(&sc, d, 0, n, b, 0, &failed_at);
  c->sample += est_cpu_now() - t1;
  c->samples += rc == RPS3_OK ? n : failed_at + 1;
}

/* Time the computation: the first samples of up to EST_CASES cases spread
   over the sweep, with the runner's own per-case code, on the process's
   CPU clock (a few ms); writing and deflating at their measured cost per
   byte times the file's bytes per sample.  A case that fails is timed up
   to its failing sample (at least that one).  0, or -1 when nothing could
   be timed (out of memory). */
static int est_cost_measure(const scene *s, const sweep_plan *p,
                            out_mask fields, int gzip, est_cost *c) {
  const size_t ncase = s->ncase < EST_CASES ? s->ncase : EST_CASES;
  out_block b;
  rps3_data *ws[RPS3_NSOLVER] = {NULL};
  size_t k;
  memset(c, 0, sizeof *c);
  if (out_block_alloc(&b, OUT_INV, 1, EST_SAMPLES / ncase,
                      p->first.model.opt.effects))
    return -1;
  /* the path the run takes: a file of the batch's fields is computed by
     rps3_inverse_batch (sweep.c) */
  b.fields = fields;
  for (k = 0; k < ncase; k++)
    time_case(s, ncase > 1 ? k * (s->ncase - 1) / (ncase - 1) : 0, &b, ws, c);
  case_workspaces_free(ws);
  out_block_free(&b);
  if (c->cases) c->per_case /= (double)c->cases;
  c->write =
      est_file_bytes(s, p, fields) / (double)p->npoint * EST_WRITE_S_PER_BYTE;
  c->deflate =
      est_file_bytes(s, p, fields) / (double)p->npoint * gzip_s_per_byte(gzip);
  if (c->samples == 0) return -1;
  c->sample /= (double)c->samples;
  return 0;
}

const char *est_human_time(double seconds, char *buf, size_t sz) {
  if (seconds < 60)
    snprintf(buf, sz,
             seconds < 1    ? "%.1g s"
             : seconds < 10 ? "%.2g s"
                            : "%.0f s",
             seconds);
  else if (seconds < 3600)
    snprintf(buf, sz, "%.2g min", seconds / 60);
  else if (seconds < 86400 * 2)
    snprintf(buf, sz, "%.2g h", seconds / 3600);
  else
    snprintf(buf, sz, "%.3g days", seconds / 86400);
  return buf;
}

const char *est_when(const est_cost *c, double samples, double cases,
                     int threads, char *buf, size_t sz) {
  double work = samples * (c->sample + c->deflate) + cases * c->per_case;
  double write = samples * c->write;
  char t[32];
  /* on threads the workers compute and deflate while the calling thread
     writes */
  if (threads > 1) work /= threads;
  snprintf(buf, sz, "about %s on %d thread%s",
           est_human_time(threads <= 1   ? work + write
                          : work > write ? work
                                         : write,
                          t, sizeof t),
           threads, threads == 1 ? "" : "s");
  return buf;
}

int est_fits(const char *out_path, double need, int gzip) {
  double avail = disk_free(out_path);
  char e1[32], e2[32];
  if (avail < 0 || need <= avail || gzip) return 0;
  fprintf(stderr,
          "rps3-run: %s: the output needs about %s, the file "
          "system has %s free: nothing written\n",
          out_path, est_human(need, e1, sizeof e1),
          est_human(avail, e2, sizeof e2));
  return -1;
}

void est_check_print(const char *path, const char *kind, size_t ncase,
                     size_t npoint, size_t nt, int common, double bytes) {
  char e[32];
  printf(
      "%s: %s%zu case%s, %zu samples (%zu per case at most)%s; output "
      "about %s uncompressed\n",
      path, kind, ncase, ncase == 1 ? "" : "s", npoint, nt,
      common ? "" : ", time grid differs by case",
      est_human(bytes, e, sizeof e));
}

int est_room(const char *out_path, const char *kind, size_t ncase,
             size_t npoint, double need, int gzip, int quiet,
             const char *when) {
  char e1[32];
  if (!quiet)
    fprintf(stderr, "rps3-run: %zu %scase%s, %zu samples: %s about %s%s, %s\n",
            ncase, kind, ncase == 1 ? "" : "s", npoint, out_path,
            est_human(need, e1, sizeof e1), gzip ? " before compression" : "",
            when);
  return est_fits(out_path, need, gzip);
}

int pre_jobs(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po) {
  size_t nj = sweep_njob(s, p);
  size_t mine = pool_count(nj, o->shard, o->nshard);
  if (o->nshard > nj && po->nrank == 1) {
    /* a part that can hold nothing is a sizing mistake: the merge would
       need it all the same */
    fprintf(stderr,
            "rps3-run: --shard %zu/%zu: the sweep has %zu work unit%s (tiles "
            "of up to %zu cases), so at most %zu shard%s can have work: use "
            "--shard K/%zu or fewer (rps3-run SCENE --check counts the "
            "work units)\n",
            o->shard, o->nshard, nj, nj == 1 ? "" : "s", p->tile_cases, nj,
            nj == 1 ? "" : "s", nj);
    return -1;
  }
  if (po->rank != 0) return 0;
  if (o->nshard > nj)
    fprintf(stderr,
            "rps3-run: warning: %zu ranks but the sweep has %zu work unit%s "
            "(tiles of up to %zu cases): ranks %zu-%zu compute nothing; use "
            "at most %zu\n",
            o->nshard, nj, nj == 1 ? "" : "s", p->tile_cases, nj, o->nshard - 1,
            nj);
  if ((size_t)o->nthread > mine && mine > 0)
    fprintf(stderr,
            "rps3-run: warning: -j %d but %s %zu work unit%s: %zu thread%s "
            "idle\n",
            o->nthread, o->nshard > 1 ? "this shard has" : "the sweep has",
            mine, mine == 1 ? "" : "s", (size_t)o->nthread - mine,
            (size_t)o->nthread - mine == 1 ? " stays" : "s stay");
  return 0;
}

/* the estimated wall time of this process's share of the run into buf
   ("about 3.2 s on 2 threads"), from the costs measured into *c; returns
   0, or -1 when nothing could be timed (out of memory; buf says so) */
static int run_time(const scene *s, const sweep_plan *p, const sweep_opts *o,
                    const pre_opts *po, est_cost *c, char *buf, size_t sz) {
  size_t cases = sweep_shard_cases(s, p, o->shard, o->nshard);
  size_t jobs = pool_count(sweep_njob(s, p), o->shard, o->nshard);
  double samples = (double)p->npoint * (double)cases / (double)s->ncase;
  /* -j 1 computes and writes on one thread; -j N on N workers and a
     writer */
  int threads = (size_t)o->nthread < jobs ? o->nthread : (int)jobs;
  if (est_cost_measure(s, p, po->fields, po->gzip, c)) {
    snprintf(buf, sz, "run time not estimated (out of memory)");
    return -1;
  }
  est_when(c, samples, (double)cases, threads < 1 ? 1 : threads, buf, sz);
  return 0;
}

void pre_check_print(const char *scene_path, const scene *s,
                     const sweep_plan *p, const sweep_opts *o,
                     const pre_opts *po) {
  size_t nj = sweep_njob(s, p);
  char when[128], unit[96];
  est_cost c;
  est_check_print(scene_path, "", s->ncase, p->npoint, p->nt, p->grid_common,
                  est_file_bytes(s, p, po->fields));
  if (run_time(s, p, o, po, &c, when, sizeof when) == 0) {
    printf(
        "run time %s (an estimate: %.3g us a sample computing, timed on "
        "%zu samples of %zu case%s, + %.3g us writing",
        when, 1e6 * c.sample, c.samples, c.cases, c.cases == 1 ? "" : "s",
        1e6 * c.write);
    if (po->gzip) printf(" + %.3g us deflating", 1e6 * c.deflate);
    printf(")\n");
  } else
    printf("%s\n", when);
  if (p->tile_cases > 1 || p->nt <= p->tile_points)
    snprintf(unit, sizeof unit, "up to %zu cases", p->tile_cases);
  else
    snprintf(unit, sizeof unit, "one case each (in windows of %zu samples)",
             p->tile_points);
  printf(
      "%zu work unit%s of %s: at most %zu shards, ranks or threads have "
      "work\n",
      nj, nj == 1 ? "" : "s", unit, nj);
}

int pre_room(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po, const char *out_path) {
  double est = est_file_bytes(s, p, po->fields), need = est;
  char when[128] = "";
  est_cost c;
  if (o->nshard > 1 && po->nrank == 1)
    need = est * (double)sweep_shard_cases(s, p, o->shard, o->nshard) /
           (double)s->ncase;
  if (po->nrank > 1) need = po->copy ? 2 * est : est;
  if (!po->quiet) run_time(s, p, o, po, &c, when, sizeof when);
  return est_room(out_path, "", s->ncase, p->npoint, need, po->gzip, po->quiet,
                  when);
}
