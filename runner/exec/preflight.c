/*
 * preflight.c - see preflight.h.
 */
#include "preflight.h"

#include <stdio.h>

#include "estimate.h"

int pre_jobs(const scene *s, const sweep_plan *p, const sweep_opts *o,
             const pre_opts *po) {
  size_t nj = sweep_njob(s, p);
  size_t mine = sweep_shard_jobs(s, p, o->shard, o->nshard);
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
  size_t jobs = sweep_shard_jobs(s, p, o->shard, o->nshard);
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
  char size[32], when[128];
  est_cost c;
  printf(
      "%s: %zu case%s, %zu samples (%zu per case at most)%s; output "
      "about %s uncompressed\n",
      scene_path, s->ncase, s->ncase == 1 ? "" : "s", p->npoint, p->nt,
      p->grid_common ? "" : ", time grid differs by case",
      est_human(est_file_bytes(s, p, po->fields), size, sizeof size));
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
    printf(
        "%zu work unit%s of up to %zu cases: at most %zu shards, ranks or "
        "threads have work\n",
        nj, nj == 1 ? "" : "s", p->tile_cases, nj);
  else
    printf(
        "%zu work unit%s of one case each (in windows of %zu samples): at "
        "most %zu shards, ranks or threads have work\n",
        nj, nj == 1 ? "" : "s", p->tile_points, nj);
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
  return est_room(out_path, "", s->ncase, p->npoint, need, po->gzip,
                  po->quiet, when);
}
