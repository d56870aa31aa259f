/*
 * cli.h - the command lines of rps3-run, rps3-study and rps3-simstudy,
 * each parsed by getopt_long from one option table, which also writes the
 * options' part of --help.  What users expect of getopt_long holds:
 * --output=F, --output F, -oF, -o F, -j2, -j 2, --jobs 2, flags bundled
 * (-qj2), a unique prefix of a long name (--out), options and operands in
 * any order, and "--" ends the options.  Numbers are strict (parse_ulong:
 * the whole argument is a decimal integer in its row's range).
 */
#ifndef RPS3_RUNNER_CLI_H
#define RPS3_RUNNER_CLI_H

#include <getopt.h>
#include <stdio.h>

/* the most rows of one table */
#define CLI_MAX 32

/* one option */
typedef struct {
  const char *name; /* long name, without "--" */
  int letter;       /* short name, or 0 for none */
  const char *arg;  /* the argument's name in --help; NULL: a flag */
  int num;          /* 1: the argument is a whole number in [lo, hi] */
  unsigned long lo, hi;
  const char *doc; /* --help text; '\n' continues on the next line */
} cli_opt;

/* the rows every program's table has */
#define CLI_ROW_OUTPUT                                                         \
  {                                                                            \
    "output", 'o', "OUT.h5", 0, 0, 0,                                          \
        "output file (written under a temporary name,\nrenamed when complete)" \
  }
#define CLI_ROW_VERSION \
  { "version", 0, NULL, 0, 0, 0, "print the version" }
#define CLI_ROW_HELP \
  { "help", 'h', NULL, 0, 0, 0, "print this help" }

/* a parse in progress (getopt_long's own state is process-wide: one
   parse at a time) */
typedef struct {
  const char *prog;     /* the program in messages ("rps3-run merge") */
  const char *help_cmd; /* the command whose --help lists these options
                           ("rps3-run" for merge); prog unless set */
  const cli_opt *opt;
  int nopt;
  int argc;
  char **argv;
  struct option lopt[CLI_MAX + 1];
  char shorts[3 * CLI_MAX + 2];
} cli;

/* what cli_next returns besides a row index */
enum { CLI_END = -1, CLI_BAD = -2 };

/* Start parsing argv[1..argc) with the nopt rows of opt (nopt <=
   CLI_MAX). */
void cli_start(cli *c, const char *prog, const cli_opt *opt, int nopt, int argc,
               char **argv);

/*
 * The next option: its row index, with *arg its argument (NULL for a
 * flag) and *num its value when the row is a number; CLI_END when no
 * option is left (the operands are then cli_operands'); CLI_BAD after a
 * message on stderr naming the option: unknown, without its argument, or
 * a number that is not one of the row's range.
 */
int cli_next(cli *c, const char **arg, unsigned long *num);

/* After CLI_END: the operands (arguments that are not options), in
   order; their number. */
int cli_operands(const cli *c, char ***first);

/* The options' part of --help: one row per option, its text aligned; a
   number's row ends with its range ("N is a whole number 1-1024"), the
   words of cli_next's message. */
void cli_help(FILE *out, const cli_opt *opt, int nopt);

/*
 * A usage error: "PROG: MESSAGE" and "Try 'HELP_CMD --help' for more
 * information." on stderr (GNU's form: what is wrong in one line, and
 * where the rest is).  cli_next reports its own errors this way.
 */
void cli_usage_error(const cli *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* The second line of a usage error: "Try 'HELP_CMD --help' for more
   information." on stderr. */
void cli_try(const char *help_cmd);

/* --version, in the GNU form: "PROG (rps3) VERSION", the copyright line,
   the licence lines and the no-warranty line (LICENSE). */
void cli_version(FILE *out, const char *prog);

/* The command line, each argument quoted for a POSIX shell when needed
   (malloc'd; NULL when out of memory). */
char *cli_command_line(int argc, char **argv);

#endif /* RPS3_RUNNER_CLI_H */
