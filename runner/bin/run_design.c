/*
 * run_design.c - rps3-run on a design study (run_steps.h): the designs
 * checked by every rank, --check, the room, then the steps of a sweep's
 * run (run_output).
 */
#include "run_steps.h"

#include <stdio.h>
#include <string.h>

#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "exec/design_run.h"
#include "exec/pool.h"
#include "output/outblock.h"

/* what a design study's file needs */
typedef struct {
  const run_args *a;
  scene *s;
  const design_plan *plan;
  char fields[64]; /* the file kinds' fields, a part's root attribute */
} design_job;

/* run_job's write of a design study: the progress of this rank's designs,
   then they are computed into the file at tmpout_path() */
static int design_write(run_job *j, const out_meta *meta, progress *pr,
                        sweep_stats *sst) {
  design_job *d = j->ctx;
  const run_args *a = d->a;
  const design_plan *plan = d->plan;
  size_t nempty = 0;
  out_file *f;
  char err[512];
  int code;
  pr->njob_all = plan->nunit;
  pr->njob = pool_count(plan->nunit, a->shard, a->nshard);
  pr->npoint = pr->ncase * (plan->npose + plan->nsample);
  f = design_file_open(tmpout_path(), d->s, plan, meta, err, sizeof err);
  if (f && design_run(d->s, plan, f, a->shard, a->nshard, a->nthread, pr, sst,
                      &nempty, err, sizeof err) == 0)
    code = out_close(f, err, sizeof err) ? run_io(a, err) : EXIT_OK;
  else {
    if (f) out_close(f, NULL, 0);
    code = run_io(a, err);
  }
  if (nempty)
    snprintf(j->note, sizeof j->note,
             "rps3-run: %zu design%s with an empty workspace (nreach = 0: a "
             "result, not a failure)\n",
             nempty, nempty == 1 ? "" : "s");
  return code;
}

/* every design checked before anything is written (every rank), and the
   room; --check says what it would do.  -1 to go on, else the exit code */
static int design_checks(scene *s, const run_args *a, const world *w,
                         design_plan *plan) {
  scene_error serr;
  int code = EXIT_OK;
  if (design_plan_make(s, plan, &serr)) {
    if (w->rank == 0) scene_error_print(a->scene_path, &serr);
    code = EXIT_USAGE;
  }
  if ((code = run_agree(w, code, NULL)) != EXIT_OK) return code;
  if (a->check) {
    if (w->rank == 0)
      (void)design_preflight(a->scene_path, s, plan, 0, 1, 1, a->nthread,
                             a->gzip, 1, a->quiet, NULL);
    return EXIT_OK;
  }
  if (w->rank == 0 && w->size > 1 && (size_t)w->size > plan->nunit)
    fprintf(stderr,
            "rps3-run: warning: %d ranks but the design study has %zu work "
            "unit%s: ranks %zu-%d compute nothing; use at most %zu\n",
            w->size, plan->nunit, plan->nunit == 1 ? "" : "s", plan->nunit,
            w->size - 1, plan->nunit);
  return -1;
}

int run_design(scene *s, const run_args *a, const world *w, int argc,
               char **argv) {
  design_plan plan;
  design_job d = {a, s, &plan, ""};
  run_job j = {NULL, "design", 0, design_write, &d, ""};
  int code;
  if (a->fields != out_fields_all())
    return run_usage_error(w,
                           "--fields selects variables of the inverse-dynamics "
                           "file; a design study writes its file whole "
                           "(design.per_pose adds the per-pose indices)");
  if ((code = design_checks(s, a, w, &plan)) >= 0) return code;
  j.fields = out_fields_attr(plan.files, 0, d.fields, sizeof d.fields);
  j.ncase = design_shard_cases(&plan, a->shard, a->nshard);
  code = w->rank == 0 && design_preflight(a->scene_path, s, &plan, a->shard,
                                          a->nshard, w->size, a->nthread,
                                          a->gzip, 0, a->quiet, a->out_path)
             ? EXIT_USAGE
             : EXIT_OK;
  return run_output(a, w, s, code, &j, argc, argv);
}
