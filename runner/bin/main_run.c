/*
 * main_run.c - rps3-run: run a scene (its sweep, its design study or its
 * simulation) into an HDF5 file; run_cli.c holds its options and --help,
 * exit_codes.h its exit codes.
 *
 * -j N computes the cases on N threads (sweep.h); --shard K/N computes the
 * jobs of shard K only, into a part file that `merge` joins with the
 * others (merge.h).  Linked with MPI (rps3-run-mpi, mpi/world.h) and
 * launched by mpirun, rank r computes shard r of the ranks and rank 0
 * joins the parts (run_steps.c): the same datasets as one process.
 * Killed by SIGINT/SIGTERM/SIGHUP, the temporary file is removed and the
 * process dies of that signal (shell status 128 + signal).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "core/h5err.h"
#include "core/progress.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "exec/design_run.h"
#include "exec/estimate.h"
#include "exec/pool.h"
#include "exec/simulate.h"
#include "exec/sweep.h"
#include "mpi/world.h"
#include "output/outblock.h"
#include "output/output.h"
#include "run_ident.h"
#include "run_steps.h"
#include "scene/design.h"
#include "scene/identify.h"
#include "scene/scene.h"
#include "shards/merge.h"

/*
 * The command line against the launch: under mpirun the ranks are the
 * shards (a's shard set from w), --copy needs mpirun, --resume a shard;
 * where the output goes is checked before anything is computed.  -1 to
 * go on, or the exit code after a message (by rank 0).
 */
static int args_for_world(run_args *a, const world *w) {
  char err[512];
  if (w->size > 1) {
    if (a->shard_arg)
      return run_usage_error(w,
                             "--shard is for runs without mpirun; under "
                             "mpirun the ranks are the shards");
    a->shard = (size_t)w->rank;
    a->nshard = (size_t)w->size;
    /* each rank's file is a part like those of --shard */
    snprintf(a->shard_text, sizeof a->shard_text, "%d/%d", w->rank, w->size);
    a->shard_arg = a->shard_text;
  } else if (a->copy) {
    return run_usage_error(w,
                           "--copy is for rps3-run-mpi under mpirun and for "
                           "merge; a run without them writes one whole file");
  }
  if (a->out_path && !a->check) {
    if (out_path_check(a->out_path, &a->scene_path, 1, err, sizeof err)) {
      if (w->rank == 0) fprintf(stderr, "rps3-run: %s\n", err);
      return EXIT_USAGE;
    }
    if (w->rank == 0) stale_report("rps3-run", a->out_path);
  }
  if (a->resume && (!a->shard_arg || w->size > 1))
    return run_usage_error(w,
                           "--resume is for --shard K/N runs (it skips a part "
                           "that is complete already)");
  return -1;
}

/* at most one thread per core (-j beyond them: said by rank 0): threads
   beyond the cores compute nothing faster and each holds a tile and a
   workspace (-j 1024 on 2 cores took 4.3 GB) */
static void use_the_cores(sweep_opts *opts, const world *w) {
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (cores >= 1 && opts->nthread > cores) {
    if (w->rank == 0)
      fprintf(stderr,
              "rps3-run: warning: -j %d on %ld core%s: computing "
              "on %ld thread%s\n",
              opts->nthread, cores, cores == 1 ? "" : "s", cores,
              cores == 1 ? "" : "s");
    opts->nthread = (int)cores;
  }
}

/* a scene with a simulate section: simulated (simulate.h), by one
   process; the exit code */
static int run_simulated(scene *s, const run_args *a, const world *w, int argc,
                         char **argv) {
  sim_args sa;
  int code;
  char *cmd;
  sa.out_path = a->out_path;
  sa.check = a->check;
  sa.quiet = a->quiet;
  sa.gzip = a->gzip;
  sa.nthread = a->nthread;
  sa.sharded = a->shard_arg != NULL || a->resume || w->size > 1;
  sa.command_line = cmd = cli_command_line(argc, argv);
  /* refused under mpirun: rank 0 says so */
  code = !cmd ? EXIT_IO : w->rank > 0 ? EXIT_USAGE : sim_main(s, &sa);
  free(cmd);
  return code;
}

/* the scene and its sweep plan, checked by every rank before anything is
   written (rank 0 says what is wrong, or else the ranks that fail):
   EXIT_OK with s loaded, else the exit code with s freed */
static int run_load(const run_args *a, const world *w, scene *s,
                    sweep_plan *plan) {
  scene_error serr;
  int code = EXIT_OK, first, worst;
  if (scene_load(s, a->scene_path, &serr))
    code = EXIT_USAGE;
  else if (w->rank == 0)
    /* values valid but likely in the wrong unit: said (before a case that
       fails because of them), not refused */
    scene_warnings_print(s, stderr);
  /* a design study is planned by run_design (exec/design_run.h) */
  if (code == EXIT_OK && !design_wanted(s) && !ident_wanted(s) &&
      sweep_plan_make(s, plan, &serr)) {
    scene_free(s);
    code = EXIT_USAGE;
  }
  worst = run_agree(w, code, &first);
  if (code && (w->rank == 0 || first == EXIT_OK))
    scene_error_print(a->scene_path, &serr);
  if (worst && !code) scene_free(s);
  return worst;
}

/* what a sweep's file needs */
typedef struct {
  const run_args *a;
  const scene *s;
  const sweep_plan *plan;
  const sweep_opts *opts;
  out_block block;
} sweep_job;

/* run_job's write of a sweep: the progress of this rank's shard, the
   sweep computed into the file at tmpout_path() */
static int sweep_write(run_job *j, const out_meta *meta, progress *pr,
                       sweep_stats *st) {
  sweep_job *sj = j->ctx;
  const sweep_plan *plan = sj->plan;
  const scene *s = sj->s;
  char err[512];
  out_file *f;
  if (out_block_alloc(&sj->block, OUT_INV, plan->tile_cases, plan->tile_points,
                      plan->first.model.opt.effects)) {
    fprintf(stderr, "rps3-run: out of memory\n");
    return EXIT_IO;
  }
  sj->block.fields = sj->a->fields;
  pr->njob_all = sweep_njob(s, plan);
  pr->njob = pool_count(pr->njob_all, sj->opts->shard, sj->opts->nshard);
  /* the shard's samples, in proportion to its cases (exact unsharded) */
  pr->npoint = s->ncase ? (size_t)((double)plan->npoint * (double)pr->ncase /
                                   (double)s->ncase)
                        : 0;
  f = out_create(tmpout_path(), s, OUT_INV, plan->nt,
                 plan->grid_common ? &plan->first : NULL, plan->chunk_points,
                 &sj->block, meta, err, sizeof err);
  if (f && sweep_run_opts(s, plan, f, &sj->block, sj->opts, pr, st, err,
                          sizeof err) == 0)
    return out_close(f, err, sizeof err) ? run_io(sj->a, err) : EXIT_OK;
  if (f) out_close(f, NULL, 0);
  return run_io(sj->a, err);
}

/* the inverse dynamics of a checked scene into OUT.h5: its room, then the
   steps of a run (run_output); the exit code */
static int run_sweep(const run_args *a, const world *w, const scene *s,
                     const sweep_plan *plan, const sweep_opts *opts,
                     const pre_opts *pre, int argc, char **argv) {
  char names[1024];
  sweep_job sj = {a, s, plan, opts, {0}};
  run_job j = {NULL, "case", 0, sweep_write, &sj, ""};
  int code;
  j.fields = out_fields_text(a->fields, names, sizeof names);
  j.ncase = sweep_shard_cases(s, plan, opts->shard, opts->nshard);
  code = w->rank == 0 && pre_room(s, plan, opts, pre, a->out_path) ? EXIT_USAGE
                                                                   : EXIT_OK;
  code = run_output(a, w, s, code, &j, argc, argv);
  out_block_free(&sj.block);
  return code;
}

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

/* rps3-run on the design study s (scene/design.h): the plan, --check,
   then the file of this process's designs (a whole file, a --shard part,
   or a rank's part joined as a sweep's are) by run_output; the exit code */
static int run_design(scene *s, const run_args *a, const world *w, int argc,
                      char **argv) {
  design_plan plan;
  design_job d = {a, s, &plan, ""};
  run_job j = {NULL, "design", 0, design_write, &d, ""};
  int code;
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

/* rps3-run SCENE.yaml: parse, check, then simulate, check only or run the
   sweep; the exit code */
static int run_main(int argc, char **argv, const world *w) {
  int code;
  run_args a;
  scene s;
  sweep_plan plan;
  sweep_opts opts = {1, 0, 1};
  pre_opts pre;
  /* the command line (run_cli.c) */
  if ((code = run_args_parse(argc, argv, &a)) >= 0) return code;
  if ((code = args_for_world(&a, w)) >= 0) return code;
  opts.nthread = a.nthread;
  opts.shard = a.shard;
  opts.nshard = a.nshard;
  if ((code = run_load(&a, w, &s, &plan)) != EXIT_OK) return code;
  pre.rank = w->rank;
  pre.nrank = w->size;
  pre.copy = a.copy;
  pre.gzip = a.gzip;
  pre.quiet = a.quiet;
  pre.fields = a.fields;
  if (a.manip_path && !ident_wanted(&s))
    code = run_usage_error(w,
                           "--manipulator writes the manipulator section an "
                           "identification fits; this scene has no identify "
                           "section");
  else if (a.fields != out_fields_all() && ident_wanted(&s))
    code = run_usage_error(w,
                           "--fields selects variables of the "
                           "inverse-dynamics file; an identification "
                           "writes its file whole");
  else if (a.fields != out_fields_all() &&
           (design_wanted(&s) || sim_wanted(&s)))
    code = run_usage_error(
        w, design_wanted(&s)
               ? "--fields selects variables of the inverse-dynamics file; a "
                 "design study writes its file whole (design.per_pose adds "
                 "the per-pose indices)"
               : "--fields selects variables of the inverse-dynamics file; a "
                 "scene with a simulate section writes the simulation file "
                 "whole");
  else if (ident_wanted(&s)) /* its fit and draws (run_ident.h) */
    code = run_identify(&s, &a, w, argc, argv);
  else if (design_wanted(&s)) /* its designs into its own file */
    code = run_design(&s, &a, w, argc, argv);
  else if (sim_wanted(&s)) /* simulated instead (simulate.h) */
    code = run_simulated(&s, &a, w, argc, argv);
  else if (pre_jobs(&s, &plan, &opts, &pre))
    code = EXIT_USAGE;
  else {
    use_the_cores(&opts, w);
    if (!a.check)
      code = run_sweep(&a, w, &s, &plan, &opts, &pre, argc, argv);
    else if (w->rank == 0)
      pre_check_print(a.scene_path, &s, &plan, &opts, &pre);
  }
  scene_free(&s);
  return code;
}

/*
 * The tasks of the launch this process belongs to, 1 if none: mpirun
 * (OMPI_COMM_WORLD_SIZE), a PMI launcher (PMI_SIZE), or a Slurm step of
 * several tasks (srun -n N: SLURM_STEP_NUM_TASKS; not SLURM_NTASKS, which
 * the batch script of a multi-task job has too, where one process is
 * right).  *by names the launcher.
 */
static int launched_tasks(const char **by) {
  const char *v = getenv("OMPI_COMM_WORLD_SIZE");
  *by = "mpirun";
  if (!v && (v = getenv("PMI_SIZE")) != NULL) *by = "a PMI launcher";
  if (!v && getenv("SLURM_PROCID") &&
      (v = getenv("SLURM_STEP_NUM_TASKS")) != NULL)
    *by = "srun";
  return v && atoi(v) > 1 ? atoi(v) : 1;
}

int main(int argc, char **argv) {
  world w = {0, 1};
  const char *by;
  int code, (*sub)(int, char **);
  /* fds 0-2 open before anything opens a file; HDF5 without atexit */
  proc_init();
  world_init(&argc, &argv, &w);
  /* the subcommands that run as one process: --clean and merge */
  sub = argc < 2                          ? NULL
        : strcmp(argv[1], "--clean") == 0 ? clean_main
        : strcmp(argv[1], "merge") == 0   ? merge_main
                                          : NULL;
  if (w.size == 1 && launched_tasks(&by) > 1) {
    if (world_has_mpi()) {
      /* srun without --mpi=pmix (or an MPI that srun cannot start): N
         singletons, each of which would compute the whole sweep */
      fprintf(stderr,
              "rps3-run: %d tasks started by %s, but MPI sees 1: "
              "use srun --mpi=pmix (or mpirun)\n",
              launched_tasks(&by), by);
      world_finalize();
      return proc_exit(EXIT_USAGE);
    }
    if (!sub) {
      fprintf(stderr,
              "rps3-run: launched as %d tasks by %s, but built "
              "without MPI: every task would compute the whole "
              "sweep; use build/rps3-run-mpi (make runner-mpi), or "
              "one task per --shard K/N (a Slurm job array)\n",
              launched_tasks(&by), by);
      return proc_exit(EXIT_USAGE);
    }
  }
  /* process-wide policy: GSL returns its errors, HDF5's are captured
     (h5err.h); the signals that end a run remove its temporary file
     (tmpout.h) */
  sig_init();
  gsl_set_error_handler_off();
  h5_errors_capture();
  if (strcmp(rps3_version(), RPS3_VERSION_STRING) != 0) {
    fprintf(stderr, "rps3-run: library %s does not match header %s\n",
            rps3_version(), RPS3_VERSION_STRING);
    code = EXIT_IO;
  } else if (sub && w.size > 1) {
    if (w.rank == 0)
      fprintf(stderr, "rps3-run: %s runs as one process\n", argv[1]);
    code = EXIT_USAGE;
  } else
    code = sub ? sub(argc, argv) : run_main(argc, argv, &w);
  world_finalize();
  return proc_exit(code);
}
