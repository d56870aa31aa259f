/*
 * table.c - the rows of a CSV table, and what the CSV and the HDF5 reader
 * (table_h5.c) share: the columns, the cells, the checks of a number.
 * Every row is checked where it is read, so that an error names the file,
 * the line (or row) and the column: a number that is not one, NaN or
 * infinity.
 */
#define _XOPEN_SOURCE 700 /* stat */

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

const char *const table_col_names[3][TABLE_NCOL] = {
    {"t", "alpha", "beta", "z_c", "alpha_dot", "beta_dot", "z_c_dot",
     "alpha_ddot", "beta_ddot", "z_c_ddot"},
    {"t", "x", "y", "z", "x_dot", "y_dot", "z_dot", "x_ddot", "y_ddot",
     "z_ddot"},
    {"t", "l1", "l2", "l3", "l1_dot", "l2_dot", "l3_dot", "l1_ddot", "l2_ddot",
     "l3_ddot", "F1", "F2", "F3"}};

int table_ncol(int what) { return what == TABLE_MEASURED ? 13 : 10; }

/* the units a column may be in, in the spellings a units attribute may
   use for them (UDUNITS symbols and names); "" ends a list */
static const char *const unit_spellings[8][6] = {
    {"s", "second", "seconds", ""},
    {"rad", "radian", "radians", ""},
    {"m", "meter", "metre", "meters", "metres", ""},
    {"rad/s", "rad s-1", ""},
    {"m/s", "m s-1", ""},
    {"rad/s^2", "rad/s2", "rad s-2", ""},
    {"m/s^2", "m/s2", "m s-2", ""},
    {"N", "newton", "newtons", ""}};

/* the units of each column (a row of unit_spellings) for TABLE_POSE,
   TABLE_CENTRE and TABLE_MEASURED */
static const int col_units[3][TABLE_NCOL] = {
    {0, 1, 1, 2, 3, 3, 4, 5, 5, 6},
    {0, 2, 2, 2, 4, 4, 4, 6, 6, 6},
    {0, 2, 2, 2, 4, 4, 4, 6, 6, 6, 7, 7, 7}};

int table_unit_ok(int what, int c, const char *units) {
  const char *const *ok = unit_spellings[col_units[what][c]];
  int i;
  if (units[0] == '\0') return 1;
  for (i = 0; ok[i][0] != '\0'; i++)
    if (strcmp(units, ok[i]) == 0) return 1;
  return 0;
}

const char *table_unit_name(int what, int c) {
  return unit_spellings[col_units[what][c]][0];
}

int table_err(char *err, size_t errsz, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errsz, fmt, ap);
  va_end(ap);
  return -1;
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
  free(t->force);
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
  int forces = t->what == TABLE_MEASURED;
  double row =
      sizeof(double) * (8.0 + (with_acc ? 3.0 : 0.0) + (forces ? 3.0 : 0.0)) +
      (with_line ? (double)sizeof(int) : 0.0);
  if ((double)n * row > TABLE_MAX_BYTES)
    return table_err(err, errsz,
                     "%s: %zu rows need %.3g GB in memory (%.0f bytes a row): "
                     "above the table limit of 1 GiB",
                     t->path, n, (double)n * row / 1e9, row);
  t->n = n;
  t->time = malloc(m * sizeof *t->time);
  t->value = malloc(m * sizeof *t->value);
  t->rate = malloc(m * sizeof *t->rate);
  t->acc = with_acc ? malloc(m * sizeof *t->acc) : NULL;
  t->line = with_line ? malloc(m * sizeof *t->line) : NULL;
  t->force = forces ? malloc(m * sizeof *t->force) : NULL;
  if (t->time && t->value && t->rate && (t->acc || !with_acc) &&
      (t->line || !with_line) && (t->force || !forces))
    return 0;
  return table_err(err, errsz, "%s: out of memory for %zu rows", t->path, n);
}

double *table_cell(table_data *t, size_t r, int c) {
  if (c == 0) return &t->time[r];
  if (c < 4) return &t->value[r][c - 1];
  if (c < 7) return &t->rate[r][c - 4];
  if (c < 10) return &t->acc[r][c - 7];
  return &t->force[r][c - 10];
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
    if (!have[c])
      return table_err(err, errsz,
                       "%s: missing %s%s (a table has %s, %s, %s, %s)", file,
                       kind, n[c], n[0], n[1], n[2], n[3]);
  /* an identification's data: every column (the C fit uses the measured
     rates and accelerations, it does not differentiate) */
  for (c = 4; what == TABLE_MEASURED && c < TABLE_NCOL; c++)
    if (!have[c])
      return table_err(err, errsz,
                       "%s: missing %s%s: an identification's data need the "
                       "measured rates l1_dot, l2_dot, l3_dot, accelerations "
                       "l1_ddot, l2_ddot, l3_ddot and forces F1, F2, F3",
                       file, kind, n[c]);
  for (g = 4; g < table_ncol(what); g += 3)
    if (have[g] + have[g + 1] + have[g + 2] != 0 &&
        have[g] + have[g + 1] + have[g + 2] != 3) {
      for (c = g; have[c]; c++)
        ;
      return table_err(err, errsz,
                       "%s: missing %s%s (give the three %s or none)", file,
                       kind, n[c], g == 4 ? "rates" : "accelerations");
    }
  if (have[7] && !have[4])
    return table_err(
        err, errsz,
        "%s: accelerations (%s%s, ...) need the rates (%s%s, ...) as well",
        file, kind, n[7], kind, n[4]);
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
  if (e == s)
    return table_err(err, errsz, "%s:%d:%d: column %s: empty field", file, line,
                     col, name);
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
  return table_err(err, errsz, "%s:%d:%d: column %s: %s", file, line, col, name,
                   why);
}

/* the header line [s, e): column c of the file is col[c] (0..TABLE_NCOL-1) */
static int csv_header(const char *s, const char *e, int what, int *col,
                      int *ncol, int have[TABLE_NCOL], const char *file,
                      int line, char *err, size_t errsz) {
  const char *p = s;
  int nc = table_ncol(what);
  *ncol = 0;
  for (;;) {
    const char *q = p, *a, *b, *u, *ue;
    int c;
    while (q < e && *q != ',') q++;
    for (a = p; a < q && (*a == ' ' || *a == '\t'); a++)
      ;
    for (b = q; b > a && (b[-1] == ' ' || b[-1] == '\t'); b--)
      ;
    /* "NAME [UNITS]": the units must be the column's */
    u = ue = NULL;
    if (b > a && b[-1] == ']')
      for (ue = b - 1, u = ue; u > a && u[-1] != '['; u--)
        ;
    if (u && u > a)
      for (b = u - 1; b > a && (b[-1] == ' ' || b[-1] == '\t'); b--)
        ;
    else
      u = NULL;
    for (c = 0; c < nc; c++)
      if ((size_t)(b - a) == strlen(table_col_names[what][c]) &&
          strncmp(a, table_col_names[what][c], (size_t)(b - a)) == 0)
        break;
    if (c == nc || have[c] || *ncol == nc) {
      char list[200], name[HINT_MAX_LEN + 1], hint[120] = "";
      int k;
      size_t len = 0;
      for (k = 0; k < nc; k++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s",
                                k ? ", " : "", table_col_names[what][k]);
      snprintf(name, sizeof name, "%.*s", (int)(b - a), a);
      if (c == nc)
        hint_text(hint, sizeof hint, name, table_col_names[what], (size_t)nc);
      return table_err(err, errsz, "%s:%d:%d: column '%s': %s%s; expected %s",
                       file, line, (int)(a - s) + 1, name,
                       c < nc ? "given twice" : "unknown column", hint, list);
    }
    if (u) {
      char units[64];
      snprintf(units, sizeof units, "%.*s", (int)(ue - u), u);
      if (!table_unit_ok(what, c, units))
        return table_err(err, errsz,
                         "%s:%d:%d: column %s: units '%s', but the table is in "
                         "%s: convert the column",
                         file, line, (int)(u - s) + 1, table_col_names[what][c],
                         units, table_unit_name(what, c));
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
  if (stat(path, &st) != 0)
    return table_err(err, errsz, "%s: cannot open: %s", path, strerror(errno));
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

int table_csv_read(table_data *t, int what, char *err, size_t errsz) {
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
