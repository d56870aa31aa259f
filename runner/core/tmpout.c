/* tmpout.c - see tmpout.h. */
#include "tmpout.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "exit_codes.h"
#include "safeio.h"

/* the name; the handlers remove it once armed (tmpout_name is never
   called while it is) */
static char tmp_path[4096];
/* the program that names itself in the messages */
static const char *prog = "rps3-run";

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
        "rps3: output pipe closed (SIGPIPE): stopped, temporary file removed\n";
    ssize_t w = write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)w;
    _exit(EXIT_IO);
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

/* block (SIG_BLOCK) or unblock (SIG_UNBLOCK) the handled signals */
static void sig_block(int how) {
  sigset_t set;
  size_t i;
  sigemptyset(&set);
  for (i = 0; i < NFATAL; i++)
    if (handled[i]) sigaddset(&set, fatal[i]);
  sigprocmask(how, &set, NULL);
}

void tmpout_prog(const char *name) { prog = name; }

const char *tmpout_path(void) { return tmp_path; }

void tmpout_arm(void) { have_tmp = 1; }

/* fsync the file or directory at path: 0, or -1 with err set */
static int sync_path(const char *path, int flags, char *err, size_t errsz) {
  int fd = open(path, flags), rc = 0;
  if (fd < 0) {
    snprintf(err, errsz, "cannot open %s to sync it: %s", path,
             strerror(errno));
    return -1;
  }
  /* EINVAL: a file system without fsync on directories */
  if (fsync(fd) != 0 && errno != EINVAL) {
    snprintf(err, errsz, "cannot sync %s to disk: %s", path, strerror(errno));
    rc = -1;
  }
  close(fd);
  return rc;
}

int tmpout_commit(const char *out_path) {
  char err[2 * sizeof tmp_path + 128], dir[4096];
  int rc = -1;
  if (!have_tmp)
    snprintf(err, sizeof err, "no temporary file to rename");
  else if (sync_path(tmp_path, O_RDONLY, err, sizeof err) == 0) {
    sig_block(SIG_BLOCK);
    if (rename(tmp_path, out_path) != 0)
      snprintf(err, sizeof err, "cannot rename %s to %s: %s", tmp_path,
               out_path, strerror(errno));
    else {
      have_tmp = 0;
      committed = 1;
      rc = 0;
    }
    sig_block(SIG_UNBLOCK);
  }
  if (rc) {
    fprintf(stderr, "%s: %s\n", prog, err);
    return -1;
  }
  /* OUT is complete and its data durable; only its name may not be yet */
  if (path_dir(out_path, dir, sizeof dir))
    fprintf(stderr, "rps3: warning: %s: path too long\n", out_path);
  else if (sync_path(dir, O_RDONLY | O_DIRECTORY, err, sizeof err))
    fprintf(stderr, "rps3: warning: %s\n", err);
  return 0;
}

void tmpout_discard(void) {
  sig_block(SIG_BLOCK);
  if (have_tmp) unlink(tmp_path);
  have_tmp = 0;
  sig_block(SIG_UNBLOCK);
}

/* buf made safe for a file name: what is not a letter, a digit, '_' or a
   character of keep becomes '_' */
static void safe_name(char *buf, const char *keep) {
  for (; *buf; buf++)
    if (!isalnum((unsigned char)*buf) && *buf != '_' && !strchr(keep, *buf))
      *buf = '_';
}

/* this machine's short host name, made safe for a file name */
static void host_name(char *buf, size_t size) {
  if (gethostname(buf, size) != 0) buf[0] = '\0';
  buf[size - 1] = '\0';
  buf[strcspn(buf, ".")] = '\0';
  safe_name(buf, "-");
  if (!buf[0]) snprintf(buf, size, "unknown");
}

/* the scheduler's job: ARRAYJOB_TASK for a Slurm array task, the Slurm
   job id, or "none" */
static void job_name(char *buf, size_t size) {
  const char *aj = getenv("SLURM_ARRAY_JOB_ID"),
             *at = getenv("SLURM_ARRAY_TASK_ID"), *j = getenv("SLURM_JOB_ID");
  if (aj && at && *aj && *at)
    snprintf(buf, size, "%s_%s", aj, at);
  else
    snprintf(buf, size, "%s", j && *j ? j : "none");
  safe_name(buf, "");
}

int tmpout_name(const char *out_path, int rank) {
  char host[256], job[128];
  int n;
  host_name(host, sizeof host);
  job_name(job, sizeof job);
  n = snprintf(tmp_path, sizeof tmp_path, "%s.tmp.%s.%ld.job%s.rank%d",
               out_path, host, (long)getpid(), job, rank);
  if (n < 0 || (size_t)n >= sizeof tmp_path) {
    fprintf(stderr, "%s: %s: path too long\n", prog, out_path);
    return -1;
  }
  return 0;
}

/* the owner of a temporary file name (after "OUT.tmp."): host and pid;
   0, or -1 when the name is not of that form */
static int owner_of(const char *tail, char *host, size_t hsize, long *pid) {
  const char *dot = strchr(tail, '.');
  char *end;
  if (!dot || (size_t)(dot - tail) >= hsize || dot == tail) return -1;
  memcpy(host, tail, (size_t)(dot - tail));
  host[dot - tail] = '\0';
  *pid = strtol(dot + 1, &end, 10);
  if (end == dot + 1 || *pid <= 0 || strncmp(end, ".job", 4) != 0 ||
      !strstr(end, ".rank"))
    return -1;
  return 0;
}

int tmpout_clean(const char *out_path, int force, int quiet) {
  const char *slash = strrchr(out_path, '/');
  char dir[4096], prefix[4096], me[256], host[256], path[8192];
  size_t np;
  DIR *d;
  struct dirent *e;
  int kept = 0;
  if (path_dir(out_path, dir, sizeof dir) ||
      (size_t)snprintf(prefix, sizeof prefix, "%s.tmp.",
                       slash ? slash + 1 : out_path) >= sizeof prefix)
    return -1;
  np = strlen(prefix);
  host_name(me, sizeof me);
  if (!(d = opendir(dir))) {
    if (!quiet) fprintf(stderr, "%s: %s: %s\n", prog, dir, strerror(errno));
    return -1;
  }
  while ((e = readdir(d)) != NULL) {
    long pid = 0;
    int known, mine, alive;
    if (strncmp(e->d_name, prefix, np) != 0) continue;
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    known = owner_of(e->d_name + np, host, sizeof host, &pid) == 0;
    mine = known && strcmp(host, me) == 0;
    /* kill(pid, 0) sends nothing: it says whether the process exists
       (EPERM: it does, another user's) */
    alive = mine && (kill((pid_t)pid, 0) == 0 || errno == EPERM);
    if (alive || (!mine && !force)) {
      kept++;
      if (!quiet)
        fprintf(stderr, "%s: kept %s: %s\n", prog, path,
                alive   ? "its process is running"
                : known ? "written on another host, not checked (--force "
                          "removes it)"
                        : "owner unknown (--force removes it)");
    } else if (unlink(path) != 0) {
      if (known && !quiet)
        fprintf(stderr, "%s: cannot remove %s: %s\n", prog, path,
                strerror(errno));
    } else if (!known)
      fprintf(stderr, "%s: removed %s (owner unknown)\n", prog, path);
    else
      fprintf(stderr, "%s: removed %s (process %ld on %s %s)\n", prog, path,
              pid, host, mine ? "is gone" : "not checked: --force");
  }
  closedir(d);
  return kept;
}
