/*
 * parts.c - the part files by shard, what to do about missing ones, and
 * the `rps3-run merge` command that checks and joins them (merge.h).
 */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hdf5.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "exec/ident_run.h"
#include "merge.h"
#include "output/out_h5.h"
#include "verify.h"

int parts_by_shard(const char *const *part, size_t npart, const char ***byk,
                   size_t *n, char *err, size_t errsz) {
  const char **by = NULL;
  size_t i, k, nn, n0 = 0;
  *byk = NULL;
  for (i = 0; i < npart; i++) {
    if (merge_shard_of(part[i], &k, &nn, err, errsz)) goto fail;
    if (i == 0) {
      n0 = nn;
      if (!(by = calloc(nn, sizeof *by))) {
        snprintf(err, errsz, "out of memory");
        return -1;
      }
    }
    if (nn != n0) {
      snprintf(err, errsz, "%s is shard %zu/%zu, %s is of %zu", part[i], k, nn,
               part[0], n0);
      goto fail;
    }
    if (by[k]) {
      snprintf(err, errsz, "%s and %s are both shard %zu/%zu", by[k], part[i],
               k, nn);
      goto fail;
    }
    by[k] = part[i];
  }
  *byk = by;
  *n = n0;
  return 0;
fail:
  free(by);
  return -1;
}

/* the end of the shell word at s (plain or single-quoted pieces, as
   main_run.c's command_line writes them) */
static const char *word_end(const char *s) {
  while (*s && *s != ' ') {
    if (*s == '\'') {
      const char *q = strchr(s + 1, '\'');
      s = q ? q + 1 : s + strlen(s);
    } else
      s++;
  }
  return s;
}

/* the output name of shard k on t: `was` (of shard k0) with its one number
   k0 replaced by k; PART_k.h5 when there is no such single number or the
   name is quoted */
static void put_part_name(FILE *t, const char *was, size_t len, size_t k0,
                          size_t k) {
  const char *p, *hit = NULL, *base = was;
  size_t nhit = 0, hitlen = 0;
  for (p = was; p < was + len; p++)
    if (*p == '/') base = p + 1;
  for (p = base; p < was + len;) {
    if (isdigit((unsigned char)*p)) {
      const char *q = p;
      while (q < was + len && isdigit((unsigned char)*q)) q++;
      if (strtoul(p, NULL, 10) == k0 && (size_t)(q - p) < 20) {
        hit = p;
        hitlen = (size_t)(q - p);
        nhit++;
      }
      p = q;
    } else
      p++;
  }
  if (nhit != 1 || memchr(was, '\'', len))
    fprintf(t, "PART_%zu.h5", k);
  else
    fprintf(t, "%.*s%zu%.*s", (int)(hit - was), was, k,
            (int)(len - (size_t)(hit - was) - hitlen), hit + hitlen);
}

/* the command that makes shard k again, from the command_line of a part
   `model` (malloc'd; NULL when out of memory or when `model` has none) */
static char *rerun_command(const char *model, size_t k, size_t n) {
  const char *p = model, *e, *sh;
  size_t k0 = (size_t)-1, len = 0;
  char *out = NULL;
  FILE *t;
  if (!model || !(t = open_memstream(&out, &len))) return NULL;
  /* the model's own shard number, for its output name */
  if ((sh = strstr(model, " --shard ")) != NULL) k0 = strtoul(sh + 9, NULL, 10);
  while (*p) {
    e = word_end(p);
    fwrite(p, 1, (size_t)(e - p), t);
    if ((e - p == 2 && strncmp(p, "-o", 2) == 0) ||
        (e - p == 7 && strncmp(p, "--shard", 7) == 0)) {
      int is_o = p[1] == 'o';
      for (p = e; *p == ' '; p++) fputc(' ', t);
      e = word_end(p);
      if (is_o)
        put_part_name(t, p, (size_t)(e - p), k0, k);
      else
        fprintf(t, "%zu/%zu", k, n);
    }
    for (p = e; *p == ' '; p++) fputc(' ', t);
  }
  if (fclose(t) != 0) {
    free(out);
    return NULL;
  }
  return out;
}

size_t parts_report(FILE *out, const char *const *byk, const int *bad,
                    size_t n) {
  size_t k, nmiss = 0;
  const char *model = NULL;
  char *cmd = NULL;
  for (k = 0; k < n; k++) {
    if (byk[k] && !(bad && bad[k]) && !model) model = byk[k];
    nmiss += !byk[k] || (bad && bad[k]);
  }
  if (nmiss == 0) return 0;
  if (!model) /* every part bad: the first given one still has the command */
    for (k = 0; k < n && !model; k++) model = byk[k];
  fprintf(out, "rps3-run merge: %zu of %zu shard%s to run again: ", nmiss, n,
          n == 1 ? "" : "s");
  for (k = 0, nmiss = 0; k < n; k++)
    if (!byk[k] || (bad && bad[k]))
      fprintf(out, "%s%zu", nmiss++ ? "," : "", k);
  fprintf(out, "\n");
  if (model) cmd = verify_root_attr(model, "command_line");
  if (!cmd) {
    fprintf(out, "  (rps3-run SCENE -o PART --shard K/%zu for each)\n", n);
    return nmiss;
  }
  fprintf(out, "  from the directory the parts were made in:\n");
  for (k = 0; k < n; k++)
    if (!byk[k] || (bad && bad[k])) {
      char *c = rerun_command(cmd, k, n);
      fprintf(out, "  %s\n", c ? c : "(out of memory)");
      free(c);
    }
  free(cmd);
  return nmiss;
}

/* the stderr line of a --resume that computes the part again: 0 */
static int run_again(const char *why, size_t k, size_t n) {
  fprintf(stderr, "rps3-run: --resume: %s: running shard %zu/%zu again\n", why,
          k, n);
  return 0;
}

int parts_resume(const char *path, size_t k, size_t n, const char *text0,
                 const char *fields, const char *inputs, size_t *nfailed) {
  char err[1024], *have;
  hid_t f;
  int rc = -1;
  size_t unset = 0;
  if (access(path, F_OK) != 0) return 0;
  if (merge_part_check(path, k, n, text0, err, sizeof err))
    return run_again(err, k, n);
  /* a part of other fields would not merge with this run's parts */
  have = verify_root_attr(path, "fields");
  if (!have || strcmp(have, fields) != 0) {
    snprintf(err, sizeof err, "%s has the fields %s, this run writes %s", path,
             have ? have : "(none)", fields);
    free(have);
    return run_again(err, k, n);
  }
  free(have);
  /* the same scene text over other data (a table measured again) is
     another run: its cases would not be this run's */
  if (verify_inputs_as(path, inputs, "the file now has", err, sizeof err))
    return run_again(err, k, n);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f >= 0) {
    rc = merge_count_failed(f, k, n, nfailed, &unset, NULL);
    H5Fclose(f);
  }
  snprintf(err, sizeof err, "%s: cannot read status", path);
  /* the cases of this shard only: the other shards' read as the fill
     value (not computed), no failure of this one */
  return rc < 0 ? run_again(err, k, n) : 1;
}

static const cli_opt MERGE_OPTS[3] = {
    {"copy", 0, NULL, 0, 0, 0,
     "one self-contained file: the parts' chunks copied\n(default: virtual "
     "datasets over the parts)"},
    {"failed-ok", 0, NULL, 0, 0, 0, "exit 0, not 1, when some cases failed"},
    {"quiet", 'q', NULL, 0, 0, 0, "say nothing when all went well"}};

/* what merge was asked, and the parts by shard */
typedef struct {
  const char *out_path, *const *part, **byk;
  size_t npart, n; /* parts given, shards of the run */
  int quiet, copy, failed_ok;
} merge_run;

/* the options and operands into m: 0, or -1 (said why) */
static int merge_args(merge_run *m, int argc, char **argv) {
  cli c;
  const char *arg;
  unsigned long v;
  char **op;
  /* what each row of MERGE_OPTS sets */
  int row, nop, *flag[3] = {&m->copy, &m->failed_ok, &m->quiet};
  cli_start(&c, "rps3-run merge", MERGE_OPTS, 3, argc, argv);
  c.help_cmd = "rps3-run"; /* its --help lists merge's options */
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    if (row == CLI_BAD) return -1;
    *flag[row] = 1;
  }
  /* OUT.h5, then the parts: the operands as getopt_long left them */
  nop = cli_operands(&c, &op);
  if (nop > 0) m->out_path = op[0];
  m->part = (const char *const *)op + 1;
  m->npart = nop > 1 ? (size_t)nop - 1 : 0;
  if (!m->out_path || m->npart == 0) {
    cli_usage_error(&c, "%s (rps3-run merge OUT.h5 PART.h5...)",
                    m->out_path ? "missing the part files"
                                : "missing OUT.h5 and the part files");
    return -1;
  }
  return 0;
}

/* every shard 0..N-1 exactly once, each complete, of one build and one
   set of inputs, OUT.h5 none of them: 0, or -1 (said why) */
static int merge_parts_check(merge_run *m, int *bad) {
  char err[768];
  size_t i;
  for (i = 0; i < m->n; i++)
    if (m->byk[i] &&
        merge_part_check(m->byk[i], i, m->n, NULL, err, sizeof err)) {
      fprintf(stderr, "rps3-run merge: %s\n", err);
      bad[i] = 1;
    }
  if (m->npart != m->n)
    fprintf(stderr,
            "rps3-run merge: %zu part%s given, the run has %zu shards\n",
            m->npart, m->npart == 1 ? "" : "s", m->n);
  if (parts_report(stderr, m->byk, bad, m->n)) return -1;
  if (out_path_check(m->out_path, m->part, m->npart, err, sizeof err) ||
      (stale_report("rps3-run merge", m->out_path),
       verify_same_versions(m->byk, m->n, err, sizeof err))) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    return -1;
  }
  /* the same data too: a table measured again between the shards makes
     parts of two runs under one scene text */
  if (verify_parts_inputs(m->byk, m->n, bad, "rps3-run merge", stderr)) {
    parts_report(stderr, m->byk, bad, m->n);
    return -1;
  }
  return 0;
}

/* every chunk of every part decodes (checksums, compression), then the
   merged file under a temporary name, renamed when complete: 0, or -1
   (said why) */
static int merge_write(const merge_run *m, const char *cmd, size_t *nfailed) {
  char err[768];
  size_t i;
  for (i = 0; i < m->n; i++)
    if (verify_file(m->byk[i], err, sizeof err)) {
      fprintf(stderr, "rps3-run merge: %s\n", err);
      return -1;
    }
  if (tmpout_name(m->out_path, 0)) return -1;
  tmpout_arm();
  if ((m->copy ? merge_copy_file(m->byk[0], tmpout_path(), err, sizeof err) ||
                     merge_parts(tmpout_path(), m->byk, m->n, cmd, nfailed, err,
                                 sizeof err)
               : join_vds(tmpout_path(), m->byk, m->n, cmd, nfailed, err,
                          sizeof err)) ||
      /* an identification's summary of the draws (ident_run.h) */
      ident_summary_path(tmpout_path(), m->quiet ? NULL : stdout, err,
                         sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    return -1;
  }
  return tmpout_commit(m->out_path) ? -1 : 0;
}

int merge_main(int argc, char **argv) {
  merge_run m = {0};
  size_t nfailed = 0;
  int code = EXIT_USAGE, *bad = NULL;
  char err[768], *cmd = cli_command_line(argc, argv);
  if (!cmd) {
    fprintf(stderr, "rps3-run: out of memory\n");
    return EXIT_IO;
  }
  if (merge_args(&m, argc - 1, argv + 1)) goto done;
  if (parts_by_shard(m.part, m.npart, &m.byk, &m.n, err, sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    goto done;
  }
  if (!(bad = calloc(m.n, sizeof *bad))) {
    fprintf(stderr, "rps3-run: out of memory\n");
    code = EXIT_IO;
    goto done;
  }
  if (merge_parts_check(&m, bad)) goto done;
  code = EXIT_IO;
  if (merge_write(&m, cmd, &nfailed)) goto done;
  if (!m.quiet)
    fprintf(stderr, "rps3-run: %s %zu part%s into %s (%zu failed case%s)\n",
            m.copy ? "merged" : "joined", m.n, m.n == 1 ? "" : "s", m.out_path,
            nfailed, nfailed == 1 ? "" : "s");
  code = nfailed && !m.failed_ok ? EXIT_FAILED_CASES : EXIT_OK;
done:
  tmpout_discard();
  free(cmd);
  free(m.byk);
  free(bad);
  return code;
}
