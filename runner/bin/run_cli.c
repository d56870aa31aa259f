/*
 * run_cli.c - rps3-run's command lines (run_steps.h).
 */
#include "run_steps.h"

#include <stdio.h>
#include <string.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "output/output.h"
#include "scene/scene.h"

/* most threads of -j */
#define MAX_THREADS 1024

/* the options of a run, one row each: X(its enum, its cli_opt row); one
   table for getopt_long and --help (cli.h) */
#define RUN_OPTIONS(X)                                                        \
  X(O_OUTPUT, CLI_ROW_OUTPUT)                                                 \
  X(O_QUIET, {"quiet", 'q', NULL, 0, 0, 0, "no progress on stderr"})          \
  X(O_GZIP, {"gzip", 0, "LEVEL", 1, 0, 9,                                     \
             "deflate the datasets at LEVEL (default 0: not\ndeflated)"})     \
  X(O_FIELDS, {"fields", 0, "LIST", 0, 0, 0,                                  \
               "write only these per-sample fields (force,length,...)"})      \
  X(O_CHECK, {"check", 0, NULL, 0, 0, 0,                                      \
              "validate the scene and every case, print the\nestimated "      \
              "output size and run time, write nothing"})                     \
  X(O_JOBS, {"jobs", 'j', "N", 1, 1, MAX_THREADS,                             \
             "compute on N threads (default 1); same output"})                \
  X(O_SHARD, {"shard", 0, "K/N", 0, 0, 0,                                     \
              "compute shard K of N (0 <= K < N <= work units)\ninto a part " \
              "file"})                                                        \
  X(O_RESUME, {"resume", 0, NULL, 0, 0, 0,                                    \
               "keep OUT.h5 when it is that part, complete"})                 \
  X(O_FAILED_OK, {"failed-ok", 0, NULL, 0, 0, 0,                              \
                  "exit 0, not 1, when the file is complete but some\ncases " \
                  "failed"})                                                  \
  X(O_COPY, {"copy", 0, NULL, 0, 0, 0,                                        \
             "rps3-run-mpi under mpirun: rank 0 merges the parts\ninto one "  \
             "self-contained file (default: joins them)"})                    \
  X(O_MANIPULATOR, {"manipulator", 0, "FILE", 0, 0, 0,                       \
                    "identification: write the fitted manipulator:\n"       \
                    "section (YAML) to FILE"})                                \
  X(O_KEYS, {"keys", 0, NULL, 0, 0, 0, "print the scene keys (markdown)"})    \
  X(O_SCHEMA,                                                                 \
    {"schema", 0, NULL, 0, 0, 0, "print the datasets of OUT.h5 (markdown)"})  \
  X(O_SIM_SCHEMA, {"sim-schema", 0, NULL, 0, 0, 0,                            \
                   "... of OUT.h5 of a scene with a simulate section"})       \
  X(O_DESIGN_SCHEMA, {"design-schema", 0, NULL, 0, 0, 0,                      \
                      "... of OUT.h5 of a scene with a design section"})      \
  X(O_VERSION, CLI_ROW_VERSION)                                               \
  X(O_HELP, CLI_ROW_HELP)
#define ROW_ENUM(o, ...) o,
#define ROW_OPT(o, ...) __VA_ARGS__,
enum { RUN_OPTIONS(ROW_ENUM) O_N };
static const cli_opt RUN_OPTS[O_N] = {RUN_OPTIONS(ROW_OPT)};

static const char USAGE[] =
    "usage: rps3-run SCENE.yaml -o OUT.h5 [OPTION]...\n"
    "       rps3-run SCENE.yaml --check [OPTION]...\n"
    "       rps3-run merge OUT.h5 PART.h5... [--copy] [--failed-ok] [--quiet]\n"
    "       mpirun -n N rps3-run-mpi SCENE.yaml -o OUT.h5 [OPTION]...\n"
    "       rps3-run --clean OUT.h5 [--force]\n"
    "       rps3-run --keys | --schema | --sim-schema | --design-schema\n"
    "       rps3-run --version | --help\n"
    "\n"
    "Run the scenes of the Lee & Shah 3-RPS manipulator into HDF5 files.\n"
    "\n"
    "Computes the inverse dynamics along the scene's trajectory, for every\n"
    "case of its sweep, into OUT.h5; a scene with a simulate section is\n"
    "simulated in closed loop instead (docs/runner.md, \"Simulation\").\n"
    "\n"
    "Options:\n";

static const char COMMANDS[] =
    "\n"
    "Commands:\n"
    "  merge                 join the part files of shards 0..N-1 into OUT.h5\n"
    "                        (virtual datasets over the parts; --copy: one\n"
    "                        self-contained file)\n"
    "  --clean               remove the temporaries of OUT.h5 left by dead\n"
    "                        processes (--force: those of other hosts too)\n"
    "\n"
    "Options take their value as --gzip=4, --gzip 4, -j2 or -j 2.\n"
    "\n"
    "Exit status: 0 ok, 1 some cases failed, 2 bad scene or usage, 3 cannot\n"
    "write.\n";

static void usage(FILE *out) {
  fputs(USAGE, out);
  cli_help(out, RUN_OPTS, O_N);
  fputs(COMMANDS, out);
}

/* K/N into *k, *n, strictly (digits only, 0 <= K < N); 0 or -1 */
static int parse_shard(const char *a, size_t *k, size_t *n) {
  char kk[32], nn[32], tail;
  unsigned long vk, vn;
  if (sscanf(a, "%31[0-9]/%31[0-9]%c", kk, nn, &tail) != 2 ||
      parse_ulong(kk, 0, (unsigned long)-1, &vk) ||
      parse_ulong(nn, 1, (unsigned long)-1, &vn) || vk >= vn)
    return -1;
  *k = vk;
  *n = vn;
  return 0;
}

/* an option that prints and ends the program; 0 when it is not one */
static int print_and_end(int row) {
  switch (row) {
  case O_HELP: usage(stdout); return 1;
  case O_VERSION: cli_version(stdout, "rps3-run"); return 1;
  case O_KEYS: scene_keys_print(); return 1;
  case O_SCHEMA: out_schema_print(OUT_INV); return 1;
  case O_SIM_SCHEMA: out_schema_print(OUT_SIM); return 1;
  case O_DESIGN_SCHEMA: out_schema_print(OUT_DESIGN); return 1;
  default: return 0;
  }
}

/* one option of a run into a; 0, or -1 after a message */
static int run_option(const cli *c, run_args *a, int row, const char *arg,
                      unsigned long v) {
  char err[512];
  switch (row) {
  case O_OUTPUT: a->out_path = arg; break;
  case O_QUIET: a->quiet = 1; break;
  case O_GZIP: a->gzip = (int)v; break;
  case O_CHECK: a->check = 1; break;
  case O_JOBS: a->nthread = (int)v; break;
  case O_RESUME: a->resume = 1; break;
  case O_FAILED_OK: a->failed_ok = 1; break;
  case O_COPY: a->copy = 1; break;
  case O_MANIPULATOR: a->manip_path = arg; break;
  case O_FIELDS:
    if (out_fields_parse(arg, &a->fields, err, sizeof err)) {
      cli_usage_error(c, "%s", err);
      return -1;
    }
    break;
  case O_SHARD:
    a->shard_arg = arg;
    if (parse_shard(arg, &a->shard, &a->nshard)) {
      cli_usage_error(c, "--shard needs K/N with 0 <= K < N, got '%s'", arg);
      return -1;
    }
    break;
  default: return -1;
  }
  return 0;
}

int run_args_parse(int argc, char **argv, run_args *a) {
  cli c;
  const char *arg;
  unsigned long v;
  char **op;
  int row, nop;
  memset(a, 0, sizeof *a);
  a->nshard = 1;
  a->nthread = 1;
  a->fields = out_fields_all();
  cli_start(&c, "rps3-run", RUN_OPTS, O_N, argc, argv);
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    if (row == CLI_BAD) return EXIT_USAGE;
    if (print_and_end(row)) return EXIT_OK;
    if (run_option(&c, a, row, arg, v)) return EXIT_USAGE;
  }
  nop = cli_operands(&c, &op);
  if (nop > 1) {
    cli_usage_error(&c, "one scene at a time ('%s' and '%s')", op[0], op[1]);
    return EXIT_USAGE;
  }
  a->scene_path = nop ? op[0] : NULL;
  if (!a->scene_path) {
    cli_usage_error(&c,
                    "missing the scene file (rps3-run SCENE.yaml -o OUT.h5)");
    return EXIT_USAGE;
  }
  if (!a->out_path && !a->check) {
    cli_usage_error(&c, "missing -o OUT.h5 (or --check, which writes nothing)");
    return EXIT_USAGE;
  }
  return -1;
}

/* the options of --clean */
static const cli_opt CLEAN_OPTS[1] = {
    {"force", 0, NULL, 0, 0, 0,
     "also those of other hosts and of unknown owners"}};

int clean_main(int argc, char **argv) {
  cli c;
  const char *arg;
  unsigned long v;
  char **op;
  int row, nop, force = 0;
  cli_start(&c, "rps3-run --clean", CLEAN_OPTS, 1, argc - 1, argv + 1);
  c.help_cmd = "rps3-run";
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    if (row == CLI_BAD) return EXIT_USAGE;
    force = 1;
  }
  nop = cli_operands(&c, &op);
  if (nop != 1) {
    if (nop == 0)
      cli_usage_error(&c, "missing OUT.h5 (rps3-run --clean OUT.h5 [--force])");
    else
      cli_usage_error(&c, "one OUT.h5 at a time ('%s' and '%s')", op[0], op[1]);
    return EXIT_USAGE;
  }
  return tmpout_clean(op[0], force, 0) < 0 ? EXIT_IO : EXIT_OK;
}
