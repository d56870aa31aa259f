/*
 * signals.c - see signals.h.
 */
#include "signals.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "safeio.h"

/* the temporary file, for the handlers */
static char tmp_path[4096];
static volatile sig_atomic_t have_tmp;
/* 1 once an output is complete under its name */
static volatile sig_atomic_t committed;

/* the signals whose handler removes the temporary file and re-raises */
static const int fatal[] = {SIGINT,  SIGTERM, SIGHUP,  SIGQUIT,
                            SIGALRM, SIGUSR1, SIGUSR2, SIGVTALRM,
                            SIGPROF, SIGXCPU, SIGPIPE};
#define NFATAL (sizeof fatal / sizeof fatal[0])

/* 1 for the signals of fatal[] that this process handles (not ignored at
   start) */
static int handled[NFATAL];

static void on_signal(int sig) {
  if (have_tmp) unlink(tmp_path);
  /* the output is complete: the run's exit code stands, and a progress
     line that cannot be written is dropped (the write fails with EPIPE) */
  if (sig == SIGPIPE && committed) return;
  /* without an output under way (--keys | head), a closed pipe ends the
     program as it ends any filter */
  if (sig == SIGPIPE && have_tmp) {
    /* the reader of stdout or stderr is gone: a write error, exit 3 */
    static const char msg[] =
        "rps3: output pipe closed (SIGPIPE): stopped, temporary file "
        "removed\n";
    ssize_t w = write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)w;
    _exit(SIG_EXIT_IO);
  }
  signal(sig, SIG_DFL);
  raise(sig);
}

void sig_init(void) {
  struct sigaction sa, old;
  size_t i;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (i = 0; i < NFATAL; i++) sigaddset(&sa.sa_mask, fatal[i]);
  for (i = 0; i < NFATAL; i++) {
    /* a signal ignored at start (nohup, `cmd &` in a non-interactive
       shell) stays ignored: whoever started us asked for that */
    if (sigaction(fatal[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
      continue;
    if (sigaction(fatal[i], &sa, NULL) == 0) handled[i] = 1;
  }
  /* a file over `ulimit -f` makes the write fail with EFBIG instead of
     killing the process: the error path removes the temporary file */
  signal(SIGXFSZ, SIG_IGN);
}

void sig_block(int how) {
  sigset_t set;
  size_t i;
  sigemptyset(&set);
  for (i = 0; i < NFATAL; i++)
    if (handled[i]) sigaddset(&set, fatal[i]);
  sigprocmask(how, &set, NULL);
}

int tmp_set(const char *path) {
  size_t n = strlen(path);
  if (n >= sizeof tmp_path) return -1;
  sig_block(SIG_BLOCK);
  memcpy(tmp_path, path, n + 1);
  have_tmp = 1;
  sig_block(SIG_UNBLOCK);
  return 0;
}

int tmp_commit(const char *out, char *err, size_t errsz) {
  int rc = -1;
  if (!have_tmp) {
    snprintf(err, errsz, "no temporary file to rename");
    return -1;
  }
  if (file_sync(tmp_path, err, errsz)) return -1;
  /* the rename and forgetting the temporary name happen together */
  sig_block(SIG_BLOCK);
  if (rename(tmp_path, out) != 0)
    snprintf(err, errsz, "cannot rename %s to %s: %s", tmp_path, out,
             strerror(errno));
  else {
    have_tmp = 0;
    committed = 1;
    rc = 0;
  }
  sig_block(SIG_UNBLOCK);
  /* OUT is complete and its data durable; only its name may not be yet */
  if (rc == 0 && dir_sync(out, err, errsz))
    fprintf(stderr, "rps3: warning: %s\n", err);
  return rc;
}

void tmp_discard(void) {
  sig_block(SIG_BLOCK);
  if (have_tmp) unlink(tmp_path);
  have_tmp = 0;
  sig_block(SIG_UNBLOCK);
}
