/*
 * tmpout.c - see tmpout.h.  The file itself, the fsync before the rename
 * and the signals are signals.c's; this names it after rps3-run's rules.
 */
#include "tmpout.h"

#include <stdio.h>

#include "signals.h"

/* the name, before and after tmpout_arm: process-wide state of this
   program only (the library has none) */
static char tmp_path[4096];

const char *tmpout_path(void)
{
  return tmp_path;
}

void tmpout_arm(void)
{
  /* the name fits: tmpout_name checked its length */
  tmp_set(tmp_path);
}

int tmpout_commit(const char *out_path)
{
  char err[2 * sizeof tmp_path + 128];
  if (tmp_commit(out_path, err, sizeof err)) {
    fprintf(stderr, "rps3-run: %s\n", err);
    return -1;
  }
  return 0;
}

void tmpout_discard(void)
{
  tmp_discard();
}

int tmpout_name(const char *out_path, long pid, int rank)
{
  int n = rank ? snprintf(tmp_path, sizeof tmp_path, "%s.tmp.%ld.part%d",
                          out_path, pid, rank)
               : snprintf(tmp_path, sizeof tmp_path, "%s.tmp.%ld", out_path,
                          pid);
  if (n < 0 || (size_t)n >= sizeof tmp_path) {
    fprintf(stderr, "rps3-run: %s: path too long\n", out_path);
    return -1;
  }
  return 0;
}
