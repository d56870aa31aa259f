/*
 * main_simstudy.c - rps3-simstudy: closed-loop tracking of the shipped
 * controllers, and what simulation accuracy costs in time (study_sim.c says
 * what is run and written).  The file, its temporary name and the exit
 * codes are those of every study program (study_run.c), and 4: a run that
 * must succeed failed.
 */
#include "study/study.h"

/* the options, in the order of SIMSTUDY_OPTS */
enum { O_OUTPUT, O_QUICK, O_VERSION, O_HELP, O_N };

static const cli_opt SIMSTUDY_OPTS[O_N] = {
    CLI_ROW_OUTPUT,
    {"quick", 0, NULL, 0, 0, 0, "shorter runs (0.5 s), one timing each"},
    CLI_ROW_VERSION,
    CLI_ROW_HELP,
};

static int simstudy_write(const char *path, const char *cmdline,
                          const study_args *a) {
  return study_sim(path, cmdline, (int)a->v[O_QUICK]);
}

static const study_prog SIMSTUDY = {
    "rps3-simstudy",
    SIMSTUDY_OPTS,
    O_N,
    "usage: rps3-simstudy -o OUT.h5 [--quick]\n"
    "       rps3-simstudy --help | --version\n\n"
    "Closed-loop tracking and what simulation accuracy costs in time.\n\n"
    "Options:\n",
    NULL,
    simstudy_write,
    1};

int main(int argc, char **argv) {
  study_args a = {.out = NULL};
  return study_main(&SIMSTUDY, &a, argc, argv);
}
