/*
 * tmpout.c - see tmpout.h.
 */
#include "tmpout.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* the temporary file, for the signal handler: process-wide state of this
   program only (the library has none) */
static char tmp_path[4096];
static volatile sig_atomic_t have_tmp;

/* remove the temporary file, then die of the same signal */
static void on_signal(int sig)
{
  if (have_tmp)
    unlink(tmp_path);
  signal(sig, SIG_DFL);
  raise(sig);
}

static const int signals[] = {SIGINT, SIGTERM, SIGHUP};
#define NSIGNAL (sizeof signals / sizeof signals[0])

static void signals_install(void)
{
  struct sigaction sa;
  size_t i;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (i = 0; i < NSIGNAL; i++)
    sigaction(signals[i], &sa, NULL);
}

static void signals_block(int how)
{
  sigset_t set;
  size_t i;
  sigemptyset(&set);
  for (i = 0; i < NSIGNAL; i++)
    sigaddset(&set, signals[i]);
  sigprocmask(how, &set, NULL);
}

const char *tmpout_path(void)
{
  return tmp_path;
}

void tmpout_arm(void)
{
  signals_install();
  have_tmp = 1;
}

/* rename the temporary file to out_path; the rename and forgetting the
   temporary name happen together.  0 or -1 (message printed) */
int tmpout_commit(const char *out_path)
{
  signals_block(SIG_BLOCK);
  if (rename(tmp_path, out_path) != 0) {
    fprintf(stderr, "rps3-run: cannot rename %s to %s: %s\n", tmp_path,
            out_path, strerror(errno));
    signals_block(SIG_UNBLOCK);
    return -1;
  }
  have_tmp = 0;
  signals_block(SIG_UNBLOCK);
  return 0;
}

/* remove the temporary file, if any */
void tmpout_discard(void)
{
  signals_block(SIG_BLOCK);
  if (have_tmp)
    unlink(tmp_path);
  have_tmp = 0;
  signals_block(SIG_UNBLOCK);
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
