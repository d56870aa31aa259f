/*
 * table_h5.c - a table of samples from an HDF5 file (table.h): one 1-D
 * dataset per column at the file's root, each checked row by row; a
 * column whose units say degrees or millimetres is refused.
 *
 * Every column is opened and checked before anything is allocated or
 * read: its link (a hard link, or a soft link to an object of the file;
 * an external link would read another file), its storage (in the file
 * itself: external raw files and virtual datasets would read other files,
 * which the checks of the table file did not see), its type (numbers), its
 * shape (one dimension, as many rows as /t) and its declared size against
 * the table's limit (a tiny file may declare 4e8 unwritten rows).  Every
 * message names the file and the dataset, and the cause HDF5 gives.
 */
/* stat() is POSIX */
#define _XOPEN_SOURCE 700

#include "table_int.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <hdf5.h>

#include "core/h5err.h"

/* the dataset's units attribute into buf, cut to sz ("" when it has none
   or it is not a string): fixed-length and variable-length strings alike */
static void h5_units(hid_t d, char *buf, size_t sz) {
  hid_t a, ft, mt;
  buf[0] = '\0';
  if (H5Aexists(d, "units") <= 0 || (a = H5Aopen(d, "units", H5P_DEFAULT)) < 0)
    return;
  ft = H5Aget_type(a);
  if (ft >= 0 && H5Tget_class(ft) == H5T_STRING) {
    /* the memory type in the file's character set: HDF5 converts none */
    mt = H5Tcopy(H5T_C_S1);
    H5Tset_cset(mt, H5Tget_cset(ft));
    if (H5Tis_variable_str(ft) > 0) {
      char *v = NULL;
      int ok = H5Tset_size(mt, H5T_VARIABLE) >= 0 && H5Aread(a, mt, &v) >= 0;
      snprintf(buf, sz, "%s", ok && v ? v : "(unreadable)");
      if (v) H5free_memory(v);
    } else {
      /* read whole, then cut to sz: a long units text is quoted (and so
         refused), never taken as no units */
      size_t n = H5Tget_size(ft);
      char *v = n < 65536 ? calloc(n + 1, 1) : NULL;
      int ok = v && H5Tset_size(mt, n + 1) >= 0 && H5Aread(a, mt, v) >= 0;
      snprintf(buf, sz, "%s", ok ? v : "(unreadable)");
      free(v);
    }
    H5Tclose(mt);
  }
  if (ft >= 0) H5Tclose(ft);
  H5Aclose(a);
}

/* err = "FILE: dataset /NAME" and the formatted rest (": what", or
   ", row R: what"); -1 */
__attribute__((format(printf, 5, 6))) static int col_err(char *err,
                                                         size_t errsz,
                                                         const char *path,
                                                         const char *name,
                                                         const char *fmt, ...) {
  va_list ap;
  int n = snprintf(err, errsz, "%s: dataset /%s", path, name);
  va_start(ap, fmt);
  if (n >= 0 && (size_t)n < errsz)
    vsnprintf(err + n, errsz - (size_t)n, fmt, ap);
  va_end(ap);
  return -1;
}

/* "FILE: dataset /NAME: cannot WHAT: CAUSE" for the HDF5 call that just
   failed (printing is off while a table is read; h5err.h), the cause a
   plain sentence when HDF5 recorded none; NAME NULL for the file itself;
   -1 */
static int h5_fail(char *err, size_t errsz, const char *path, const char *name,
                   const char *what) {
  char why[400];
  h5_cause(why, sizeof why);
  return table_err(err, errsz, "%s: %s%s%scannot %s: %s", path,
                   name ? "dataset /" : "", name ? name : "", name ? ": " : "",
                   what, why[0] ? why : "the HDF5 library gave no cause");
}

/* a units attribute must name the column's SI unit: a column in degrees
   or millimetres is refused rather than misread */
static int h5_units_check(hid_t d, const char *path, const char *name, int what,
                          int c, char *err, size_t errsz) {
  char units[64];
  h5_units(d, units, sizeof units);
  if (table_unit_ok(what, c, units)) return 0;
  return col_err(err, errsz, path, name,
                 ": units '%s', but the table is in %s: convert the column",
                 units, table_unit_name(what, c));
}

/* the type classes that are not numbers, as a message names them */
static const char *class_name(H5T_class_t c) {
  static const char *const name[] = {
      "an integer",     "a floating-point",  "a time",     "a string",
      "a bit field",    "an opaque",         "a compound", "a reference",
      "an enumeration", "a variable-length", "an array"};
  return c >= 0 && (size_t)c < sizeof name / sizeof name[0] ? name[c]
                                                            : "an unknown";
}

/* the rule a column stored elsewhere breaks, after what it is */
#define IN_FILE ": a table's columns must be stored in the table file itself"

/* the link of a column: a hard link, or a soft link to an object of this
   file; an external link (another file) or a user-defined one is refused */
static int h5_link_check(hid_t f, const char *path, const char *name, char *err,
                         size_t errsz) {
  H5L_info_t li;
  char *val;
  const char *file = NULL, *obj = NULL;
  unsigned flags;
  int rc = -1;
  if (H5Lget_info(f, name, &li, H5P_DEFAULT) < 0)
    return h5_fail(err, errsz, path, name, "read its link");
  if (li.type == H5L_TYPE_HARD) return 0;
  if (li.type != H5L_TYPE_SOFT && li.type != H5L_TYPE_EXTERNAL)
    return col_err(err, errsz, path, name,
                   ": a user-defined link (type %d): a table's columns are "
                   "datasets of the file itself",
                   (int)li.type);
  /* the link's value: a path (soft), or a file and a path (external) */
  if (li.u.val_size > 65536 || (val = calloc(li.u.val_size + 1, 1)) == NULL)
    return col_err(err, errsz, path, name, ": a %s link of %zu bytes",
                   li.type == H5L_TYPE_SOFT ? "soft" : "external",
                   li.u.val_size);
  if (H5Lget_val(f, name, val, li.u.val_size, H5P_DEFAULT) < 0) {
    h5_fail(err, errsz, path, name, "read its link");
  } else if (li.type == H5L_TYPE_SOFT) {
    if (H5Oexists_by_name(f, name, H5P_DEFAULT) > 0)
      rc = 0;
    else
      col_err(err, errsz, path, name,
              ": a soft link to '%.200s', which names no object of the file (a "
              "dangling link)",
              val);
    H5Eclear2(H5E_DEFAULT);
  } else if (H5Lunpack_elink_val(val, li.u.val_size, &flags, &file, &obj) >=
             0) {
    col_err(err, errsz, path, name,
            ": an external link to %.200s:%.200s" IN_FILE, file, obj);
  } else {
    col_err(err, errsz, path, name,
            ": an external link (to another file)" IN_FILE);
  }
  free(val);
  return rc;
}

/* the source file of a virtual dataset exists: "." is the file itself
   (and then its dataset must exist), a relative name is taken from the
   table's directory, as HDF5 does without HDF5_VDS_PREFIX */
static int h5_source_exists(hid_t f, const char *path, const char *file,
                            const char *dset) {
  const char *slash = strrchr(path, '/');
  struct stat st;
  char full[4200];
  if (strcmp(file, ".") == 0) {
    int x = H5Lexists(f, dset, H5P_DEFAULT) > 0 &&
            H5Oexists_by_name(f, dset, H5P_DEFAULT) > 0;
    H5Eclear2(H5E_DEFAULT);
    return x;
  }
  if (file[0] == '/' || slash == NULL)
    snprintf(full, sizeof full, "%s", file);
  else
    snprintf(full, sizeof full, "%.*s/%s", (int)(slash - path), path, file);
  return stat(full, &st) == 0;
}

/* the column's storage is in the file itself: a virtual dataset's rows
   are in other datasets (a missing source reads as fill values) and an
   external one's in raw files (any file: /etc/passwd read as numbers) */
static int h5_storage_check(hid_t f, hid_t d, const char *path,
                            const char *name, char *err, size_t errsz) {
  hid_t p = H5Dget_create_plist(d);
  int rc = -1, next;
  if (p < 0) return h5_fail(err, errsz, path, name, "read how it is stored");
  next = H5Pget_external_count(p);
  if (H5Pget_layout(p) == H5D_VIRTUAL) {
    size_t nsrc = 0;
    char file[1024] = "", dset[1024] = "";
    if (H5Pget_virtual_count(p, &nsrc) >= 0 && nsrc > 0 &&
        H5Pget_virtual_filename(p, 0, file, sizeof file) >= 0 &&
        H5Pget_virtual_dsetname(p, 0, dset, sizeof dset) >= 0) {
      file[sizeof file - 1] = dset[sizeof dset - 1] = '\0';
      col_err(err, errsz, path, name,
              ": a virtual dataset, its rows in %.200s:%.200s%s%s" IN_FILE,
              file, dset,
              h5_source_exists(f, path, file, dset) ? "" : ", which is missing",
              nsrc > 1 ? " and other sources" : "");
    } else {
      col_err(err, errsz, path, name,
              ": a virtual dataset (its rows in other datasets)" IN_FILE);
    }
    H5Eclear2(H5E_DEFAULT);
  } else if (next != 0) {
    char file[1024] = "";
    off_t off;
    hsize_t size;
    if (next > 0 && H5Pget_external(p, 0, sizeof file, file, &off, &size) >= 0)
      file[sizeof file - 1] = '\0';
    else
      snprintf(file, sizeof file, "?");
    H5Eclear2(H5E_DEFAULT);
    col_err(err, errsz, path, name,
            ": stored in the external raw file '%.200s'%s" IN_FILE, file,
            next > 1 ? " and others" : "");
  } else {
    rc = 0;
  }
  H5Pclose(p);
  return rc;
}

/* the element size of column d's numbers (integers or floating point);
   0 or -1 with err set */
static int h5_column_type(hid_t d, const char *path, const char *name,
                          size_t *el, char *err, size_t errsz) {
  hid_t ty;
  H5T_class_t cls;
  if ((ty = H5Dget_type(d)) < 0 || (cls = H5Tget_class(ty)) == H5T_NO_CLASS) {
    h5_fail(err, errsz, path, name, "read its type");
    if (ty >= 0) H5Tclose(ty);
    return -1;
  }
  *el = H5Tget_size(ty);
  H5Tclose(ty);
  if (cls != H5T_INTEGER && cls != H5T_FLOAT)
    return col_err(err, errsz, path, name,
                   ": of %s type, not numbers (a column holds integers or "
                   "floating-point numbers)",
                   class_name(cls));
  return 0;
}

/* the rows of column d, which has one dimension; 0 or -1 with err set */
static int h5_column_rows(hid_t d, const char *path, const char *name,
                          hsize_t *rows, char *err, size_t errsz) {
  hid_t sp = H5Dget_space(d);
  int nd;
  H5S_class_t type;
  if (sp < 0) return h5_fail(err, errsz, path, name, "read its shape");
  nd = H5Sget_simple_extent_ndims(sp);
  type = H5Sget_simple_extent_type(sp);
  if (type == H5S_SIMPLE && nd == 1 &&
      H5Sget_simple_extent_dims(sp, rows, NULL) == 1) {
    H5Sclose(sp);
    return 0;
  }
  H5Sclose(sp);
  H5Eclear2(H5E_DEFAULT);
  if (type == H5S_NULL)
    col_err(err, errsz, path, name,
            ": holds nothing (a null dataspace); a column has one dimension");
  else if (type == H5S_SCALAR || nd == 0)
    col_err(err, errsz, path, name,
            ": a single value (a scalar); a column has one dimension");
  else
    col_err(err, errsz, path, name, ": %d dimensions; a column has one", nd);
  return -1;
}

/* column c (named name): open it and check everything but its rows'
   values; rows and the bytes it declares (as read: elements of at least a
   double's 8 bytes) out.  0, or -1 with err set (d closed) */
static int h5_open_column(hid_t f, const char *path, const char *name, int what,
                          int c, hid_t *out, hsize_t *rows, double *bytes,
                          char *err, size_t errsz) {
  hid_t d;
  size_t el;
  H5I_type_t kind;
  if (h5_link_check(f, path, name, err, errsz)) return -1;
  d = H5Oopen(f, name, H5P_DEFAULT);
  if (d < 0) return h5_fail(err, errsz, path, name, "be opened");
  kind = H5Iget_type(d);
  if (kind != H5I_DATASET) {
    H5Oclose(d);
    return col_err(err, errsz, path, name, ": a %s, not a dataset",
                   kind == H5I_GROUP      ? "group"
                   : kind == H5I_DATATYPE ? "named datatype"
                                          : "object of another kind");
  }
  if (h5_storage_check(f, d, path, name, err, errsz) ||
      h5_column_type(d, path, name, &el, err, errsz) ||
      h5_column_rows(d, path, name, rows, err, errsz) ||
      h5_units_check(d, path, name, what, c, err, errsz)) {
    H5Oclose(d);
    return -1;
  }
  *bytes = (double)*rows * (double)(el > sizeof(double) ? el : sizeof(double));
  if (*bytes > TABLE_MAX_BYTES) {
    H5Oclose(d);
    return col_err(err, errsz, path, name,
                   ": declares %llu rows of %zu-byte numbers, %.3g GB as read: "
                   "above the table limit of 1 GiB",
                   (unsigned long long)*rows, el, *bytes / 1e9);
  }
  *out = d;
  return 0;
}

/* the values of column c, read from d into the table's arrays (a strided
   memory selection: column k of the n x 3 array), each checked */
static int h5_read_column(hid_t d, table_data *t, const char *name, int c,
                          char *err, size_t errsz) {
  hsize_t dims[2], start[2] = {0, 0}, count[2];
  hid_t ms;
  herr_t x;
  size_t r;
  if (t->n == 0) return 0;
  dims[0] = count[0] = t->n;
  dims[1] = c ? 3 : 1;
  count[1] = 1;
  if (c) start[1] = (hsize_t)((c - 1) % 3);
  ms = H5Screate_simple(2, dims, NULL);
  x = ms < 0
          ? -1
          : H5Sselect_hyperslab(ms, H5S_SELECT_SET, start, NULL, count, NULL);
  if (x >= 0)
    x = H5Dread(d, H5T_NATIVE_DOUBLE, ms, H5S_ALL, H5P_DEFAULT,
                c == 0   ? t->time
                : c < 4  ? t->value[0]
                : c < 7  ? t->rate[0]
                : c < 10 ? t->acc[0]
                         : t->force[0]);
  /* the cause first: a successful call clears HDF5's error stack */
  if (x < 0) h5_fail(err, errsz, t->path, name, "read it as numbers");
  if (ms >= 0) H5Sclose(ms);
  if (x < 0) return -1;
  for (r = 0; r < t->n; r++) {
    double v = *table_cell(t, r, c);
    if (table_bad_number(v))
      return col_err(err, errsz, t->path, name, ", row %zu: %g %s", r, v,
                     table_bad_number(v));
  }
  return 0;
}

int table_h5_read(table_data *t, int what, char *err, size_t errsz) {
  H5E_auto2_t fn;
  void *data;
  hid_t f, d[TABLE_NCOL];
  hsize_t rows = 0;
  double bytes = 0.0, sum = 0.0;
  int have[TABLE_NCOL] = {0}, c, rc = -1;
  const char *const *names = table_col_names[what];
  int nc = table_ncol(what);
  for (c = 0; c < TABLE_NCOL; c++) d[c] = -1;
  if (table_regular_file(t->path, err, errsz)) return -1;
  H5Eget_auto2(H5E_DEFAULT, &fn, &data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  H5Eclear2(H5E_DEFAULT);
  f = H5Fopen(t->path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) {
    h5_fail(err, errsz, t->path, NULL, "open as an HDF5 file");
    H5Eset_auto2(H5E_DEFAULT, fn, data);
    return -1;
  }
  for (c = 0; c < nc; c++) {
    htri_t x = H5Lexists(f, names[c], H5P_DEFAULT);
    if (x < 0) {
      /* not absent: the file's root cannot be read (a damaged file) */
      h5_fail(err, errsz, t->path, names[c],
              "look it up in the file's root group");
      goto done;
    }
    have[c] = x > 0;
  }
  if (table_columns_check(have, what, 1, t->path, err, errsz)) goto done;
  /* every column opened and checked, its declared size with them, before
     anything is allocated: the time first, it gives the rows */
  for (c = 0; c < nc; c++) {
    if (!have[c]) continue;
    if (h5_open_column(f, t->path, names[c], what, c, &d[c], &rows, &bytes, err,
                       errsz))
      goto done;
    if (c == 0) {
      t->n = (size_t)rows;
    } else if (rows != (hsize_t)t->n) {
      col_err(err, errsz, t->path, names[c], ": %llu rows, /t has %zu",
              (unsigned long long)rows, t->n);
      goto done;
    }
    sum += bytes;
    if (sum > TABLE_MAX_BYTES) {
      col_err(err, errsz, t->path, names[c],
              ": with it the datasets declare %.3g GB as read (%zu rows each): "
              "above the table limit of 1 GiB",
              sum / 1e9, t->n);
      goto done;
    }
  }
  if (table_alloc_rows(t, t->n, have[7], 0, err, errsz)) goto done;
  for (c = 0; c < nc; c++)
    if (have[c] && h5_read_column(d[c], t, names[c], c, err, errsz)) goto done;
  t->rates_given = have[4];
  rc = 0;
done:
  for (c = 0; c < TABLE_NCOL; c++)
    if (d[c] >= 0) H5Dclose(d[c]);
  H5Fclose(f);
  H5Eclear2(H5E_DEFAULT);
  H5Eset_auto2(H5E_DEFAULT, fn, data);
  return rc;
}
