/*
 * run_design.c - see run_design.h.  The steps of a sweep's run (main_run.c)
 * for a design study: the designs checked by every rank, the output and
 * its room, --resume, the temporary file renamed when complete, the ranks'
 * parts joined.
 */
#include "run_design.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "exec/design_run.h"
#include "exec/pool.h"
#include "scene/inputs.h"
#include "shards/parts.h"

/* the worst of the ranks' codes (this code without MPI) */
static int agree_all(const world *w, int code) {
  int worst = code;
  if (w->size > 1) world_max_int(&code, &worst, 1);
  return worst;
}

int run_design(scene *s, const run_args *a, const world *w, int argc,
               char **argv, ranks_join_fn join) {
  design_plan plan;
  sweep_stats st;
  out_file *f;
  scene_error serr;
  size_t nempty = 0;
  progress pr;
  out_meta meta;
  char err[512], fields[64], *cmd = NULL, *inputs = NULL;
  int code = EXIT_OK, rc = -1, nthread = a->nthread;

  if (a->fields != out_fields_all()) {
    if (w->rank == 0) {
      fprintf(stderr,
              "rps3-run: --fields selects variables of the "
              "inverse-dynamics file; a design study writes its "
              "file whole (design.per_pose adds the per-pose "
              "indices)\n");
      cli_try("rps3-run");
    }
    return EXIT_USAGE;
  }
  /* every design checked before anything is written (every rank) */
  if (design_plan_make(s, &plan, &serr)) {
    if (w->rank == 0) scene_error_print(a->scene_path, &serr);
    code = EXIT_USAGE;
  }
  if ((code = agree_all(w, code)) != EXIT_OK) return code;
  if (a->check) {
    if (w->rank == 0)
      (void)design_preflight(a->scene_path, s, &plan, 0, 1, 1, nthread, a->gzip,
                             1, a->quiet, NULL);
    return EXIT_OK;
  }
  if (w->rank == 0 && w->size > 1 && (size_t)w->size > plan.nunit)
    fprintf(stderr,
            "rps3-run: warning: %d ranks but the design study has %zu work "
            "unit%s: ranks %zu-%d compute nothing; use at most %zu\n",
            w->size, plan.nunit, plan.nunit == 1 ? "" : "s", plan.nunit,
            w->size - 1, plan.nunit);
  if (w->rank == 0 &&
      design_preflight(a->scene_path, s, &plan, a->shard, a->nshard, w->size,
                       nthread, a->gzip, 0, a->quiet, a->out_path))
    code = EXIT_USAGE;
  if (code == EXIT_OK && !(inputs = inputs_record(s, err, sizeof err))) {
    fprintf(stderr, "rps3-run: %s: %s\n", a->scene_path, err);
    code = EXIT_IO;
  }
  if ((code = agree_all(w, code)) != EXIT_OK) {
    free(inputs);
    return code;
  }
  /* a complete part of this study and these data is not computed again */
  if (a->resume) {
    size_t nfailed = 0, ncase = design_shard_cases(&plan, a->shard, a->nshard);
    if (parts_resume(a->out_path, a->shard, a->nshard, s->text,
                     out_fields_attr(plan.files, 0, fields, sizeof fields),
                     inputs, &nfailed)) {
      if (!a->quiet)
        fprintf(stderr,
                "rps3-run: %s is shard %zu/%zu of this scene, complete "
                "(%zu design%s, %zu failed): not run again\n",
                a->out_path, a->shard, a->nshard, ncase, ncase == 1 ? "" : "s",
                nfailed);
      free(inputs);
      return nfailed && !a->failed_ok ? EXIT_FAILED_CASES : EXIT_OK;
    }
  }
  if (w->rank == 0) tmpout_clean(a->out_path, 0, 1);
  cmd = cli_command_line(argc, argv);
  if (!cmd) {
    fprintf(stderr, "rps3-run: out of memory\n");
    code = EXIT_IO;
  }
  meta.command_line = cmd;
  meta.gzip = a->gzip;
  meta.shard = a->shard_arg;
  meta.fields = a->fields;
  meta.inputs = inputs;
  if (code == EXIT_OK && tmpout_name(a->out_path, w->rank)) code = EXIT_USAGE;
  if ((code = agree_all(w, code)) != EXIT_OK) goto done;
  tmpout_arm();
  progress_start(&pr, design_shard_cases(&plan, a->shard, a->nshard),
                 a->quiet || w->rank != 0);
  pr.njob_all = plan.nunit;
  pr.njob = pool_count(plan.nunit, a->shard, a->nshard);
  pr.npoint = pr.ncase * (plan.npose + plan.nsample);
  memset(&st, 0, sizeof st);
  f = design_file_open(tmpout_path(), s, &plan, &meta, err, sizeof err);
  if (f)
    rc = design_run(s, &plan, f, a->shard, a->nshard, nthread, &pr, &st,
                    &nempty, err, sizeof err);
  if (f && out_close(f, rc ? NULL : err, sizeof err) && rc == 0) rc = -1;
  if (rc) {
    fprintf(stderr, "rps3-run: %s: %s\n", a->out_path, err);
    code = EXIT_IO;
  }
  if (w->size > 1)
    code = join(w, code, a->copy, a->out_path, cmd, &pr, &st, s->ncase);
  else if (code != EXIT_OK || tmpout_commit(a->out_path))
    code = EXIT_IO;
  else {
    progress_finish(&pr, st.cases_done, st.points_done, st.nfailed);
    if (!a->quiet && nempty)
      fprintf(stderr,
              "rps3-run: %zu design%s with an empty workspace (nreach = 0: "
              "a result, not a failure)\n",
              nempty, nempty == 1 ? "" : "s");
    code = st.nfailed ? EXIT_FAILED_CASES : EXIT_OK;
  }
done:
  if (code == EXIT_FAILED_CASES && a->failed_ok) code = EXIT_OK;
  tmpout_discard();
  free(cmd);
  free(inputs);
  return code;
}
