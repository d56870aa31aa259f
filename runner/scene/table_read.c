/*
 * table_read.c - table_read (table.h): the file named relative to the
 * scene, read by table.c (CSV) or table_h5.c (HDF5), then checked and
 * completed as a whole; every failure named with the file.
 */
#define _XOPEN_SOURCE 700 /* realpath */

#include "table.h"
#include "table_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the path of name relative to the directory of scene_file */
static char *path_join(const char *scene_file, const char *name) {
  const char *slash = strrchr(scene_file, '/');
  size_t dir =
      (name[0] == '/' || !slash) ? 0 : (size_t)(slash - scene_file) + 1;
  char *p = malloc(dir + strlen(name) + 1);
  if (p) {
    memcpy(p, scene_file, dir);
    strcpy(p + dir, name);
  }
  return p;
}

static int ends_with(const char *s, const char *tail) {
  size_t a = strlen(s), b = strlen(tail);
  return a >= b && strcmp(s + a - b, tail) == 0;
}

/* err made printable text: a control character or a byte that is not
   part of valid UTF-8 (a file's bytes quoted in a message) becomes \xNN */
static void table_printable(char *err, size_t errsz) {
  char in[1024];
  size_t i = 0, o = 0;
  if (errsz == 0) return;
  snprintf(in, sizeof in, "%s", err);
  while (in[i] != '\0' && o + 1 < errsz) {
    unsigned char b = (unsigned char)in[i];
    size_t n = b < 0x80             ? 1
               : (b & 0xE0) == 0xC0 ? 2
               : (b & 0xF0) == 0xE0 ? 3
               : (b & 0xF8) == 0xF0 ? 4
                                    : 0,
           j;
    int ok = n != 0 && b != 0x7F && (b >= 0x20 || n != 1) && b != 0xC0 &&
             b != 0xC1 && b < 0xF5;
    for (j = 1; ok && j < n; j++)
      ok = ((unsigned char)in[i + j] & 0xC0) == 0x80;
    /* C1 controls (U+0080..U+009F) are not printable either */
    if (ok && n == 2 && b == 0xC2 && (unsigned char)in[i + 1] < 0xA0) ok = 0;
    if (ok && o + n < errsz) {
      memcpy(err + o, in + i, n);
      o += n;
      i += n;
    } else if (!ok && o + 4 < errsz) {
      snprintf(err + o, 5, "\\x%02X", b);
      o += 4;
      i++;
    } else {
      break;
    }
  }
  err[o] = '\0';
}

int table_read(table_data *t, const char *scene_file, const char *name,
               int what, char *err, size_t errsz) {
  char *abs;
  memset(t, 0, sizeof *t);
  if (errsz > 0) err[0] = '\0';
  if (name[0] == '\0') {
    table_err(err, errsz, "an empty file name");
    return -1;
  }
  t->path = path_join(scene_file, name);
  if (!t->path) {
    table_err(err, errsz, "out of memory");
    return -1;
  }
  t->hdf5 = ends_with(name, ".h5") || ends_with(name, ".hdf5");
  if ((t->hdf5 ? table_h5_read(t, what, err, errsz)
               : table_csv_read(t, what, err, errsz)) != 0 ||
      table_finish(t, what, err, errsz) != 0) {
    /* every failure sets its message; should one not, the file is named */
    if (errsz > 0 && err[0] == '\0')
      table_err(err, errsz, "%s: cannot read the table", t->path);
    table_printable(err, errsz);
    table_free(t);
    return -1;
  }
  abs = realpath(t->path, NULL);
  t->abs = abs ? abs : t->path;
  return 0;
}
