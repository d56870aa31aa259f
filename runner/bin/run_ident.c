/* run_ident.c - see run_ident.h. */
#include "run_ident.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/exit_codes.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "exec/ident_run.h"
#include "exec/pool.h"

/* what the file of an identification needs */
typedef struct {
  const run_args *a;
  const scene *s;
  const ident_plan *p;
  const ident_fit *fit;
  const char *yaml; /* the manipulator section, or NULL: */
  const char *why;  /* why not */
} ident_job;

/* the fit of the noise-free forces as a table on out */
static void fit_print(FILE *out, const ident_plan *p, const ident_fit *r) {
  size_t j;
  int w = 12; /* the paper's names; the general model's are longer */
  for (j = 0; j < p->p; j++)
    if ((int)strlen(p->names[j]) > w) w = (int)strlen(p->names[j]);
  fprintf(out,
          "identification (%s, %zu samples): condition number %.4g, rank "
          "%zu, residual RMS %.3g N\n%-*s %14s %12s %14s %10s  %s\n",
          p->ids.method == IDENT_OLS ? "ols" : "wls", p->ns, r->cond, r->rank,
          r->resid_rms, w, "parameter", "estimate", "std", "truth", "share",
          "unit");
  for (j = 0; j < p->p; j++)
    fprintf(out, "%-*s %14.8g %12.3g %14.8g %9.3f%%  %s\n", w, p->names[j],
            r->theta[j], r->std[j], p->truth[j], 100 * p->share[j],
            p->general ? rps3_std_unit(p->lay_std[p->col[j]][0])
                       : rps3_paper_unit(p->col[j]));
  if (r->cstatus >= 0)
    fprintf(out, "consistent fit: %s%s%s\n",
            r->consistent ? "physically consistent" : "not consistent",
            r->cmsg[0] ? ": " : "", r->cmsg);
}

/* run_job's write: the fit, then the draws of this shard, then (a whole
   file) their summary */
static int ident_write(run_job *j, const out_meta *meta, progress *pr,
                       sweep_stats *st) {
  ident_job *ij = j->ctx;
  const run_args *a = ij->a;
  const ident_plan *p = ij->p;
  char err[512];
  out_file *f;
  int rc = 0;
  pr->njob_all = p->nunit ? p->nunit : 1;
  pr->njob = p->nunit ? pool_count(p->nunit, a->shard, a->nshard) : 1;
  pr->npoint = j->ncase * p->ns;
  f = ident_file_open(tmpout_path(), ij->s, p, ij->fit, ij->yaml, ij->why,
                      meta, err, sizeof err);
  if (!f) return run_io(a, err);
  if (p->ids.runs > 0)
    rc = ident_mc_run(p, f, a->shard, a->nshard, a->nthread, pr, st, err,
                      sizeof err);
  else {
    st->cases_done = 1;
    st->points_done = p->ns;
  }
  /* a part's summary is its merge's */
  if (rc == 0 && p->ids.runs > 0 && a->nshard == 1)
    rc = ident_summary(f->file, a->quiet ? NULL : stdout, err, sizeof err);
  if (rc) {
    out_close(f, NULL, 0);
    return run_io(a, err);
  }
  return out_close(f, err, sizeof err) ? run_io(a, err) : EXIT_OK;
}

/* text into path atomically: a temporary file next to it, fsync'd and
   renamed, then the directory fsync'd (as tmpout_commit does for the
   HDF5 file); 0 or -1 with a message on stderr */
static int write_atomic(const char *path, const char *textv) {
  char tmp[4096], dir[4096];
  size_t len = strlen(textv), off = 0;
  int fd, rc = -1;
  if (snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid()) >=
          (int)sizeof tmp ||
      path_dir(path, dir, sizeof dir)) {
    fprintf(stderr, "rps3-run: %s: the name is too long\n", path);
    return -1;
  }
  if ((fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0666)) < 0) {
    fprintf(stderr, "rps3-run: %s: cannot write: %s\n", tmp, strerror(errno));
    return -1;
  }
  while (off < len) {
    ssize_t n = write(fd, textv + off, len - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    off += (size_t)n;
  }
  if (off == len && fsync(fd) == 0 && close(fd) == 0) {
    fd = -1;
    if (rename(tmp, path) == 0) {
      int dfd = open(dir, O_RDONLY);
      rc = 0;
      if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
      }
    }
  }
  if (rc) {
    fprintf(stderr, "rps3-run: %s: cannot write: %s\n", path,
            strerror(errno));
    if (fd >= 0) close(fd);
    remove(tmp);
  }
  return rc;
}

/* the plan and the noise-free fit, or the exit code after the message */
static int ident_checks(const scene *s, const run_args *a, ident_plan *p,
                        ident_fit *fit) {
  scene_error serr;
  if (ident_plan_make(s, p, &serr)) {
    scene_error_print(a->scene_path, &serr);
    return EXIT_USAGE;
  }
  ident_fit_run(p, p->F0, p->ids.consistent, fit);
  if (fit->status != RPS3_OK) {
    fprintf(stderr,
            "%s: identify: %s not excite the parameters (condition number "
            "%.3g): %s\n",
            a->scene_path,
            p->measured ? "the data (identify.data) do" : "the trajectory does",
            fit->cond, fit->msg);
    return EXIT_USAGE;
  }
  if (a->shard_arg && p->ids.runs == 0) {
    fprintf(stderr,
            "rps3-run: --shard K/N splits the Monte Carlo's draws; "
            "this identification has none (identify.monte_carlo.runs "
            "0)\n");
    return EXIT_USAGE;
  }
  if (a->nshard > 1 && a->nshard > p->nunit) {
    fprintf(stderr,
            "rps3-run: --shard %s: the Monte Carlo has %zu work unit%s of %d "
            "draws: use at most %zu shards\n",
            a->shard_arg, p->nunit, p->nunit == 1 ? "" : "s", IDENT_UNIT,
            p->nunit);
    return EXIT_USAGE;
  }
  return -1;
}

int run_identify(scene *s, const run_args *a, const world *w, int argc,
                 char **argv) {
  ident_plan p;
  ident_fit fit;
  ident_job ij = {a, s, &p, &fit, NULL, NULL};
  run_job j = {"identification", "draw", 0, ident_write, &ij, ""};
  int code;
  char why[512] = "";
  char *yaml = NULL;
  if (w->size > 1) {
    if (w->rank == 0)
      fprintf(stderr,
              "rps3-run: an identification runs as one process; "
              "split its Monte Carlo with --shard K/N\n");
    return EXIT_USAGE;
  }
  memset(&fit, 0, sizeof fit);
  if (a->manip_path && a->out_path && strcmp(a->manip_path, a->out_path) == 0) {
    fprintf(stderr, "rps3-run: --manipulator %s: the output file's name\n",
            a->manip_path);
    return EXIT_USAGE;
  }
  if (a->manip_path) {
    const char *in[2] = {a->scene_path, a->out_path};
    char err[600];
    if (out_path_check(a->manip_path, in, a->out_path ? 2 : 1, err,
                       sizeof err)) {
      fprintf(stderr, "rps3-run: --manipulator %s: %s\n", a->manip_path, err);
      return EXIT_USAGE;
    }
  }
  if ((code = ident_checks(s, a, &p, &fit)) >= 0) {
    ident_fit_free(&fit);
    ident_plan_free(&p);
    return code;
  }
  yaml = ident_manipulator_yaml(&p, &fit, why, sizeof why);
  ij.yaml = yaml;
  ij.why = why;
  if (a->manip_path && !yaml) {
    fprintf(stderr, "rps3-run: --manipulator %s: %s: %s\n", a->manip_path,
            a->scene_path, why);
    ident_fit_free(&fit);
    ident_plan_free(&p);
    return EXIT_USAGE;
  }
  /* said even when quiet: a result that may be wrong */
  if (p.warning[0])
    fprintf(stderr, "rps3-run: warning: %s: %s\n", a->scene_path, p.warning);
  if (fit.cstatus > 0)
    fprintf(stderr, "rps3-run: warning: %s: the consistent fit: %s\n",
            a->scene_path, fit.cmsg);
  if (!a->quiet || a->check) fit_print(a->check ? stdout : stderr, &p, &fit);
  if (a->check) {
    printf(
        "%s: %zu samples, %zu parameters, %d Monte Carlo draws in %zu "
        "work units\n",
        a->scene_path, p.ns, p.p, p.ids.runs, p.nunit);
    free(yaml);
    ident_fit_free(&fit);
    ident_plan_free(&p);
    return EXIT_OK;
  }
  j.ncase = p.ids.runs > 0 ? ident_shard_draws(&p, a->shard, a->nshard) : 1;
  code = run_output(a, w, s, EXIT_OK, &j, argc, argv);
  /* the section once the file is complete */
  if ((code == EXIT_OK || code == EXIT_FAILED_CASES) && a->manip_path &&
      write_atomic(a->manip_path, yaml))
    code = EXIT_IO;
  free(yaml);
  ident_fit_free(&fit);
  ident_plan_free(&p);
  return code;
}
