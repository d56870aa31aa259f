/*
 * swap_shim.c - an LD_PRELOAD library for tests/test_shard_inputs.py: a
 * table rewritten while rps3-run reads it.  At the SWAP_AT-th fopen of a
 * file whose name ends in SWAP_NAME, the file SWAP_WITH is first renamed
 * over it (an atomic replacement, as an acquisition program writes a new
 * table), then the file is opened as asked.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef FILE *(*fopen_fn)(const char *, const char *);

static FILE *swap_then_open(const char *path, const char *mode,
                            const char *sym)
{
  static int n;
  const char *name = getenv("SWAP_NAME"), *with = getenv("SWAP_WITH");
  const char *at = getenv("SWAP_AT");
  size_t lp = strlen(path), ln = name ? strlen(name) : 0;
  fopen_fn real;
  void *p = dlsym(RTLD_NEXT, sym);
  memcpy(&real, &p, sizeof real);
  if (name && with && at && lp >= ln && strcmp(path + lp - ln, name) == 0 &&
      ++n == atoi(at))
    rename(with, path);
  return real(path, mode);
}

FILE *fopen(const char *path, const char *mode)
{
  return swap_then_open(path, mode, "fopen");
}

FILE *fopen64(const char *path, const char *mode)
{
  return swap_then_open(path, mode, "fopen64");
}
