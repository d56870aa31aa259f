/* h5err.c - see h5err.h. */
#include "h5err.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

typedef struct {
  char outer[200];
  char filter[200];
  char inner[400];
  unsigned n;
} walk;

static herr_t walk_cb(unsigned n, const H5E_error2_t *e, void *data) {
  walk *w = data;
  const char *d = e->desc != NULL && e->desc[0] != '\0' ? e->desc : NULL;
  if (d == NULL) d = e->func_name != NULL ? e->func_name : "?";
  /* H5E_WALK_DOWNWARD: from the API call (n == 0) to the innermost */
  if (n == 0) {
    /* the system's part, when the outermost has one, is said below */
    const char *cut = strstr(d, ", errno = ");
    int len = cut ? (int)(cut - d) : (int)strlen(d);
    snprintf(w->outer, sizeof w->outer, "%.*s", len, d);
  }
  /* a missing filter: the innermost is then the plugin search */
  if (w->filter[0] == '\0' && strstr(d, "filter") != NULL)
    snprintf(w->filter, sizeof w->filter, "%s", d);
  snprintf(w->inner, sizeof w->inner, "%s", d);
  w->n = n + 1;
  return 0;
}

/* the errno in an HDF5 description ("..., errno = 28, ..."), or 0 */
static int errno_in(const char *d) {
  const char *p = strstr(d, "errno = ");
  return p ? atoi(p + 8) : 0;
}

/* errno e in the words a user can act on */
static const char *in_words(int e) {
  switch (e) {
  case EAGAIN:
    return "the file is locked by another process (an rps3-run or h5py that "
           "has it open?)";
  case ENOSPC: return "no space left on the device";
  case EDQUOT: return "disk quota exceeded";
  case EROFS: return "read-only file system";
  case ENOENT: return "no such file or directory";
  case EACCES:
  case EPERM: return "permission denied";
  case EFBIG: return "file too large (ulimit -f?)";
  case EIO: return "input/output error of the device";
  default: return strerror(e);
  }
}

/* the last failure (process-wide state of the programs, which call HDF5
   from one thread) */
static walk last;

static herr_t on_error(hid_t stack, void *data) {
  (void)data;
  memset(&last, 0, sizeof last);
  H5Ewalk2(stack, H5E_WALK_DOWNWARD, walk_cb, &last);
  return 0;
}

void h5_errors_capture(void) { H5Eset_auto2(H5E_DEFAULT, on_error, NULL); }

void h5_cause(char *buf, size_t sz) {
  walk w = last;
  int e;
  buf[0] = '\0';
  /* a failure still on the stack (printing off, no call since) is the
     last one; else the capture's */
  if (H5Eget_num(H5E_DEFAULT) > 0) {
    memset(&w, 0, sizeof w);
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk_cb, &w);
  }
  H5Eclear2(H5E_DEFAULT);
  memset(&last, 0, sizeof last);
  if (w.n == 0) return;
  e = errno_in(w.inner);
  if (e)
    snprintf(buf, sz, "%s: %s", w.outer, in_words(e));
  else if (w.filter[0] != '\0' && strcmp(w.filter, w.inner) != 0)
    snprintf(buf, sz, "%s: %s (%s)", w.outer, w.filter, w.inner);
  else if (w.n > 1 && strcmp(w.outer, w.inner) != 0)
    snprintf(buf, sz, "%s: %s", w.outer, w.inner);
  else
    snprintf(buf, sz, "%s", w.outer);
}
