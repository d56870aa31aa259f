/*
 * table_read.c - table_read (table.h): the file named relative to the
 * scene, read by table.c (CSV) or table_h5.c (HDF5), then checked and
 * completed as a whole: times that increase, steps the interpolant can
 * take, the rates a file lacks from the spline.  Every failure names the
 * file, and the row or line where it can.  Reachability is the library's
 * (rps3_traj_check), mapped back to the row by table_where.
 */
#define _XOPEN_SOURCE 700 /* realpath */

#include "scene_int.h"
#include "table.h"
#include "table_int.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the label of column c in a message: "column NAME" (CSV) or "dataset
   /NAME" (HDF5) */
static void col_label(const table_data *t, int what, int c, char *buf,
                      size_t sz) {
  snprintf(buf, sz, "%s%s", t->hdf5 ? "dataset /" : "column ",
           table_col_names[what][c]);
}

/* x as the file most likely wrote it (scene_format_real) */
static const char *num(char buf[32], double x) {
  scene_format_real(buf, 32, x);
  return buf;
}

/* the rows' times and their steps, each named at its row: strictly
   increasing; their span a finite double (rps3_table_duration and the
   time within the table are differences of times); every step at least
   TIME_RESOLUTION of the largest |t| (the interpolant finds the time
   within a step as (t0 + t - t_i) / h, rounded to a unit in the last
   place of the times); and no step so short for the change of a value
   that the interpolant's rate (~ change / h) or acceleration (~ change /
   h^2) overflows */
#define TIME_RESOLUTION                             \
  0x1p-36 /* 2^16 units in the last place: the time \
             within a step rounds by <= 1.5e-5 of it */
#define DERIV_MAX                                             \
  (DBL_MAX / 64.0) /* the Hermite polynomials' factors (up to \
                      20) on top of change / h^2 */

/* the step from row r - 1 to row r of t's times: increasing, within the
   range of a double and not too small; 0 or -1 with err set */
static int table_step_time(const table_data *t, int what, size_t r,
                           const char *where, char *err, size_t errsz) {
  char lt[40], n1[32], n2[32];
  double scale = fmax(fabs(t->time[0]), fabs(t->time[t->n - 1]));
  double h = t->time[r] - t->time[r - 1];
  col_label(t, what, 0, lt, sizeof lt);
  num(n1, t->time[r]);
  num(n2, t->time[r - 1]);
  if (!(t->time[r] > t->time[r - 1]))
    return table_err(err, errsz,
                     "%s: %s: %s after %s: times must increase strictly", where,
                     lt, n1, n2);
  if (!isfinite(t->time[r] - t->time[0]))
    return table_err(
        err, errsz,
        "%s: %s: %s is more than 1.8e308 s after the first row's %s: the time "
        "range overflows a double (the times must span less than 1.8e308 s)",
        where, lt, n1, num(n2, t->time[0]));
  if (h < scale * TIME_RESOLUTION)
    return table_err(
        err, errsz,
        "%s: %s: %s after %s: the rows are %.3g s apart, too close relative to "
        "the time scale %.3g s (the largest |t|): a step must be at least "
        "1.5e-11 of it, or the time within the step rounds by more than 1.5e-5 "
        "of the step; subtract an offset from the times or thin the rows",
        where, lt, n1, n2, h, scale);
  if (h * h < DBL_MIN)
    return table_err(
        err, errsz,
        "%s: %s: %s after %s: the rows are %.3g s apart, a spacing too small "
        "for a double: the interpolant's acceleration divides by the step "
        "squared, which underflows below 1.5e-154 s",
        where, lt, n1, n2, h);
  return 0;
}

/* value k over the step from row r - 1 to row r: its change, and the
   interpolant's acceleration, within the range of a double; 0 or -1 with
   err set */
static int table_step_value(const table_data *t, int what, size_t r, int k,
                            const char *where, char *err, size_t errsz) {
  char lc[40], lr[40], n1[32], n2[32];
  double h = t->time[r] - t->time[r - 1];
  double dv = t->value[r][k] - t->value[r - 1][k], mv, mr, ma;
  col_label(t, what, 1 + k, lc, sizeof lc);
  if (!isfinite(dv))
    return table_err(
        err, errsz,
        "%s: %s: %s after %s: the change between the rows overflows a double",
        where, lc, num(n1, t->value[r][k]), num(n2, t->value[r - 1][k]));
  /* the interpolant's acceleration: change / h^2, and with the file's
     rates rate / h, with its accelerations their own */
  mv = fabs(dv) / h / h;
  mr = t->rates_given ? (fabs(t->rate[r][k]) + fabs(t->rate[r - 1][k])) / h
                      : 0.0;
  ma = t->acc != NULL ? fabs(t->acc[r][k]) + fabs(t->acc[r - 1][k]) : 0.0;
  if (mv + mr + ma < DERIV_MAX) return 0;
  if (mv >= mr && mv >= ma)
    return table_err(err, errsz,
                     "%s: %s: changes by %.3g in %.3g s from the previous row: "
                     "the spacing of the rows is too small for so large a "
                     "change, the interpolant's rate and acceleration across "
                     "the step (of order change / step^2) overflow a double",
                     where, lc, dv, h);
  col_label(t, what, mr >= ma ? 4 + k : 7 + k, lr, sizeof lr);
  return table_err(
      err, errsz,
      "%s: %s: %.3g and %.3g across a step of %.3g s: the interpolant's "
      "acceleration there (of order %s) overflows a double",
      where, lr, mr >= ma ? t->rate[r - 1][k] : t->acc[r - 1][k],
      mr >= ma ? t->rate[r][k] : t->acc[r][k], h,
      mr >= ma ? "rate / step" : "the accelerations themselves");
}

static int table_steps(table_data *t, int what, char *err, size_t errsz) {
  size_t r;
  int k;
  char where[300];
  for (r = 1; r < t->n; r++) {
    table_where(t, r, where, sizeof where);
    if (table_step_time(t, what, r, where, err, errsz)) return -1;
    for (k = 0; k < 3; k++)
      if (table_step_value(t, what, r, k, where, err, errsz)) return -1;
  }
  return 0;
}

/* the rows checked (table_steps); then the rates a table lacks, from the
   spline */
static int table_finish(table_data *t, int what, char *err, size_t errsz) {
  size_t r;
  char where[300];
  double *work;
  int min = t->rates_given ? 2 : 4, k, x;
  if (t->n < (size_t)min)
    return table_err(err, errsz, "%s: %zu rows; a table needs at least %d%s",
                     t->path, t->n, min,
                     t->rates_given ? ""
                                    : " without rate columns (the not-a-knot "
                                      "spline that gives the rates)");
  if (table_steps(t, what, err, errsz)) return -1;
  if (t->rates_given) return 0;
  work = malloc(t->n * sizeof *work);
  if (!work)
    return table_err(err, errsz, "%s: out of memory for the spline of %zu rows",
                     t->path, t->n);
  x = rps3_table_spline(t->n, t->time, (const double(*)[3])t->value, t->rate,
                        work);
  free(work);
  if (x == RPS3_OK) return 0;
  /* the rows passed table_steps: name the first rate that overflowed */
  for (r = 0; r < t->n; r++)
    for (k = 0; k < 3; k++)
      if (!isfinite(t->rate[r][k])) {
        char lc[40];
        table_where(t, r, where, sizeof where);
        col_label(t, what, 1 + k, lc, sizeof lc);
        return table_err(
            err, errsz,
            "%s: %s: the spline's rate at this row overflows a double (the "
            "values change too fast for the spacing of the rows)",
            where, lc);
      }
  return table_err(err, errsz, "%s: the spline of the rows failed (%s)",
                   t->path, rps3_strerror(x));
}

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
  if (name[0] == '\0') return table_err(err, errsz, "an empty file name");
  t->path = path_join(scene_file, name);
  if (!t->path) return table_err(err, errsz, "out of memory");
  t->hdf5 = ends_with(name, ".h5") || ends_with(name, ".hdf5");
  t->what = what;
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
