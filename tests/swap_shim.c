/*
 * swap_shim.c - an LD_PRELOAD library for tests/test_shard_inputs.py: a
 * table rewritten while rps3-run reads it.  At the SWAP_AT-th fopen or
 * open (HDF5's excepted: it opens through its own driver after the digest)
 * of a file whose name ends in SWAP_NAME, the file SWAP_WITH is first
 * renamed over it (an atomic replacement, as an acquisition program writes
 * a new table), then the file is opened as asked.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef FILE *(*fopen_fn)(const char *, const char *);
typedef int (*open_fn)(const char *, int, ...);

/* the address of the next definition of sym (the C library's) */
static void *next(const char *sym)
{
  return dlsym(RTLD_NEXT, sym);
}

static void swap_before(const char *path)
{
  static int n;
  const char *name = getenv("SWAP_NAME"), *with = getenv("SWAP_WITH");
  const char *at = getenv("SWAP_AT");
  size_t lp = strlen(path), ln = name ? strlen(name) : 0;
  if (name && with && at && lp >= ln && strcmp(path + lp - ln, name) == 0 &&
      ++n == atoi(at))
    rename(with, path);
}

static FILE *swap_then_open(const char *path, const char *mode,
                            const char *sym)
{
  fopen_fn real;
  void *p = next(sym);
  memcpy(&real, &p, sizeof real);
  swap_before(path);
  return real(path, mode);
}

/* open(2) as the readers of scenes and CSV tables call it (read-only, no
   mode); a call with O_CREAT passes its mode on */
static int swap_then_open2(const char *path, int flags, int mode,
                           const char *sym)
{
  open_fn real;
  void *p = next(sym);
  memcpy(&real, &p, sizeof real);
  if ((flags & O_ACCMODE) == O_RDONLY && (flags & O_NONBLOCK))
    swap_before(path);
  return real(path, flags, mode);
}

FILE *fopen(const char *path, const char *mode)
{
  return swap_then_open(path, mode, "fopen");
}

FILE *fopen64(const char *path, const char *mode)
{
  return swap_then_open(path, mode, "fopen64");
}

int open(const char *path, int flags, ...)
{
  int mode = 0;
  if (flags & O_CREAT) {
    va_list ap;
    va_start(ap, flags);
    mode = va_arg(ap, int);
    va_end(ap);
  }
  return swap_then_open2(path, flags, mode, "open");
}

int open64(const char *path, int flags, ...)
{
  int mode = 0;
  if (flags & O_CREAT) {
    va_list ap;
    va_start(ap, flags);
    mode = va_arg(ap, int);
    va_end(ap);
  }
  return swap_then_open2(path, flags, mode, "open64");
}
