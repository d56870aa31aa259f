/*
 * cmd_merge.c - `rps3-run merge`: see cmd.h.
 */
#include "cmd_merge.h"
#include "core/exit_codes.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/cli.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "join.h"
#include "merge.h"
#include "parts.h"
#include "verify.h"

/* the options of merge */
static const cli_opt MERGE_OPTS[3] = {
    {"copy", 0, NULL, 0, 0, 0,
     "one self-contained file: the parts' chunks copied\n(default: virtual "
     "datasets over the parts)"},
    {"failed-ok", 0, NULL, 0, 0, 0, "exit 0, not 1, when some cases failed"},
    {"quiet", 'q', NULL, 0, 0, 0, "say nothing when all went well"}};

/*
 * rps3-run merge OUT.h5 PART.h5 ...: the parts of shards 0..N-1, in any
 * order.  By default OUT.h5 is a file of virtual datasets over the parts
 * (join.h); with --copy it is a copy of part 0 into which the other parts'
 * chunks are copied (merge.h).  Either is written under a temporary name
 * and renamed when complete.  A missing or incomplete part is named, with
 * the command that makes it again (parts.h).
 */
int merge_main(int argc, char **argv, const char *cmd) {
  const char *out_path = NULL, **part = NULL, **byk = NULL, **src = NULL;
  size_t npart = 0, n = 0, i, *ks = NULL, nfailed = 0;
  int quiet = 0, copy = 0, failed_ok = 0, code = EXIT_USAGE, *bad = NULL;
  char err[768], **op;
  cli c;
  const char *arg;
  unsigned long v;
  int row, nop;

  part = calloc((size_t)argc, sizeof *part);
  if (!part) {
    fprintf(stderr, "rps3-run: out of memory\n");
    return EXIT_IO;
  }
  cli_start(&c, "rps3-run merge", MERGE_OPTS, 3, argc, argv);
  c.help_cmd = "rps3-run"; /* its --help lists merge's options */
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    if (row == CLI_BAD) goto done;
    if (row == 0)
      copy = 1;
    else if (row == 1)
      failed_ok = 1;
    else
      quiet = 1;
  }
  nop = cli_operands(&c, &op);
  if (nop > 0) out_path = op[0];
  for (i = 1; i < (size_t)nop; i++) part[npart++] = op[i];
  if (!out_path || npart == 0) {
    cli_usage_error(&c, "%s (rps3-run merge OUT.h5 PART.h5...)",
                    out_path ? "missing the part files"
                             : "missing OUT.h5 "
                               "and the part "
                               "files");
    goto done;
  }

  /* every shard 0..N-1 exactly once, each complete */
  if (parts_by_shard(part, npart, &byk, &n, err, sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    goto done;
  }
  bad = calloc(n, sizeof *bad);
  src = calloc(n, sizeof *src);
  ks = calloc(n, sizeof *ks);
  if (!bad || !src || !ks) {
    fprintf(stderr, "rps3-run: out of memory\n");
    code = EXIT_IO;
    goto done;
  }
  for (i = 0; i < n; i++)
    if (byk[i] && join_part_check(byk[i], i, n, NULL, err, sizeof err)) {
      fprintf(stderr, "rps3-run merge: %s\n", err);
      bad[i] = 1;
    }
  if (npart != n)
    fprintf(stderr,
            "rps3-run merge: %zu part%s given, the run has %zu "
            "shards\n",
            npart, npart == 1 ? "" : "s", n);
  if (parts_report(stderr, byk, bad, n)) goto done;
  if (out_path_check(out_path, part, npart, err, sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    goto done;
  }
  stale_report("rps3-run merge", out_path);
  if (verify_same_versions(byk, n, err, sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    goto done;
  }
  /* the same data too: a table measured again between the shards makes
     parts of two runs under one scene text */
  if (verify_parts_inputs(byk, n, bad, "rps3-run merge", stderr)) {
    parts_report(stderr, byk, bad, n);
    goto done;
  }

  /* every chunk of every part decodes (checksums, compression) before the
     merged file can claim the parts' cases */
  code = EXIT_IO;
  for (i = 0; i < n; i++)
    if (verify_file(byk[i], err, sizeof err)) {
      fprintf(stderr, "rps3-run merge: %s\n", err);
      goto done;
    }
  if (tmpout_name(out_path, 0)) goto done;
  tmpout_arm();
  for (i = 1; i < n; i++) {
    src[i - 1] = byk[i];
    ks[i - 1] = i;
  }
  if (copy ? merge_copy_file(byk[0], tmpout_path(), err, sizeof err) ||
                 merge_parts(tmpout_path(), src, ks, n - 1, n, cmd, &nfailed,
                             err, sizeof err)
           : join_vds(tmpout_path(), byk, n, cmd, &nfailed, err, sizeof err)) {
    fprintf(stderr, "rps3-run merge: %s\n", err);
    goto done;
  }
  if (tmpout_commit(out_path)) goto done;
  if (!quiet)
    fprintf(stderr,
            "rps3-run: %s %zu part%s into %s (%zu failed "
            "case%s)\n",
            copy ? "merged" : "joined", n, n == 1 ? "" : "s", out_path, nfailed,
            nfailed == 1 ? "" : "s");
  code = nfailed && !failed_ok ? EXIT_FAILED_CASES : EXIT_OK;
done:
  tmpout_discard();
  free(part);
  free(byk);
  free(bad);
  free(src);
  free(ks);
  return code;
}
