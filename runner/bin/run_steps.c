/*
 * run_steps.c - see run_steps.h.
 */
#include "run_steps.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "scene/inputs.h"
#include "shards/merge.h"

/* the name of rank r's part once complete: OUT.h5.part<r>of<N> */
#define RANK_PART "%s.part%dof%d"

/* rank 0: the ranks' parts into OUT.h5 under a temporary name, joined by
   virtual datasets over the parts renamed OUT.h5.part<r>of<N>, or with
   `copy` merged into its own part (the parts by their temporary names);
   the exit code (EXIT_IO on the other ranks) */
static int ranks_merge(const world *w, int copy, const char *out_path,
                       const char *cmd) {
  char(*paths)[4096] = calloc((size_t)w->size, sizeof *paths);
  const char **part = calloc((size_t)w->size, sizeof *part);
  char err[768], me[4096];
  size_t nfailed = 0;
  int r, code = EXIT_IO;
  if (!paths || !part) {
    fprintf(stderr, "rps3-run: out of memory\n");
    world_abort(EXIT_IO);
  }
  for (r = 0; r < w->size; r++) {
    snprintf(paths[r], sizeof paths[r], RANK_PART, out_path, r, w->size);
    part[r] = paths[r];
  }
  /* the ranks' temporary names, each with its own host and process */
  snprintf(me, sizeof me, "%s", tmpout_path());
  if (copy) world_gather(me, sizeof me, (char *)paths);
  if (w->rank == 0 && (copy || tmpout_name(out_path, 0) == 0)) {
    tmpout_arm();
    if (copy ? merge_parts(tmpout_path(), part, (size_t)w->size, cmd, &nfailed,
                           err, sizeof err)
             : join_vds(tmpout_path(), part, (size_t)w->size, cmd, &nfailed,
                        err, sizeof err))
      fprintf(stderr,
              copy ? "rps3-run: merging the ranks' parts: %s\n"
                   : "rps3-run: joining the ranks' parts: %s (the parts "
                     "%s.part*of%d are complete: join them with rps3-run "
                     "merge)\n",
              err, out_path, w->size);
    else if (tmpout_commit(out_path) == 0)
      code = nfailed ? EXIT_FAILED_CASES : EXIT_OK;
  }
  free(paths);
  free(part);
  return code;
}

/*
 * After every rank has written its part.  By default every rank renames
 * its part to OUT.h5.part<r>of<N> and rank 0 joins them by virtual
 * datasets (join.c); with `copy` rank 0 merges the parts of ranks 1.. into
 * its own file (merge.h) and every rank removes its part.  `code` is this
 * rank's outcome so far; returns the exit code of the run, the same on
 * every rank.
 */
static int ranks_join(const world *w, int code, int copy, const char *out_path,
                      const char *cmd, progress *pr, const sweep_stats *st,
                      size_t ncase) {
  unsigned long mine[3] = {st->cases_done, st->points_done, st->nfailed};
  unsigned long sum[3];
  int worst = code;
  world_idle_barrier();
  world_max_int(&code, &worst, 1);
  world_sum_ulong(mine, sum, 3);
  if (worst < EXIT_USAGE && !copy) {
    char name[4096];
    snprintf(name, sizeof name, RANK_PART, out_path, w->rank, w->size);
    code = tmpout_commit(name) ? EXIT_IO : code;
    world_max_int(&code, &worst, 1);
  }
  if (worst < EXIT_USAGE) worst = ranks_merge(w, copy, out_path, cmd);
  if (w->rank == 0 && worst < EXIT_USAGE) {
    pr->ncase = ncase;
    pr->njob = pr->njob_all;
    progress_finish(pr, sum[0], sum[1], sum[2]);
  }
  /* the other ranks sleep through rank 0's join; then, with --copy, the
     parts are read and every rank removes its own */
  world_idle_barrier();
  world_bcast_int(&worst);
  tmpout_discard();
  return worst;
}

/* every rank calls it at the same points, so that they all stop or all
   go on together */
int run_agree(const world *w, int code, int *first) {
  int mine[2], all[2];
  mine[0] = all[0] = code;
  mine[1] = all[1] = w->rank == 0 ? code : 0;
  if (w->size > 1) world_max_int(mine, all, 2);
  if (first) *first = all[1];
  return all[0];
}

int run_usage_error(const world *w, const char *msg) {
  if (w->rank == 0) {
    fprintf(stderr, "rps3-run: %s\n", msg);
    cli_try("rps3-run");
  }
  return EXIT_USAGE;
}

int run_io(const run_args *a, const char *err) {
  fprintf(stderr, "rps3-run: %s: %s\n", a->out_path, err);
  return EXIT_IO;
}

/* 1 when OUT.h5 is already this shard's complete part of this scene and
   these data (--resume), not computed again; the exit code in *code */
static int run_resumed(const run_args *a, const scene *s, const run_job *j,
                       const char *inputs, int *code) {
  size_t nfailed = 0;
  if (!a->resume || !parts_resume(a->out_path, a->shard, a->nshard, s->text,
                                  j->fields, inputs, &nfailed))
    return 0;
  if (!a->quiet)
    fprintf(stderr,
            "rps3-run: %s is shard %zu/%zu of this scene, "
            "complete (%zu %s%s, %zu failed): not run again\n",
            a->out_path, a->shard, a->nshard, j->ncase, j->noun,
            j->ncase == 1 ? "" : "s", nfailed);
  *code = nfailed && !a->failed_ok ? EXIT_FAILED_CASES : EXIT_OK;
  return 1;
}

/* j's file under a temporary name in the same directory (tmpout.h),
   renamed at the end or joined with the other ranks' parts; the exit
   code */
static int run_write(const run_args *a, const world *w, const scene *s,
                     run_job *j, const char *inputs, int argc, char **argv) {
  int code = EXIT_OK;
  char *cmd = cli_command_line(argc, argv);
  out_meta meta = {.command_line = cmd,
                   .gzip = a->gzip,
                   .shard = a->shard_arg,
                   .fields = a->fields,
                   .inputs = inputs};
  progress pr;
  sweep_stats st = {0};
  if (!cmd) {
    fprintf(stderr, "rps3-run: out of memory\n");
    code = EXIT_IO;
  }
  if (code == EXIT_OK && tmpout_name(a->out_path, w->rank)) code = EXIT_USAGE;
  if ((code = run_agree(w, code, NULL)) == EXIT_OK) {
    tmpout_arm();
    progress_start(&pr, j->ncase, a->quiet || w->rank != 0);
    code = j->write(j, &meta, &pr, &st);
    if (w->size > 1)
      code = ranks_join(w, code, a->copy, a->out_path, cmd, &pr, &st, s->ncase);
    else if (code != EXIT_OK || tmpout_commit(a->out_path))
      code = EXIT_IO;
    else {
      progress_finish(&pr, st.cases_done, st.points_done, st.nfailed);
      if (!a->quiet && j->note[0]) fputs(j->note, stderr);
      code = st.nfailed ? EXIT_FAILED_CASES : EXIT_OK;
    }
  }
  tmpout_discard();
  free(cmd);
  return code;
}

int run_output(const run_args *a, const world *w, const scene *s, int code,
               run_job *j, int argc, char **argv) {
  char err[512], *inputs = NULL;
  /* the files the scene read, by content (inputs.h): recorded in the
     file, compared by --resume and merge (each rank its own, before the
     ranks agree to go on) */
  if (code == EXIT_OK && !(inputs = inputs_record(s, err, sizeof err))) {
    fprintf(stderr, "rps3-run: %s: %s\n", a->scene_path, err);
    code = EXIT_IO;
  }
  if ((code = run_agree(w, code, NULL)) == EXIT_OK &&
      !run_resumed(a, s, j, inputs, &code)) {
    /* what killed runs of this output left on this host */
    if (w->rank == 0) tmpout_clean(a->out_path, 0, 1);
    code = run_write(a, w, s, j, inputs, argc, argv);
  }
  /* a complete file with failed cases, as a success (for schedulers) */
  if (code == EXIT_FAILED_CASES && a->failed_ok) code = EXIT_OK;
  free(inputs);
  return code;
}
