/*
 * output.c - write a sweep as a self-describing HDF5 file (netCDF-4 style:
 * dimension scales on every axis, units and description on every dataset),
 * readable by h5py and by xarray through h5netcdf.
 */
#include "output.h"
#include "h5err.h"
#include "out_cf.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <yaml.h>

/* swept values are written in runs of this many cases */
#define AXIS_RUN 65536

/* ------------------------------------------------------------ HDF5 bits */

struct out_file {
  hid_t file;
  hid_t ds[OUT_NFIELD];
  hid_t case_time;    /* [case, time] when the grid differs, else -1 */
  hid_t str;          /* variable-length UTF-8 string type */
  size_t ncase;
  size_t nt;
  int neffect;
  out_layout layout;  /* for out_pack */
};

static void vfail(char *err, size_t errsz, const char *fmt, va_list ap)
{
  char h5[600], what[256];
  h5_cause(h5, sizeof h5);
  vsnprintf(what, sizeof what, fmt, ap);
  snprintf(err, errsz, "%s%s%s", what, h5[0] ? ": HDF5: " : "", h5);
}

static void fail(char *err, size_t errsz, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vfail(err, errsz, fmt, ap);
  va_end(ap);
}

void out_fail(char *err, size_t errsz, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vfail(err, errsz, fmt, ap);
  va_end(ap);
}

int out_h5_attr(hid_t obj, hid_t str, const char *name, const char *value)
{
  hid_t sp = H5Screate(H5S_SCALAR), a;
  int rc = -1;
  if (sp < 0)
    return -1;
  a = H5Acreate2(obj, name, str, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    rc = H5Awrite(a, str, &value) < 0 ? -1 : 0;
    H5Aclose(a);
  }
  H5Sclose(sp);
  return rc;
}

/* a dataset with units and description attributes; chunk may be NULL
   (contiguous) */
/* the HDF5 memory/file type of a schema field */
static hid_t field_type(const out_file *f, const out_field_info *fi) {
  return fi->type == OUT_F64   ? H5T_NATIVE_DOUBLE
         : fi->type == OUT_I32 ? H5T_NATIVE_INT32
                               : f->str;
}

hid_t out_h5_dataset(hid_t file, hid_t str, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const hsize_t *chunk,
                     int gzip, const void *fill, const char *units,
                     const char *doc)
{
  hid_t sp = rank ? H5Screate_simple(rank, dims, NULL) : H5Screate(H5S_SCALAR);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE), lcpl = H5Pcreate(H5P_LINK_CREATE);
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  hid_t ds = -1;
  if (sp < 0 || dcpl < 0 || lcpl < 0 || dapl < 0)
    goto done;
  /* tiles are whole chunks, written once: no chunk cache, so that memory
     does not hold a chunk per dataset */
  if (H5Pset_chunk_cache(dapl, 0, 0, 1.0) < 0)
    goto done;
  /* names such as manipulator.rho are plain names, no groups */
  if (chunk && H5Pset_chunk(dcpl, rank, chunk) < 0)
    goto done;
  if (chunk && gzip > 0 && H5Pset_deflate(dcpl, (unsigned)gzip) < 0)
    goto done;
  /* a checksum of each stored chunk (after deflate: of the bytes on disk),
     checked by every read: merge refuses a damaged part (verify.h); the
     strings' chunks hold heap references, which HDF5 does not checksum */
  if (chunk && H5Tis_variable_str(type) <= 0 && H5Pset_fletcher32(dcpl) < 0)
    goto done;
  if (fill && H5Pset_fill_value(dcpl, type, fill) < 0)
    goto done;
  if (H5Pset_char_encoding(lcpl, H5T_CSET_UTF8) < 0)
    goto done;
  ds = H5Dcreate2(file, name, type, sp, lcpl, dcpl, dapl);
  if (ds >= 0 && (out_h5_attr(ds, str, "units", units) < 0 ||
                  out_h5_attr(ds, str, "description", doc) < 0)) {
    H5Dclose(ds);
    ds = -1;
  }
done:
  if (sp >= 0)
    H5Sclose(sp);
  if (dcpl >= 0)
    H5Pclose(dcpl);
  if (lcpl >= 0)
    H5Pclose(lcpl);
  if (dapl >= 0)
    H5Pclose(dapl);
  return ds;
}

/* write all of a small dataset */
static int write_all(hid_t ds, hid_t type, const void *data)
{
  return H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0 ? -1 : 0;
}

/* write n elements from data into rows [c0, c0 + n) of a [case] dataset */
int out_h5_rows(hid_t ds, hid_t type, size_t c0, size_t n,
                      const void *data)
{
  hsize_t start = c0, count = n;
  hid_t fs = H5Dget_space(ds), ms = H5Screate_simple(1, &count, NULL);
  int rc = -1;
  if (fs >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &count, NULL) >=
          0 &&
      H5Dwrite(ds, type, ms, fs, H5P_DEFAULT, data) >= 0)
    rc = 0;
  if (fs >= 0)
    H5Sclose(fs);
  if (ms >= 0)
    H5Sclose(ms);
  return rc;
}

/* a dimension scale: a 1-D dataset named after its dimension */
hid_t out_h5_scale(hid_t file, hid_t str, const char *name, hid_t type,
                   size_t n, const void *data, const char *units,
                   const char *doc)
{
  hsize_t dim = n;
  hid_t ds = out_h5_dataset(file, str, name, type, 1, &dim, NULL, 0, NULL,
                            units, doc);
  if (ds < 0)
    return -1;
  if ((data && write_all(ds, type, data) < 0) || H5DSset_scale(ds, name) < 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

/* "a b c": the coordinates attribute of the per-case variables */
char *out_h5_coordinates(const scene *s, int grid_common)
{
  size_t a, len = 1;
  char *c;
  for (a = 0; a < s->naxis; a++)
    len += strlen(s->axis[a].path) + 1;
  len += grid_common ? 0 : strlen(" case_time");
  c = malloc(len);
  if (!c)
    return NULL;
  c[0] = '\0';
  for (a = 0; a < s->naxis; a++) {
    if (a)
      strcat(c, " ");
    strcat(c, s->axis[a].path);
  }
  if (!grid_common)
    strcat(c, s->naxis ? " case_time" : "case_time");
  return c;
}

/* the swept values of axis a, case by case, in runs of AXIS_RUN cases */
int out_h5_axis(hid_t ds, hid_t str, const scene *s, size_t a)
{
  const scene_axis *ax = &s->axis[a];
  const scene_key_info *ki = scene_key_get(ax->key);
  size_t c0, i, n;
  int rc = 0;
  void *buf = malloc(AXIS_RUN * sizeof(double));
  if (!buf)
    return -1;
  for (c0 = 0; c0 < s->ncase && rc == 0; c0 += n) {
    n = s->ncase - c0 < AXIS_RUN ? s->ncase - c0 : AXIS_RUN;
    for (i = 0; i < n; i++) {
      double x = ax->val[scene_case_coord(s, c0 + i, a)];
      if (ki->type == KEY_REAL || ki->type == KEY_REAL3)
        ((double *)buf)[i] = x;
      else if (ki->type == KEY_ENUM)
        ((const char **)buf)[i] = scene_enum_name(ax->key, (int)x);
      else
        ((int32_t *)buf)[i] = (int32_t)x;
    }
    rc = out_h5_rows(ds,
                    (ki->type == KEY_REAL || ki->type == KEY_REAL3)
                        ? H5T_NATIVE_DOUBLE
                    : ki->type == KEY_ENUM ? str
                                           : H5T_NATIVE_INT32,
                    c0, n, buf);
  }
  free(buf);
  return rc;
}

/* the time now, ISO 8601 in UTC */
void out_utc_now(char now[32])
{
  time_t t = time(NULL);
  struct tm tm;
  gmtime_r(&t, &tm);
  strftime(now, 32, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

int out_stamp(hid_t file, const char *command_line)
{
  char now[32];
  hid_t str = H5Tcopy(H5T_C_S1);
  int rc = -1;
  out_utc_now(now);
  if (str >= 0 && H5Tset_size(str, H5T_VARIABLE) >= 0 &&
      H5Tset_cset(str, H5T_CSET_UTF8) >= 0 &&
      (H5Aexists(file, "created_utc") <= 0 ||
       H5Adelete(file, "created_utc") >= 0) &&
      (H5Aexists(file, "command_line") <= 0 ||
       H5Adelete(file, "command_line") >= 0) &&
      out_h5_attr(file, str, "created_utc", now) >= 0 &&
      out_h5_attr(file, str, "command_line", command_line) >= 0 &&
      out_cf_history_add(file, str, now, command_line) >= 0)
    rc = 0;
  if (str >= 0)
    H5Tclose(str);
  return rc;
}

/* the root attributes: versions, time of creation, command line */
static int root_attrs(hid_t file, hid_t str, const out_meta *meta)
{
  char now[32], h5v[32], fields[1024];
  unsigned maj, min, rel;
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (out_h5_attr(file, str, "rps3_version", rps3_version()) < 0 ||
          out_h5_attr(file, str, "created_utc", now) < 0 ||
          out_h5_attr(file, str, "command_line", meta->command_line) < 0 ||
          out_h5_attr(file, str, "gsl_version", gsl_version) < 0 ||
          out_h5_attr(file, str, "hdf5_version", h5v) < 0 ||
          out_h5_attr(file, str, "yaml_version",
                      yaml_get_version_string()) < 0 ||
          out_h5_attr(file, str, "title",
                   "rps3: inverse dynamics of the Lee & Shah 3-RPS "
                   "manipulator along a trajectory, per case of a sweep") < 0 ||
          out_h5_attr(file, str, "fields",
                   out_fields_text(meta->fields, fields, sizeof fields)) < 0 ||
          out_cf_root(file, str, now, meta->command_line) < 0 ||
          (meta->shard && out_h5_attr(file, str, "shard", meta->shard) < 0))
             ? -1
             : 0;
}

out_file *out_create(const char *path, const scene *s,
                     const scene_case *first, size_t nt, int grid_common,
                     size_t chunk_points, const out_block *b,
                     const out_meta *meta, char *err, size_t errsz)
{
  static const int32_t one23[3] = {1, 2, 3};
  const double fnan = (double)NAN;
  const int32_t fneg = -1, fnotrun = OUT_STATUS_NOT_COMPUTED;
  out_file *f = calloc(1, sizeof *f);
  hid_t dcase = -1, dtime = -1, dlink = -1, deff = -1, dcon = -1;
  hid_t *axis_ds = NULL;
  hsize_t dims[4], chunk[4];
  char *coords = NULL;
  const char *names[RPS3_NEFFECT];
  size_t a, k, c0, n;
  int i;

  if (!f) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  f->file = f->str = f->case_time = -1;
  for (i = 0; i < OUT_NFIELD; i++)
    f->ds[i] = -1;
  f->ncase = s->ncase;
  f->nt = nt;
  f->neffect = b->neffect;
  f->layout.ncase = s->ncase;
  f->layout.nt = nt;
  f->layout.tc = b->cases < s->ncase ? b->cases : s->ncase;
  f->layout.q = chunk_points < nt ? chunk_points : nt;
  f->layout.neffect = b->neffect;
  f->layout.gzip = meta->gzip;
  f->layout.fields = meta->fields;
  f->layout.case_time = !grid_common;

  f->str = H5Tcopy(H5T_C_S1);
  if (f->str < 0 || H5Tset_size(f->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(f->str, H5T_CSET_UTF8) < 0) {
    fail(err, errsz, "cannot make the string type");
    goto fail;
  }
  f->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f->file < 0) {
    fail(err, errsz, "cannot create %s", path);
    goto fail;
  }
  if (root_attrs(f->file, f->str, meta) < 0) {
    fail(err, errsz, "cannot write the root attributes");
    goto fail;
  }

  /* the scene file, verbatim */
  {
    hid_t ds = out_h5_dataset(f->file, f->str, "scene", f->str, 0, NULL,
                              NULL, 0, NULL, "1",
                              "the scene file (YAML), verbatim");
    const char *text = s->text;
    if (ds < 0 || out_cf_long_name(ds, f->str, "scene file") < 0 ||
        write_all(ds, f->str, &text) < 0) {
      if (ds >= 0)
        H5Dclose(ds);
      fail(err, errsz, "cannot write the scene text");
      goto fail;
    }
    H5Dclose(ds);
  }

  /* dimension scales */
  dcase = out_h5_scale(f->file, f->str, "case", H5T_NATIVE_INT64, s->ncase,
                       NULL, "1",
                       "case number; row-major over the sweep keys in file "
                       "order, the last key fastest");
  if (dcase >= 0) {
    int64_t *idx = malloc(AXIS_RUN * sizeof *idx);
    for (c0 = 0; idx && c0 < s->ncase; c0 += n) {
      n = s->ncase - c0 < AXIS_RUN ? s->ncase - c0 : AXIS_RUN;
      for (k = 0; k < n; k++)
        idx[k] = (int64_t)(c0 + k);
      if (out_h5_rows(dcase, H5T_NATIVE_INT64, c0, n, idx) < 0)
        break;
    }
    if (!idx || c0 < s->ncase) {
      H5Dclose(dcase);
      dcase = -1;
    }
    free(idx);
  }
  /* the time scale in runs of AXIS_RUN samples: memory does not grow
     with the length of a case */
  dtime = grid_common
              ? out_h5_scale(f->file, f->str, "time", H5T_NATIVE_DOUBLE, nt,
                             NULL, "s",
                             "time since the start of the trajectory")
              : out_h5_scale(f->file, f->str, "time", H5T_NATIVE_INT32, nt,
                             NULL, "1",
                             "sample index: the time grid differs between "
                             "cases, the time of each sample is case_time");
  if (dtime >= 0) {
    double *t = malloc(AXIS_RUN * sizeof *t);
    int32_t *ix = (int32_t *)t;
    for (c0 = 0; t && c0 < nt; c0 += n) {
      n = nt - c0 < AXIS_RUN ? nt - c0 : AXIS_RUN;
      for (k = 0; k < n; k++) {
        if (grid_common)
          t[k] = scene_case_time(first, c0 + k);
        else
          ix[k] = (int32_t)(c0 + k);
      }
      if (out_h5_rows(dtime,
                     grid_common ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT32, c0,
                     n, t) < 0)
        break;
    }
    if (!t || c0 < nt) {
      H5Dclose(dtime);
      dtime = -1;
    }
    free(t);
  }
  dlink = out_h5_scale(f->file, f->str, "link", H5T_NATIVE_INT32, 3, one23, "1",
                "link (leg) number i; link i is pinned at angle "
                "2 pi (i - 1) / 3 from X");
  dcon = out_h5_scale(f->file, f->str, "constraint", H5T_NATIVE_INT32, 3, one23,
               "1", "constraint k of eqs. (8), (9), (10): ball joints 1-2, "
                    "2-3, 3-1");
  for (i = 0; i < b->neffect; i++)
    names[i] = rps3_effect_name(b->effect[i]);
  deff = out_h5_scale(f->file, f->str, "effect", f->str, (size_t)b->neffect,
                      names, "1",
                      "physical effect, as named by rps3_effect_name");
  if (dcase < 0 || dtime < 0 || dlink < 0 || dcon < 0 || deff < 0 ||
      out_cf_long_name(dcase, f->str, "case number") < 0 ||
      out_cf_long_name(dtime, f->str,
                       grid_common ? "time" : "sample index") < 0 ||
      out_cf_long_name(dlink, f->str, "link number") < 0 ||
      out_cf_long_name(dcon, f->str, "constraint number") < 0 ||
      out_cf_long_name(deff, f->str, "physical effect") < 0) {
    fail(err, errsz, "cannot write the dimension scales");
    goto fail;
  }

  /* the swept keys, [case] */
  coords = out_h5_coordinates(s, grid_common);
  axis_ds = calloc(s->naxis + 1, sizeof *axis_ds);
  if (!coords || !axis_ds) {
    snprintf(err, errsz, "out of memory");
    goto fail;
  }
  for (a = 0; a < s->naxis; a++) {
    const scene_key_info *ki = scene_key_get(s->axis[a].key);
    char doc[400], units[32], long_name[128];
    hsize_t nc = s->ncase;
    hid_t type = (ki->type == KEY_REAL || ki->type == KEY_REAL3)
                     ? H5T_NATIVE_DOUBLE
                 : ki->type == KEY_ENUM ? f->str
                                        : H5T_NATIVE_INT32;
    snprintf(doc, sizeof doc, "swept scene key %s: %s (paper: %s)",
             s->axis[a].path, ki->doc, ki->symbol);
    snprintf(long_name, sizeof long_name, "swept key %s", s->axis[a].path);
    axis_ds[a] = out_h5_dataset(f->file, f->str, s->axis[a].path, type, 1,
                                &nc, NULL, 0, NULL,
                                out_cf_axis_units(s, a, units, sizeof units),
                                doc);
    if (axis_ds[a] < 0 || out_cf_long_name(axis_ds[a], f->str, long_name) < 0 ||
        H5DSattach_scale(axis_ds[a], dcase, 0) < 0 ||
        out_h5_axis(axis_ds[a], f->str, s, a) < 0) {
      fail(err, errsz, "cannot write the swept key %s", s->axis[a].path);
      goto fail;
    }
  }

  /* the fields of the schema that are asked for (--fields) */
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    hid_t type = field_type(f, fi);
    hid_t axes[4];
    int rank = 0, r;
    if (!(meta->fields >> i & 1))
      continue;
    dims[rank] = s->ncase;
    chunk[rank] = b->cases < s->ncase ? b->cases : s->ncase;
    axes[rank++] = dcase;
    if (fi->shape != OUT_C) {
      dims[rank] = nt;
      chunk[rank] = chunk_points < nt ? chunk_points : nt;
      axes[rank++] = dtime;
    }
    if (fi->shape == OUT_CTEL) {
      dims[rank] = chunk[rank] = (hsize_t)b->neffect;
      axes[rank++] = deff;
    }
    if (fi->shape == OUT_CTL || fi->shape == OUT_CTEL) {
      dims[rank] = chunk[rank] = 3;
      axes[rank++] = dlink;
    }
    if (fi->shape == OUT_CTK) {
      dims[rank] = chunk[rank] = 3;
      axes[rank++] = dcon;
    }
    f->ds[i] = out_h5_dataset(f->file, f->str, fi->name, type, rank, dims,
                              chunk, meta->gzip,
                              fi->type == OUT_F64   ? (const void *)&fnan
                              : i == OUT_status     ? (const void *)&fnotrun
                              : fi->type == OUT_I32 ? (const void *)&fneg
                                                    : NULL,
                              fi->units, fi->doc);
    if (f->ds[i] < 0 || out_cf_field(f->ds[i], f->str, i) < 0 ||
        (coords[0] &&
         out_h5_attr(f->ds[i], f->str, "coordinates", coords) < 0)) {
      fail(err, errsz, "cannot create dataset %s", fi->name);
      goto fail;
    }
    for (r = 0; r < rank; r++)
      if (H5DSattach_scale(f->ds[i], axes[r], (unsigned)r) < 0) {
        fail(err, errsz, "cannot attach the dimension scales of %s",
             fi->name);
        goto fail;
      }
  }
  if (!grid_common) {
    dims[0] = s->ncase;
    dims[1] = nt;
    chunk[0] = b->cases < s->ncase ? b->cases : s->ncase;
    chunk[1] = chunk_points < nt ? chunk_points : nt;
    f->case_time = out_h5_dataset(
        f->file, f->str, "case_time", H5T_NATIVE_DOUBLE, 2, dims, chunk,
        meta->gzip, &fnan, "s",
        "time of each sample of each case (the time grid differs between "
        "cases); NaN past a case's last sample");
    if (f->case_time < 0 ||
        out_cf_long_name(f->case_time, f->str, "time of the sample") < 0 ||
        H5DSattach_scale(f->case_time, dcase, 0) < 0 ||
        H5DSattach_scale(f->case_time, dtime, 1) < 0) {
      fail(err, errsz, "cannot create dataset case_time");
      goto fail;
    }
  }
  for (a = 0; a < s->naxis; a++)
    H5Dclose(axis_ds[a]);
  free(axis_ds);
  free(coords);
  H5Dclose(dcase);
  H5Dclose(dtime);
  H5Dclose(dlink);
  H5Dclose(dcon);
  H5Dclose(deff);
  return f;

fail:
  if (axis_ds)
    for (a = 0; a < s->naxis; a++)
      if (axis_ds[a] > 0)
        H5Dclose(axis_ds[a]);
  free(axis_ds);
  free(coords);
  if (dcase >= 0)
    H5Dclose(dcase);
  if (dtime >= 0)
    H5Dclose(dtime);
  if (dlink >= 0)
    H5Dclose(dlink);
  if (dcon >= 0)
    H5Dclose(dcon);
  if (deff >= 0)
    H5Dclose(deff);
  out_close(f, NULL, 0);
  return NULL;
}

/* write slots [0, nc) x samples [0, nk) of a [cases, points, cols] buffer
   to rows [c0, c0 + nc) x [k0, k0 + nk) of a dataset of rank `rank` */
static int write_tile(hid_t ds, hid_t type, int rank, const out_block *b,
                      const void *buf, size_t c0, size_t nc, size_t k0,
                      size_t nk)
{
  hsize_t mdims[4], start[4] = {0, 0, 0, 0}, count[4], fstart[4] = {0};
  hid_t fs = H5Dget_space(ds), ms;
  int r, rc = -1;
  mdims[0] = b->cases;
  count[0] = nc;
  fstart[0] = c0;
  if (rank >= 2) {
    mdims[1] = b->points;
    count[1] = nk;
    fstart[1] = k0;
  }
  /* the trailing axes (effect, link) are whole: flatten them into one */
  if (rank >= 3) {
    hsize_t fdims[4];
    H5Sget_simple_extent_dims(fs, fdims, NULL);
    for (r = 2; r < rank; r++) {
      mdims[r] = fdims[r];
      count[r] = fdims[r];
      fstart[r] = 0;
    }
  }
  ms = H5Screate_simple(rank, mdims, NULL);
  if (fs >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(ms, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, fstart, NULL, count, NULL) >=
          0 &&
      H5Dwrite(ds, type, ms, fs, H5P_DEFAULT, buf) >= 0)
    rc = 0;
  if (fs >= 0)
    H5Sclose(fs);
  if (ms >= 0)
    H5Sclose(ms);
  return rc;
}

void out_file_layout(const out_file *f, out_layout *L)
{
  *L = f->layout;
}

/* write the chunks out_pack made, as they are */
static int write_packed(out_file *f, const out_block *b, char *err,
                        size_t errsz)
{
  size_t i;
  for (i = 0; i < b->npk; i++) {
    const out_chunk *ck = &b->pk[i];
    hid_t ds = ck->field < OUT_NFIELD ? f->ds[ck->field] : f->case_time;
    hsize_t off[4] = {0, 0, 0, 0};
    off[0] = ck->c0;
    off[1] = ck->k0;
    if (H5Dwrite_chunk(ds, H5P_DEFAULT, 0, off, ck->size,
                       b->pk_buf + ck->off) < 0) {
      fail(err, errsz, "cannot write %s of cases %zu-",
           ck->field < OUT_NFIELD ? out_field_table[ck->field].name
                                  : "case_time",
           ck->c0);
      return -1;
    }
  }
  return 0;
}

int out_write(out_file *f, const out_block *b, size_t c0, size_t nc,
              size_t k0, size_t nk, int with_case, char *err, size_t errsz)
{
  int i;
  if (b->packed && write_packed(f, b, err, errsz))
    return -1;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    hid_t type = field_type(f, fi);
    int rank = fi->shape == OUT_C      ? 1
               : fi->shape == OUT_CT   ? 2
               : fi->shape == OUT_CTEL ? 4
                                       : 3;
    if ((fi->shape == OUT_C && !with_case) || f->ds[i] < 0 ||
        (fi->shape != OUT_C && b->packed))
      continue;
    if (write_tile(f->ds[i], type, rank, b, out_block_field(b, i), c0, nc, k0,
                   nk) < 0) {
      fail(err, errsz, "cannot write %s of cases %zu-%zu", fi->name, c0,
           c0 + nc - 1);
      return -1;
    }
  }
  if (f->case_time >= 0 && !b->packed &&
      write_tile(f->case_time, H5T_NATIVE_DOUBLE, 2, b, b->t, c0, nc, k0, nk) <
          0) {
    fail(err, errsz, "cannot write case_time of cases %zu-%zu", c0,
         c0 + nc - 1);
    return -1;
  }
  return 0;
}

int out_close(out_file *f, char *err, size_t errsz)
{
  int i, rc = 0;
  if (!f)
    return 0;
  for (i = 0; i < OUT_NFIELD; i++)
    if (f->ds[i] >= 0 && H5Dclose(f->ds[i]) < 0)
      rc = -1;
  if (f->case_time >= 0 && H5Dclose(f->case_time) < 0)
    rc = -1;
  if (f->str >= 0)
    H5Tclose(f->str);
  if (f->file >= 0 && H5Fclose(f->file) < 0)
    rc = -1;
  if (rc < 0 && err)
    fail(err, errsz, "cannot close the file");
  free(f);
  return rc;
}
