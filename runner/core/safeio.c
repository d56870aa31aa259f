/* safeio.c - see safeio.h. */
#include "safeio.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <hdf5.h>

#include "exit_codes.h"

void proc_init(void) {
  int fd;
  for (fd = 0; fd <= 2; fd++)
    if (fcntl(fd, F_GETFD) < 0 && errno == EBADF) {
      /* open() returns the lowest free fd: this one */
      int n = open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
      if (n >= 0 && n != fd) {
        dup2(n, fd);
        close(n);
      }
    }
  /* before any other HDF5 call */
  H5dont_atexit();
}

int proc_exit(int code) {
  if (code != EXIT_IO) H5close();
  return code;
}

int path_dir(const char *path, char *dir, size_t sz) {
  const char *slash = strrchr(path, '/');
  size_t n;
  if (!slash) {
    snprintf(dir, sz, ".");
    return 0;
  }
  n = slash == path ? 1 : (size_t)(slash - path);
  if (n >= sz) return -1;
  memcpy(dir, path, n);
  dir[n] = '\0';
  return 0;
}

const char *file_kind(mode_t m) {
  return S_ISDIR(m)    ? "a directory"
         : S_ISLNK(m)  ? "a symbolic link"
         : S_ISCHR(m)  ? "a character device"
         : S_ISBLK(m)  ? "a block device"
         : S_ISFIFO(m) ? "a FIFO"
         : S_ISSOCK(m) ? "a socket"
                       : "not a regular file";
}

int out_path_check(const char *out, const char *const *in, size_t ninput,
                   char *err, size_t errsz) {
  struct stat so, si;
  char dir[4096];
  size_t i = 0, n = strlen(out);
  int there = n > 0 && lstat(out, &so) == 0, e = errno;
  /* the input that is the output itself, under any name */
  while (there && i < ninput &&
         !(stat(in[i], &si) == 0 && si.st_dev == so.st_dev &&
           si.st_ino == so.st_ino))
    i++;
  if (n == 0)
    snprintf(err, errsz, "-o needs a file name, got ''");
  else if (out[n - 1] == '/')
    snprintf(err, errsz, "-o %s names a directory: give a file name", out);
  else if (there && !S_ISREG(so.st_mode))
    snprintf(err, errsz,
             "-o %s is %s: the output must be a new or a regular file (it is "
             "replaced when the run is complete)",
             out, file_kind(so.st_mode));
  else if (there && i < ninput)
    snprintf(err, errsz, "-o %s is the input %s itself", out, in[i]);
  else if (!there && e != ENOENT)
    snprintf(err, errsz, "-o %s: %s", out, strerror(e));
  else if (path_dir(out, dir, sizeof dir))
    snprintf(err, errsz, "-o %s: path too long", out);
  else if (stat(dir, &si) != 0)
    snprintf(err, errsz, "-o %s: directory %s: %s", out, dir, strerror(errno));
  else if (!S_ISDIR(si.st_mode))
    snprintf(err, errsz, "-o %s: %s is not a directory", out, dir);
  /* EROFS for a read-only file system, EACCES without permission */
  else if (access(dir, W_OK | X_OK) != 0)
    snprintf(err, errsz, "-o %s: cannot create files in %s: %s", out, dir,
             strerror(errno));
  else
    return 0;
  return -1;
}

/* up to cap bytes of fd into buf: their number, or -1 (errno set) */
static ssize_t read_upto(int fd, char *buf, size_t cap) {
  size_t got = 0;
  while (got < cap) {
    ssize_t n = read(fd, buf + got, cap - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -1;
    if (n == 0) break;
    got += (size_t)n;
  }
  return (ssize_t)got;
}

int file_read_all(const char *path, size_t max, const char *kind_rule,
                  const char *size_rule, char **text, size_t *len, char *why,
                  size_t whysz) {
  struct stat st;
  size_t cap = 0;
  ssize_t got;
  char *buf = NULL;
  /* O_NONBLOCK: opening a FIFO must not wait for a writer */
  int fd = open(path, O_RDONLY | O_NONBLOCK);
  *text = NULL;
  *len = 0;
  if (fd < 0)
    snprintf(why, whysz, "cannot open: %s", strerror(errno));
  else if (fstat(fd, &st) != 0)
    snprintf(why, whysz, "cannot read: %s", strerror(errno));
  else if (!S_ISREG(st.st_mode))
    snprintf(why, whysz, "is %s: %s", file_kind(st.st_mode), kind_rule);
  else if ((unsigned long long)st.st_size > (unsigned long long)max)
    snprintf(why, whysz, "is %lld bytes: %s", (long long)st.st_size, size_rule);
  /* one byte more than fstat said: a file that grew since is refused */
  else if (!(buf = malloc((cap = (size_t)st.st_size + 1) + 1)))
    snprintf(why, whysz, "out of memory");
  else if ((got = read_upto(fd, buf, cap)) < 0)
    snprintf(why, whysz, "cannot read: %s", strerror(errno));
  else if ((size_t)got == cap)
    snprintf(why, whysz, "changed while it was read");
  else {
    buf[got] = '\0';
    *text = buf;
    *len = (size_t)got;
  }
  if (fd >= 0) close(fd);
  if (!*text) free(buf);
  return *text ? 0 : -1;
}

/* the pid of NAME = BASE.tmp.PID or BASE.tmp.PID.partR; 0 if not one */
static long tmp_pid(const char *name, const char *base) {
  size_t n = strlen(base);
  const char *p;
  char *end;
  long pid;
  if (strncmp(name, base, n) != 0 || strncmp(name + n, ".tmp.", 5) != 0)
    return 0;
  p = name + n + 5;
  if (*p < '0' || *p > '9') return 0;
  pid = strtol(p, &end, 10);
  if (*end == '\0') return pid;
  if (strncmp(end, ".part", 5) != 0 || end[5] < '0' || end[5] > '9') return 0;
  strtol(end + 5, &end, 10);
  return *end == '\0' ? pid : 0;
}

size_t stale_report(const char *prog, const char *out) {
  char dir[4096];
  const char *slash = strrchr(out, '/'), *base = slash ? slash + 1 : out;
  struct dirent *e;
  size_t count = 0;
  DIR *d;
  if (path_dir(out, dir, sizeof dir) || !(d = opendir(dir))) return 0;
  while ((e = readdir(d)) != NULL) {
    long pid = tmp_pid(e->d_name, base);
    if (pid <= 0 || pid == (long)getpid()) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;
    fprintf(stderr,
            "%s: warning: %s%s%s is the temporary file of process %ld, which "
            "no longer runs on this machine (killed?): it is not a complete "
            "output; remove it\n",
            prog, slash ? dir : "", slash ? "/" : "", e->d_name, pid);
    count++;
  }
  closedir(d);
  return count;
}

double disk_free(const char *out) {
  char dir[4096];
  struct statvfs v;
  if (path_dir(out, dir, sizeof dir) || statvfs(dir, &v) != 0) return -1;
  return (double)v.f_bavail * (double)v.f_frsize;
}

int parse_ulong(const char *a, unsigned long lo, unsigned long hi,
                unsigned long *v) {
  char *end;
  unsigned long x;
  if (a[0] < '0' || a[0] > '9') return -1;
  errno = 0;
  x = strtoul(a, &end, 10);
  if (*end != '\0' || errno || x < lo || x > hi) return -1;
  *v = x;
  return 0;
}
