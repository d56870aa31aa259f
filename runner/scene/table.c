/*
 * table.c - read a table of samples (table.h): the file named relative to
 * the scene, its rows read from CSV here or from HDF5 (table_h5.c), then
 * checked and completed as a whole.  Every row is checked where it is
 * read, so that an error names the file, the line (or row) and the column:
 * a number that is not one, NaN or infinity, a time that does not
 * increase.  Reachability is the library's (rps3_traj_check), mapped back
 * to the row by table_where.
 */
#define _XOPEN_SOURCE 700 /* realpath */

#include "table.h"
#include "core/hint.h"
#include "core/safeio.h"
#include "table_int.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

const char *const table_col_names[2][TABLE_NCOL] = {
    {"t", "alpha", "beta", "z_c", "alpha_dot", "beta_dot", "z_c_dot",
     "alpha_ddot", "beta_ddot", "z_c_ddot"},
    {"t", "x", "y", "z", "x_dot", "y_dot", "z_dot", "x_ddot", "y_ddot",
     "z_ddot"}};

void table_err(char *err, size_t errsz, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errsz, fmt, ap);
  va_end(ap);
}

void table_free(table_data *t) {
  if (!t) return;
  if (t->abs != t->path) free(t->abs);
  free(t->path);
  free(t->time);
  free(t->value);
  free(t->rate);
  free(t->acc);
  free(t->line);
  memset(t, 0, sizeof *t);
}

void table_where(const table_data *t, size_t r, char *buf, size_t sz) {
  if (t->line != NULL && r < t->n)
    snprintf(buf, sz, "%s:%d", t->path, t->line[r]);
  else
    snprintf(buf, sz, "%s, row %zu", t->path, r);
}

rps3_table table_view(const table_data *t) {
  rps3_table v;
  memset(&v, 0, sizeof v);
  v.n = t->n;
  v.time = t->time;
  v.value = (const double(*)[3])t->value;
  v.rate = (const double(*)[3])t->rate;
  v.acc = (const double(*)[3])t->acc;
  return v;
}

int table_alloc_rows(table_data *t, size_t n, int with_acc, int with_line,
                     char *err, size_t errsz) {
  size_t m = n ? n : 1; /* a table of no rows is refused later */
  /* a row in memory: the time, values and rates (the file's or the
     spline's), the accelerations, the spline's work, the CSV line */
  double row = sizeof(double) * (8.0 + (with_acc ? 3.0 : 0.0)) +
               (with_line ? (double)sizeof(int) : 0.0);
  if ((double)n * row > TABLE_MAX_BYTES) {
    table_err(err, errsz,
              "%s: %zu rows need %.3g GB in memory (%.0f bytes a row): above "
              "the table limit of 1 GiB",
              t->path, n, (double)n * row / 1e9, row);
    return -1;
  }
  t->n = n;
  t->time = malloc(m * sizeof *t->time);
  t->value = malloc(m * sizeof *t->value);
  t->rate = malloc(m * sizeof *t->rate);
  t->acc = with_acc ? malloc(m * sizeof *t->acc) : NULL;
  t->line = with_line ? malloc(m * sizeof *t->line) : NULL;
  if (t->time && t->value && t->rate && (t->acc || !with_acc) &&
      (t->line || !with_line))
    return 0;
  table_err(err, errsz, "%s: out of memory for %zu rows", t->path, n);
  return -1;
}

double *table_cell(table_data *t, size_t r, int c) {
  if (c == 0) return &t->time[r];
  if (c < 4) return &t->value[r][c - 1];
  if (c < 7) return &t->rate[r][c - 4];
  return &t->acc[r][c - 7];
}

const char *table_bad_number(double x) {
  if (!isfinite(x)) return "is not a finite number";
  if (fpclassify(x) == FP_SUBNORMAL)
    return "is subnormal (nonzero but below 2.2e-308 in magnitude, where a "
           "double loses precision): write 0 or a normal number";
  return NULL;
}

int table_columns_check(const int have[TABLE_NCOL], int what, int hdf5,
                        const char *file, char *err, size_t errsz) {
  int c, g;
  const char *kind = hdf5 ? "dataset /" : "column ";
  const char *const *n = table_col_names[what];
  for (c = 0; c < 4; c++)
    if (!have[c]) {
      table_err(err, errsz, "%s: missing %s%s (a table has %s, %s, %s, %s)",
                file, kind, n[c], n[0], n[1], n[2], n[3]);
      return -1;
    }
  for (g = 4; g < TABLE_NCOL; g += 3)
    if (have[g] + have[g + 1] + have[g + 2] != 0 &&
        have[g] + have[g + 1] + have[g + 2] != 3) {
      for (c = g; have[c]; c++)
        ;
      table_err(err, errsz, "%s: missing %s%s (give the three %s or none)",
                file, kind, n[c], g == 4 ? "rates" : "accelerations");
      return -1;
    }
  if (have[7] && !have[4]) {
    table_err(
        err, errsz,
        "%s: accelerations (%s%s, ...) need the rates (%s%s, ...) as well",
        file, kind, n[7], kind, n[4]);
    return -1;
  }
  return 0;
}

/* the number in the field [s, e) of line `line`, which starts at start:
   parsed where it stands (e is NUL-terminated for strtod, then restored),
   so a number of any length that strtod reads is read */
static int parse_field(char *s, char *e, double *x, const char *file, int line,
                       const char *start, const char *name, char *err,
                       size_t errsz) {
  char *end, keep, q[48], why[300] = "";
  int col;
  while (s < e && (*s == ' ' || *s == '\t')) s++;
  while (e > s && (e[-1] == ' ' || e[-1] == '\t')) e--;
  col = (int)(s - start) + 1; /* of the number itself, blanks skipped */
  if (e == s) {
    table_err(err, errsz, "%s:%d:%d: column %s: empty field", file, line, col,
              name);
    return -1;
  }
  /* the field as quoted in a message: its first 40 bytes */
  snprintf(q, sizeof q, "'%.*s'%s", e - s > 40 ? 40 : (int)(e - s), s,
           e - s > 40 ? "..." : "");
  keep = *e;
  *e = '\0';
  errno = 0;
  *x = strtod(s, &end);
  if (end != e)
    snprintf(why, sizeof why, "expected a number, got %s", q);
  else if (table_bad_number(*x))
    snprintf(why, sizeof why, "%s %s%s", q, table_bad_number(*x),
             !isfinite(*x) && errno == ERANGE
                 ? " (beyond the largest double, 1.8e308)"
                 : "");
  else if (*x == 0.0 && errno == ERANGE)
    snprintf(why, sizeof why,
             "%s underflows to 0 (nonzero but below 4.9e-324 in magnitude, the "
             "smallest double): write 0 or a normal number",
             q);
  *e = keep;
  if (why[0] == '\0') return 0;
  table_err(err, errsz, "%s:%d:%d: column %s: %s", file, line, col, name, why);
  return -1;
}

/* the header line [s, e): column c of the file is col[c] (0..TABLE_NCOL-1) */
static int csv_header(const char *s, const char *e, int what, int *col,
                      int *ncol, int have[TABLE_NCOL], const char *file,
                      int line, char *err, size_t errsz) {
  const char *p = s;
  *ncol = 0;
  for (;;) {
    const char *q = p, *a, *b;
    int c;
    while (q < e && *q != ',') q++;
    for (a = p; a < q && (*a == ' ' || *a == '\t'); a++)
      ;
    for (b = q; b > a && (b[-1] == ' ' || b[-1] == '\t'); b--)
      ;
    for (c = 0; c < TABLE_NCOL; c++)
      if ((size_t)(b - a) == strlen(table_col_names[what][c]) &&
          strncmp(a, table_col_names[what][c], (size_t)(b - a)) == 0)
        break;
    if (c == TABLE_NCOL || have[c] || *ncol == TABLE_NCOL) {
      char list[200], name[HINT_MAX_LEN + 1], hint[120] = "";
      int k;
      size_t len = 0;
      for (k = 0; k < TABLE_NCOL; k++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s",
                                k ? ", " : "", table_col_names[what][k]);
      snprintf(name, sizeof name, "%.*s", (int)(b - a), a);
      if (c == TABLE_NCOL)
        hint_text(hint, sizeof hint, name, table_col_names[what], TABLE_NCOL);
      table_err(err, errsz, "%s:%d:%d: column '%s': %s%s; expected %s", file,
                line, (int)(a - s) + 1, name,
                c < TABLE_NCOL ? "given twice" : "unknown column", hint, list);
      return -1;
    }
    have[c] = 1;
    col[(*ncol)++] = c;
    if (q == e) break;
    p = q + 1;
  }
  return table_columns_check(have, what, 0, file, err, errsz);
}

/* a table is a regular file of at most TABLE_MAX_BYTES: checked before
   anything opens it (opening a FIFO would wait for a writer, a device
   would never end); what it must be, said after its name */
static const char kind_rule[] = "a table is a regular file of at most 1 GiB";

int table_regular_file(const char *path, char *err, size_t errsz) {
  struct stat st;
  if (stat(path, &st) != 0) {
    table_err(err, errsz, "%s: cannot open: %s", path, strerror(errno));
    return -1;
  }
  if (!S_ISREG(st.st_mode))
    table_err(err, errsz, "%s: is %s: %s", path, file_kind(st.st_mode),
              kind_rule);
  else if ((double)st.st_size > TABLE_MAX_BYTES)
    table_err(err, errsz, "%s: is %lld bytes: %s", path, (long long)st.st_size,
              kind_rule);
  else
    return 0;
  return -1;
}

/* the whole file into a NUL-terminated buffer (a regular file only) */
static char *slurp(const char *path, size_t *len, char *err, size_t errsz) {
  char *buf, why[200];
  if (file_read_all(path, (size_t)TABLE_MAX_BYTES, kind_rule, kind_rule, &buf,
                    len, why, sizeof why) == 0)
    return buf;
  table_err(err, errsz, "%s: %s", path, why);
  return NULL;
}

/* the end of the line that starts at p: its CR or LF, or the text's NUL;
   and the start of the next line (past a CR LF pair as one line end):
   LF (Unix), CR LF (Windows) and CR alone (classic Mac OS) all end a line */
static char *line_end(char *p) { return p + strcspn(p, "\r\n"); }

static char *line_next(char *e) {
  if (*e == '\0') return e;
  return e + (e[0] == '\r' && e[1] == '\n' ? 2 : 1);
}

/* lines that hold no row: blank, or a comment starting with '#' */
static int csv_skip(const char *s, const char *e) {
  while (s < e && (*s == ' ' || *s == '\t')) s++;
  return s == e || *s == '#';
}

static int table_csv_read(table_data *t, int what, char *err, size_t errsz) {
  size_t len, rows = 0, r = 0;
  char *text = slurp(t->path, &len, err, errsz), *p, *e;
  int have[TABLE_NCOL] = {0}, col[TABLE_NCOL], ncol = 0, line, header = 0,
      rc = -1;
  if (!text) return -1;
  if (memchr(text, '\0', len) != NULL) {
    table_err(err, errsz, "%s: a NUL byte: not a text file", t->path);
    goto done;
  }
  /* a UTF-8 byte order mark (spreadsheets write one) is not a column name */
  if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) memset(text, ' ', 3);
  /* count the lines that may be rows, to allocate once */
  for (p = text; p < text + len; p = line_next(e)) {
    e = line_end(p);
    rows += !csv_skip(p, e);
  }
  for (p = text, line = 1; p < text + len; p = line_next(e), line++) {
    char *f;
    int c;
    e = line_end(p);
    if (csv_skip(p, e)) continue;
    if (!header) {
      if (!memchr(p, ',', (size_t)(e - p)) &&
          (memchr(p, ';', (size_t)(e - p)) ||
           memchr(p, '\t', (size_t)(e - p)))) {
        table_err(err, errsz,
                  "%s:%d: the columns are separated by %s; a table separates "
                  "them by commas",
                  t->path, line,
                  memchr(p, ';', (size_t)(e - p)) ? "semicolons" : "tabs");
        goto done;
      }
      if (csv_header(p, e, what, col, &ncol, have, t->path, line, err, errsz))
        goto done;
      header = 1;
      if (table_alloc_rows(t, rows - 1, have[7], 1, err, errsz)) goto done;
      continue;
    }
    t->line[r] = line;
    for (c = 0, f = p; c < ncol; c++) {
      char *q = f;
      while (q < e && *q != ',') q++;
      if (q == e && c + 1 < ncol) {
        table_err(err, errsz, "%s:%d: %d fields, the header has %d columns",
                  t->path, line, c + 1, ncol);
        goto done;
      }
      if (parse_field(f, q, table_cell(t, r, col[c]), t->path, line, p,
                      table_col_names[what][col[c]], err, errsz))
        goto done;
      f = q + 1;
      if (c + 1 == ncol && q < e) {
        table_err(err, errsz,
                  "%s:%d:%d: more fields than the header's %d columns", t->path,
                  line, (int)(q - p) + 1, ncol);
        goto done;
      }
    }
    r++;
  }
  if (!header) {
    table_err(err, errsz, "%s: no header line (t, %s, %s, %s, ...)", t->path,
              table_col_names[what][1], table_col_names[what][2],
              table_col_names[what][3]);
    goto done;
  }
  t->rates_given = have[4];
  rc = 0;
done:
  free(text);
  return rc;
}

/* the label of column c in a message: "column NAME" (CSV) or "dataset
   /NAME" (HDF5) */
static void col_label(const table_data *t, int what, int c, char *buf,
                      size_t sz) {
  snprintf(buf, sz, "%s%s", t->hdf5 ? "dataset /" : "column ",
           table_col_names[what][c]);
}

/* x in the fewest significant digits (15 to 17) that read back as x,
   as the file most likely wrote it */
static const char *num(char buf[32], double x) {
  int p;
  for (p = 15; p < 17; p++) {
    snprintf(buf, 32, "%.*g", p, x);
    if (strtod(buf, NULL) == x) return buf;
  }
  snprintf(buf, 32, "%.17g", x);
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
  if (!(t->time[r] > t->time[r - 1])) {
    table_err(err, errsz, "%s: %s: %s after %s: times must increase strictly",
              where, lt, n1, n2);
    return -1;
  }
  if (!isfinite(t->time[r] - t->time[0])) {
    table_err(
        err, errsz,
        "%s: %s: %s is more than 1.8e308 s after the first row's %s: the time "
        "range overflows a double (the times must span less than 1.8e308 s)",
        where, lt, n1, num(n2, t->time[0]));
    return -1;
  }
  if (h < scale * TIME_RESOLUTION) {
    table_err(
        err, errsz,
        "%s: %s: %s after %s: the rows are %.3g s apart, too close relative to "
        "the time scale %.3g s (the largest |t|): a step must be at least "
        "1.5e-11 of it, or the time within the step rounds by more than 1.5e-5 "
        "of the step; subtract an offset from the times or thin the rows",
        where, lt, n1, n2, h, scale);
    return -1;
  }
  if (h * h < DBL_MIN) {
    table_err(err, errsz,
              "%s: %s: %s after %s: the rows are %.3g s apart, a spacing too "
              "small for a double: the interpolant's acceleration divides by "
              "the step squared, which underflows below 1.5e-154 s",
              where, lt, n1, n2, h);
    return -1;
  }
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
  if (!isfinite(dv)) {
    table_err(
        err, errsz,
        "%s: %s: %s after %s: the change between the rows overflows a double",
        where, lc, num(n1, t->value[r][k]), num(n2, t->value[r - 1][k]));
    return -1;
  }
  /* the interpolant's acceleration: change / h^2, and with the file's
     rates rate / h, with its accelerations their own */
  mv = fabs(dv) / h / h;
  mr = t->rates_given ? (fabs(t->rate[r][k]) + fabs(t->rate[r - 1][k])) / h
                      : 0.0;
  ma = t->acc != NULL ? fabs(t->acc[r][k]) + fabs(t->acc[r - 1][k]) : 0.0;
  if (mv + mr + ma < DERIV_MAX) return 0;
  if (mv >= mr && mv >= ma) {
    table_err(err, errsz,
              "%s: %s: changes by %.3g in %.3g s from the previous row: the "
              "spacing of the rows is too small for so large a change, the "
              "interpolant's rate and acceleration across the step (of order "
              "change / step^2) overflow a double",
              where, lc, dv, h);
    return -1;
  }
  col_label(t, what, mr >= ma ? 4 + k : 7 + k, lr, sizeof lr);
  table_err(err, errsz,
            "%s: %s: %.3g and %.3g across a step of %.3g s: the interpolant's "
            "acceleration there (of order %s) overflows a double",
            where, lr, mr >= ma ? t->rate[r - 1][k] : t->acc[r - 1][k],
            mr >= ma ? t->rate[r][k] : t->acc[r][k], h,
            mr >= ma ? "rate / step" : "the accelerations themselves");
  return -1;
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
  if (t->n < (size_t)min) {
    table_err(err, errsz, "%s: %zu rows; a table needs at least %d%s", t->path,
              t->n, min,
              t->rates_given ? ""
                             : " without rate columns (the not-a-knot spline "
                               "that gives the rates)");
    return -1;
  }
  if (table_steps(t, what, err, errsz)) return -1;
  if (t->rates_given) return 0;
  work = malloc(t->n * sizeof *work);
  if (!work) {
    table_err(err, errsz, "%s: out of memory for the spline of %zu rows",
              t->path, t->n);
    return -1;
  }
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
        table_err(err, errsz,
                  "%s: %s: the spline's rate at this row overflows a double "
                  "(the values change too fast for the spacing of the rows)",
                  where, lc);
        return -1;
      }
  table_err(err, errsz, "%s: the spline of the rows failed (%s)", t->path,
            rps3_strerror(x));
  return -1;
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
