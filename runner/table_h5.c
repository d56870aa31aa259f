/*
 * table_h5.c - a table of samples from an HDF5 file (table.h): one 1-D
 * dataset per column at the file's root, each checked row by row; a
 * column whose units say degrees or millimetres is refused.
 */
#include "table_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

/* the units each column must be in, in the spellings a units attribute may
   use for them (UDUNITS symbols and names); "" ends a list */
static const char *const col_units[2][TABLE_NCOL][6] = {
    {{"s", "second", "seconds", ""}, {"rad", "radian", "radians", ""},
     {"rad", "radian", "radians", ""}, {"m", "meter", "metre", "meters",
                                        "metres", ""},
     {"rad/s", "rad s-1", ""}, {"rad/s", "rad s-1", ""}, {"m/s", "m s-1", ""},
     {"rad/s^2", "rad/s2", "rad s-2", ""}, {"rad/s^2", "rad/s2", "rad s-2", ""},
     {"m/s^2", "m/s2", "m s-2", ""}},
    {{"s", "second", "seconds", ""}, {"m", "meter", "metre", "meters",
                                      "metres", ""},
     {"m", "meter", "metre", "meters", "metres", ""},
     {"m", "meter", "metre", "meters", "metres", ""}, {"m/s", "m s-1", ""},
     {"m/s", "m s-1", ""}, {"m/s", "m s-1", ""}, {"m/s^2", "m/s2", "m s-2", ""},
     {"m/s^2", "m/s2", "m s-2", ""}, {"m/s^2", "m/s2", "m s-2", ""}}};

/* the dataset's units attribute into buf ("" when it has none or it is
   not a string): fixed-length and variable-length strings alike */
static void h5_units(hid_t d, char *buf, size_t sz)
{
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
      if (H5Tset_size(mt, H5T_VARIABLE) >= 0 && H5Aread(a, mt, &v) >= 0 && v)
        snprintf(buf, sz, "%s", v);
      if (v)
        H5free_memory(v);
    } else {
      size_t n = H5Tget_size(ft);
      if (n < sz && H5Tset_size(mt, n + 1) >= 0 && H5Aread(a, mt, buf) < 0)
        buf[0] = '\0';
    }
    H5Tclose(mt);
  }
  if (ft >= 0)
    H5Tclose(ft);
  H5Aclose(a);
}

/* a units attribute must name the column's SI unit: a column in degrees
   or millimetres is refused rather than misread */
static int h5_units_check(hid_t d, const char *path, const char *name,
                          int what, int c, char *err, size_t errsz)
{
  char units[64];
  int i;
  h5_units(d, units, sizeof units);
  if (units[0] == '\0')
    return 0;
  for (i = 0; col_units[what][c][i][0] != '\0'; i++)
    if (strcmp(units, col_units[what][c][i]) == 0)
      return 0;
  table_err(err, errsz, "%s: dataset /%s: units '%s', but the table is in "
          "%s: convert the column", path, name, units, col_units[what][c][0]);
  return -1;
}

/* one 1-D dataset of n doubles at the root (n taken from the first) */
static int h5_column(hid_t f, const char *name, table_data *t, int what,
                     int c, char *err, size_t errsz)
{
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT), sp;
  hsize_t dims[2];
  double *buf = NULL;
  int rc = -1;
  size_t r;
  if (d < 0)
    return 1; /* absent */
  sp = H5Dget_space(d);
  if (h5_units_check(d, t->path, name, what, c, err, errsz))
    goto done;
  if (sp < 0 || H5Sget_simple_extent_ndims(sp) != 1 ||
      H5Sget_simple_extent_dims(sp, dims, NULL) != 1) {
    table_err(err, errsz, "%s: dataset /%s: expected one dimension", t->path,
            name);
    goto done;
  }
  if (t->n == 0 && c == 0) {
    t->n = (size_t)dims[0];
  } else if ((size_t)dims[0] != t->n) {
    table_err(err, errsz, "%s: dataset /%s: %llu rows, /t has %zu", t->path,
            name, (unsigned long long)dims[0], t->n);
    goto done;
  }
  buf = malloc((t->n ? t->n : 1) * sizeof *buf);
  if (!buf || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                      buf) < 0) {
    table_err(err, errsz, "%s: dataset /%s: cannot read it as numbers", t->path,
            name);
    goto done;
  }
  for (r = 0; r < t->n; r++) {
    if (!isfinite(buf[r])) {
      table_err(err, errsz, "%s: dataset /%s, row %zu: %g is not a finite "
              "number", t->path, name, r, buf[r]);
      goto done;
    }
    if (t->time != NULL)
      *table_cell(t, r, c) = buf[r];
  }
  if (c == 0) {
    /* the time column sizes the table: keep it until the arrays exist */
    t->time = buf;
    buf = NULL;
  }
  rc = 0;
done:
  free(buf);
  if (sp >= 0)
    H5Sclose(sp);
  H5Dclose(d);
  return rc;
}

int table_h5_read(table_data *t, int what, char *err, size_t errsz)
{
  H5E_auto2_t fn;
  void *data;
  hid_t f;
  int have[TABLE_NCOL] = {0}, c, rc = -1, x;
  if (table_regular_file(t->path, err, errsz))
    return -1;
  H5Eget_auto2(H5E_DEFAULT, &fn, &data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  f = H5Fopen(t->path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) {
    table_err(err, errsz, "%s: cannot open as an HDF5 file", t->path);
    H5Eset_auto2(H5E_DEFAULT, fn, data);
    return -1;
  }
  for (c = 0; c < TABLE_NCOL; c++)
    have[c] = H5Lexists(f, table_col_names[what][c], H5P_DEFAULT) > 0;
  if (table_columns_check(have, what, t->path, err, errsz))
    goto done;
  /* the time first: it gives the rows */
  if (h5_column(f, table_col_names[what][0], t, what, 0, err, errsz))
    goto done;
  {
    double *time = t->time;
    t->time = NULL;
    x = table_alloc_rows(t, t->n, have[7]);
    free(t->time);
    t->time = time;
    if (x) {
      table_err(err, errsz, "%s: out of memory for %zu rows", t->path, t->n);
      goto done;
    }
  }
  for (c = 1; c < TABLE_NCOL; c++)
    if (have[c] && h5_column(f, table_col_names[what][c], t, what, c, err, errsz))
      goto done;
  t->rates_given = have[4];
  rc = 0;
done:
  H5Fclose(f);
  H5Eset_auto2(H5E_DEFAULT, fn, data);
  return rc;
}
