/*
 * cmd_merge.c - `rps3-run merge` (merge.h).
 */
#include "core/exit_codes.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cli.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "merge.h"
#include "verify.h"

/* the options of merge */
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
  if (m->copy ? merge_copy_file(m->byk[0], tmpout_path(), err, sizeof err) ||
                    merge_parts(tmpout_path(), m->byk, m->n, cmd, nfailed, err,
                                sizeof err)
              : join_vds(tmpout_path(), m->byk, m->n, cmd, nfailed, err,
                         sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    return -1;
  }
  return tmpout_commit(m->out_path) ? -1 : 0;
}

int merge_main(int argc, char **argv) {
  merge_run m;
  size_t nfailed = 0;
  int code = EXIT_USAGE, *bad = NULL;
  char err[768], *cmd = cli_command_line(argc, argv);
  memset(&m, 0, sizeof m);
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
