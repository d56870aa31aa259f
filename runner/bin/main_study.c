/*
 * main_study.c - rps3-study: what accuracy costs in time (study_accuracy.c),
 * and the workspace (study_workspace.c); docs/accuracy.md says what is
 * measured and how.  The file, its temporary name and the exit codes are
 * those of every study program (study_run.c).
 */
#include <string.h>

#include "study/study.h"

/* the options, in the order of STUDY_OPTS */
enum { O_OUTPUT, O_SAMPLES, O_REPEATS, O_QUICK, O_VERSION, O_HELP, O_N };

static const cli_opt STUDY_OPTS[O_N] = {
    CLI_ROW_OUTPUT,
    {"samples", 0, "N", 1, 10, 1000000, "samples per trajectory (default 400)"},
    {"repeats", 0, "R", 1, 1, 1000, "timed passes per setting (default 9)"},
    {"quick", 0, NULL, 0, 0, 0, "a coarse workspace grid"},
    CLI_ROW_VERSION,
    CLI_ROW_HELP,
};

static const char *const STUDIES[] = {"accuracy", "workspace", NULL};

static int study_write(const char *path, const char *cmdline,
                       const study_args *a) {
  if (!strcmp(a->study, "accuracy"))
    return study_accuracy(path, cmdline, (size_t)a->v[O_SAMPLES],
                          (int)a->v[O_REPEATS]);
  return study_workspace(path, cmdline, (int)a->v[O_QUICK]);
}

static const study_prog STUDY = {
    "rps3-study",
    STUDY_OPTS,
    O_N,
    "usage: rps3-study accuracy -o OUT.h5 [--samples N] [--repeats R]\n"
    "       rps3-study workspace -o OUT.h5 [--quick]\n"
    "       rps3-study --help | --version\n"
    "\n"
    "Measure what accuracy costs in time, and map the workspace.\n"
    "\n"
    "Studies:\n"
    "  accuracy              what accuracy costs in time: every solver,\n"
    "                        tolerance, derivative, method, effect set and dt\n"
    "                        against a precise reference (docs/accuracy.md)\n"
    "  workspace             status, conditioning and assembly mode over a\n"
    "                        (rho, alpha, beta, z_c) grid\n"
    "\n"
    "Options:\n",
    STUDIES,
    study_write,
    0};

int main(int argc, char **argv) {
  study_args a = {.v = {[O_SAMPLES] = 400, [O_REPEATS] = 9}};
  return study_main(&STUDY, &a, argc, argv);
}
