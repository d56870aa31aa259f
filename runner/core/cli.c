/* cli.c - see cli.h. */
#include "cli.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "rps3.h"
#include "safeio.h"

/* getopt_long's value of a long option: past every char, so that it never
   meets a short option's letter */
#define CLI_LONG 256

/* the column of the options' text in --help */
#define HELP_COL 24

void cli_start(cli *c, const char *prog, const cli_opt *opt, int nopt, int argc,
               char **argv) {
  char *s = c->shorts;
  int i;
  c->prog = prog;
  c->help_cmd = prog;
  c->opt = opt;
  c->nopt = nopt < CLI_MAX ? nopt : CLI_MAX;
  c->argc = argc;
  c->argv = argv;
  /* ':' first: a missing argument is told apart from an unknown option */
  *s++ = ':';
  for (i = 0; i < c->nopt; i++) {
    c->lopt[i].name = opt[i].name;
    c->lopt[i].has_arg = opt[i].arg ? required_argument : no_argument;
    c->lopt[i].flag = NULL;
    c->lopt[i].val = CLI_LONG + i;
    if (opt[i].letter) {
      *s++ = (char)opt[i].letter;
      if (opt[i].arg) *s++ = ':';
    }
  }
  *s = '\0';
  memset(&c->lopt[c->nopt], 0, sizeof c->lopt[c->nopt]);
  /* a fresh parse, and the messages are ours */
  optind = 1;
  opterr = 0;
}

/* the row of a short option's letter, or -1 */
static int row_of_letter(const cli *c, int letter) {
  int i;
  for (i = 0; i < c->nopt; i++)
    if (c->opt[i].letter && c->opt[i].letter == letter) return i;
  return -1;
}

/* the option's name as a user knows it: "-j" when it has a letter */
static void display_name(const cli_opt *o, char *buf, size_t size) {
  if (o->letter)
    snprintf(buf, size, "-%c", o->letter);
  else
    snprintf(buf, size, "--%s", o->name);
}

int cli_next(cli *c, const char **arg, unsigned long *num) {
  char name[64];
  int r = getopt_long(c->argc, c->argv, c->shorts, c->lopt, NULL), row;
  *arg = NULL;
  *num = 0;
  if (r == -1) return CLI_END;
  if (r == '?') {
    if (optopt > 0 && optopt < CLI_LONG)
      cli_usage_error(c, "unknown option '-%c'", optopt);
    else
      cli_usage_error(c, "unknown option '%s'", c->argv[optind - 1]);
    return CLI_BAD;
  }
  if (r == ':') {
    row = optopt >= CLI_LONG ? optopt - CLI_LONG : row_of_letter(c, optopt);
    if (row >= 0)
      display_name(&c->opt[row], name, sizeof name);
    else
      snprintf(name, sizeof name, "-%c", optopt);
    cli_usage_error(c, "%s needs a value", name);
    return CLI_BAD;
  }
  row = r >= CLI_LONG ? r - CLI_LONG : row_of_letter(c, r);
  if (row < 0 || row >= c->nopt) return CLI_BAD;
  *arg = optarg;
  if (c->opt[row].num &&
      parse_ulong(optarg, c->opt[row].lo, c->opt[row].hi, num)) {
    display_name(&c->opt[row], name, sizeof name);
    cli_usage_error(c, "%s needs a whole number %lu-%lu, got '%s'", name,
                    c->opt[row].lo, c->opt[row].hi, optarg);
    return CLI_BAD;
  }
  return row;
}

void cli_usage_error(const cli *c, const char *fmt, ...) {
  va_list ap;
  fprintf(stderr, "%s: ", c->prog);
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
  cli_try(c->help_cmd);
}

void cli_try(const char *help_cmd) {
  fprintf(stderr, "Try '%s --help' for more information.\n", help_cmd);
}

void cli_version(FILE *out, const char *prog) {
  fprintf(
      out,
      "%s (rps3) %s\n"
      "Copyright (C) 2026 the rps3 authors.\n"
      "License BSD-3-Clause <https://opensource.org/licenses/BSD-3-Clause>.\n"
      "Linked with GSL: GNU GPL version 3 or later "
      "<https://gnu.org/licenses/gpl.html>.\n"
      "This is free software: you are free to change and redistribute it.\n"
      "There is NO WARRANTY, to the extent permitted by law.\n",
      prog, rps3_version());
}

int cli_operands(const cli *c, char ***first) {
  *first = c->argv + optind;
  return c->argc - optind;
}

void cli_help(FILE *out, const cli_opt *opt, int nopt) {
  int i;
  for (i = 0; i < nopt; i++) {
    const char *d = opt[i].doc, *nl;
    char left[96], letter[8] = "";
    int n;
    if (opt[i].letter) snprintf(letter, sizeof letter, "-%c, ", opt[i].letter);
    n = snprintf(left, sizeof left, "  %s--%s%s%s", letter, opt[i].name,
                 opt[i].arg ? " " : "", opt[i].arg ? opt[i].arg : "");
    /* a long left part: the text starts on the next line */
    if (n >= HELP_COL - 1)
      fprintf(out, "%s\n%*s", left, HELP_COL, "");
    else
      fprintf(out, "%-*s", HELP_COL, left);
    while ((nl = strchr(d, '\n')) != NULL) {
      fprintf(out, "%.*s\n%*s", (int)(nl - d), d, HELP_COL, "");
      d = nl + 1;
    }
    fprintf(out, "%s\n", d);
    if (opt[i].num)
      fprintf(out, "%*s%s is a whole number %lu-%lu\n", HELP_COL, "",
              opt[i].arg, opt[i].lo, opt[i].hi);
  }
}

char *cli_command_line(int argc, char **argv) {
  size_t len = 1, i;
  char *s, *p;
  for (i = 0; i < (size_t)argc; i++) len += 4 * strlen(argv[i]) + 3;
  s = malloc(len);
  if (!s) return NULL;
  p = s;
  for (i = 0; i < (size_t)argc; i++) {
    const char *a = argv[i];
    int plain = a[0] != '\0' &&
                strspn(a,
                       "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                       "0123456789-_./=:,+@%") == strlen(a);
    if (i) *p++ = ' ';
    if (plain) {
      strcpy(p, a);
      p += strlen(a);
      continue;
    }
    *p++ = '\'';
    for (; *a; a++) {
      if (*a == '\'') {
        memcpy(p, "'\\''", 4);
        p += 4;
      } else
        *p++ = *a;
    }
    *p++ = '\'';
  }
  *p = '\0';
  return s;
}
