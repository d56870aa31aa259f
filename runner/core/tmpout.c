/*
 * tmpout.c - see tmpout.h.  The file itself, the fsync before the rename
 * and the signals are signals.c's; this names it after rps3-run's rules.
 */
#include "tmpout.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "signals.h"

/* the name, before and after tmpout_arm: process-wide state of this
   program only (the library has none) */
static char tmp_path[4096];
/* the program that names itself in the messages */
static const char *prog = "rps3-run";

void tmpout_prog(const char *name) { prog = name; }

const char *tmpout_path(void) { return tmp_path; }

void tmpout_arm(void) {
  /* the name fits: tmpout_name checked its length */
  tmp_set(tmp_path);
}

int tmpout_commit(const char *out_path) {
  char err[2 * sizeof tmp_path + 128];
  if (tmp_commit(out_path, err, sizeof err)) {
    fprintf(stderr, "%s: %s\n", prog, err);
    return -1;
  }
  return 0;
}

void tmpout_discard(void) { tmp_discard(); }

/* this machine's short host name, made safe for a file name */
static void host_name(char *buf, size_t size) {
  size_t i;
  if (gethostname(buf, size) != 0) buf[0] = '\0';
  buf[size - 1] = '\0';
  for (i = 0; buf[i]; i++) {
    if (buf[i] == '.') {
      buf[i] = '\0';
      break;
    }
    if (!isalnum((unsigned char)buf[i]) && buf[i] != '-' && buf[i] != '_')
      buf[i] = '_';
  }
  if (!buf[0]) snprintf(buf, size, "unknown");
}

/* the scheduler's job: ARRAYJOB_TASK for a Slurm array task, the Slurm
   job id, or "none" */
static void job_name(char *buf, size_t size) {
  const char *aj = getenv("SLURM_ARRAY_JOB_ID"),
             *at = getenv("SLURM_ARRAY_TASK_ID"), *j = getenv("SLURM_JOB_ID");
  size_t i;
  if (aj && at && *aj && *at)
    snprintf(buf, size, "%s_%s", aj, at);
  else
    snprintf(buf, size, "%s", j && *j ? j : "none");
  for (i = 0; buf[i]; i++)
    if (!isalnum((unsigned char)buf[i]) && buf[i] != '_') buf[i] = '_';
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
  int kept = 0, n;
  if (slash) {
    n = snprintf(dir, sizeof dir, "%.*s", (int)(slash - out_path), out_path);
    if (slash == out_path) strcpy(dir, "/");
  } else
    n = snprintf(dir, sizeof dir, ".");
  if (n < 0 || (size_t)n >= sizeof dir ||
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
    long pid;
    int mine, alive;
    if (strncmp(e->d_name, prefix, np) != 0) continue;
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    if (owner_of(e->d_name + np, host, sizeof host, &pid) != 0) {
      if (force && unlink(path) == 0)
        fprintf(stderr, "%s: removed %s (owner unknown)\n", prog, path);
      else if (!force) {
        kept++;
        if (!quiet)
          fprintf(stderr,
                  "%s: kept %s: owner unknown (--force "
                  "removes it)\n",
                  prog, path);
      }
      continue;
    }
    mine = strcmp(host, me) == 0;
    /* kill(pid, 0) sends nothing: it says whether the process exists
       (EPERM: it does, another user's) */
    alive = mine && (kill((pid_t)pid, 0) == 0 || errno == EPERM);
    if (alive || (!mine && !force)) {
      kept++;
      if (!quiet)
        fprintf(stderr, "%s: kept %s: %s\n", prog, path,
                alive ? "its process is running"
                      : "written on another host, not checked (--force "
                        "removes it)");
      continue;
    }
    if (unlink(path) == 0)
      fprintf(stderr, "%s: removed %s (process %ld on %s %s)\n", prog, path,
              pid, host, mine ? "is gone" : "not checked: --force");
    else if (!quiet)
      fprintf(stderr, "%s: cannot remove %s: %s\n", prog, path,
              strerror(errno));
  }
  closedir(d);
  return kept;
}
