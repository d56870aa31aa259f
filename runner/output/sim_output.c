/*
 * sim_output.c - see sim_output.h: the datasets of SIM_OUTPUT_FIELDS with
 * the runner's conventions (output.h), written a window of one case at a
 * time.
 */
#include "sim_output.h"
#include "out_cf.h"
#include "output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <yaml.h>

/* the schema */
#define fields out_field_table

/* 1 when field i is the simulation's */
static int sim_field(int i) { return (fields[i].files & OUT_SIM) != 0; }

/* case numbers are written in runs of this many cases */
#define RUN 4096

/* cases per chunk of the per-case datasets: each case's values are
   written alone (the cases end in any order), and HDF5 rewrites (and
   checksums) the whole chunk, with no chunk cache (output.h): small */
#define CASE_CHUNK 64

static size_t columns(out_shape shape) { return shape == OUT_CTL ? 3 : 1; }

int sim_window_alloc(sim_window *w, size_t points) {
  int i;
  memset(w, 0, sizeof *w);
  w->points = points;
  for (i = 0; i < OUT_NFIELD; i++) {
    if (fields[i].shape == OUT_C || !sim_field(i)) continue;
    w->buf[i] = malloc(points * columns(fields[i].shape) * sizeof(double));
    if (!w->buf[i]) {
      sim_window_free(w);
      return -1;
    }
  }
  return 0;
}

void sim_window_free(sim_window *w) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++) free(w->buf[i]);
  memset(w, 0, sizeof *w);
}

struct sim_file {
  hid_t file;
  hid_t ds[OUT_NFIELD];
  hid_t case_time; /* [case, time] when the grid differs, else -1 */
  hid_t str;       /* variable-length UTF-8 string */
};

static hid_t mem_type(const sim_file *f, out_type t) {
  return t == OUT_F64   ? H5T_NATIVE_DOUBLE
         : t == OUT_I32 ? H5T_NATIVE_INT32
         : t == OUT_I64 ? H5T_NATIVE_INT64
                        : f->str;
}

static int attr_str(const sim_file *f, hid_t obj, const char *name,
                    const char *v) {
  return out_h5_attr(obj, f->str, name, v);
}

/* a dataset with units, long_name and description (output.h's
   out_h5_dataset and the CF long_name) */
static hid_t dataset(const sim_file *f, const char *name, hid_t type, int rank,
                     const hsize_t *dims, const hsize_t *chunk, int gzip,
                     const void *fill, const char *units, const char *long_name,
                     const char *doc) {
  hid_t ds = out_h5_dataset(f->file, f->str, name, type, rank, dims, chunk,
                            gzip, fill, units, doc);
  if (ds >= 0 && out_cf_long_name(ds, f->str, long_name) < 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

/* a dimension scale (out_h5_scale) with its CF long_name */
static hid_t scale(const sim_file *f, const char *name, hid_t type, size_t n,
                   const void *data, const char *units, const char *long_name,
                   const char *doc) {
  hid_t ds = out_h5_scale(f->file, f->str, name, type, n, data, units, doc);
  if (ds >= 0 && out_cf_long_name(ds, f->str, long_name) < 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

/* a hyperslab write: start/count of rank dims from a contiguous buffer */
static int write_slab(hid_t ds, hid_t type, int rank, const hsize_t *start,
                      const hsize_t *count, const void *buf) {
  hid_t fs = H5Dget_space(ds), ms = H5Screate_simple(rank, count, NULL);
  int rc = -1;
  if (fs >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
      H5Dwrite(ds, type, ms, fs, H5P_DEFAULT, buf) >= 0)
    rc = 0;
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

/* the case numbers 0 .. ncase - 1 of the case scale */
static int case_numbers(hid_t ds, size_t ncase) {
  int64_t *idx = malloc(RUN * sizeof *idx);
  size_t c0, n = 0, k;
  int rc = idx ? 0 : -1;
  for (c0 = 0; rc == 0 && c0 < ncase; c0 += n) {
    n = ncase - c0 < RUN ? ncase - c0 : RUN;
    for (k = 0; k < n; k++) idx[k] = (int64_t)(c0 + k);
    rc = out_h5_rows(ds, H5T_NATIVE_INT64, c0, n, idx);
  }
  free(idx);
  return rc;
}

static int root_attrs(const sim_file *f, const char *command_line) {
  char h5v[32];
  unsigned maj, min, rel;
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (attr_str(f, f->file, "rps3_version", rps3_version()) < 0 ||
          out_stamp(f->file, command_line) < 0 ||
          out_cf_conventions(f->file, f->str) < 0 ||
          attr_str(f, f->file, "gsl_version", gsl_version) < 0 ||
          attr_str(f, f->file, "hdf5_version", h5v) < 0 ||
          attr_str(f, f->file, "yaml_version", yaml_get_version_string()) < 0 ||
          attr_str(f, f->file, "content", "simulation") < 0 ||
          attr_str(f, f->file, "title",
                   "rps3: closed-loop simulation of the Lee & Shah 3-RPS "
                   "manipulator along a trajectory, per case of a sweep") < 0)
             ? -1
             : 0;
}

/* the dimension scales, the scene and the swept keys; the scales' ids
   into sc[0..2] (case, time, link) */
static int create_axes(sim_file *f, const scene *s, size_t nt,
                       const double *times, hid_t sc[3], char *err,
                       size_t errsz) {
  static const int32_t one23[3] = {1, 2, 3};
  const char *text = s->text;
  hid_t ds;
  size_t a, k;
  ds = dataset(f, "scene", f->str, 0, NULL, NULL, 0, NULL, "1", "scene file",
               "the scene file (YAML), verbatim");
  if (ds < 0 ||
      H5Dwrite(ds, f->str, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) < 0) {
    if (ds >= 0) H5Dclose(ds);
    out_fail(err, errsz, "cannot write the scene text");
    return -1;
  }
  H5Dclose(ds);
  sc[0] = scale(f, "case", H5T_NATIVE_INT64, s->ncase, NULL, "1", "case number",
                "case number; row-major over the sweep keys in file order, "
                "the last key fastest");
  if (sc[0] >= 0 && case_numbers(sc[0], s->ncase) < 0) {
    H5Dclose(sc[0]);
    sc[0] = -1;
  }
  if (times) {
    sc[1] = scale(f, OUT_CF_SAMPLE_DIM(1), H5T_NATIVE_DOUBLE, nt, times,
                  OUT_CF_TIME_UNITS, "time",
                  "simulated time since the start of the trajectory, in s "
                  "(the reference date of the units is nominal)");
    if (sc[1] >= 0 && out_cf_time(sc[1], f->str) < 0) {
      H5Dclose(sc[1]);
      sc[1] = -1;
    }
  } else {
    int32_t *ix = malloc(nt * sizeof *ix);
    for (k = 0; ix && k < nt; k++) ix[k] = (int32_t)k;
    sc[1] = ix ? scale(f, OUT_CF_SAMPLE_DIM(0), H5T_NATIVE_INT32, nt, ix, "1",
                       "sample index",
                       "sample index: the time grid differs between cases, "
                       "the time of each sample is case_time")
               : -1;
    free(ix);
  }
  sc[2] = scale(f, "link", H5T_NATIVE_INT32, 3, one23, "1", "link number",
                "link (leg) number i; link i is pinned at angle "
                "2 pi (i - 1) / 3 from X");
  if (sc[0] < 0 || sc[1] < 0 || sc[2] < 0) {
    out_fail(err, errsz, "cannot write the dimension scales");
    return -1;
  }
  for (a = 0; a < s->naxis; a++) {
    const scene_key_info *ki = scene_key_get(s->axis[a].key);
    char doc[400], units[32], name[160];
    hsize_t nc = s->ncase;
    hid_t type = (ki->type == KEY_REAL || ki->type == KEY_REAL3)
                     ? H5T_NATIVE_DOUBLE
                 : ki->type == KEY_ENUM ? f->str
                                        : H5T_NATIVE_INT32;
    snprintf(doc, sizeof doc, "swept scene key %s: %s (paper: %s)",
             s->axis[a].path, ki->doc, ki->symbol);
    /* the variable has the key's CF name, the key in scene_key */
    ds = out_h5_dataset(f->file, f->str,
                        out_cf_key_name(s->axis[a].path, name, sizeof name),
                        type, 1, &nc, NULL, 0, NULL,
                        out_cf_axis_units(s, a, units, sizeof units), doc);
    if (ds < 0 || out_cf_swept_key(ds, f->str, s->axis[a].path) < 0 ||
        H5DSattach_scale(ds, sc[0], 0) < 0 ||
        out_h5_axis(ds, f->str, s, a) < 0) {
      if (ds >= 0) H5Dclose(ds);
      out_fail(err, errsz, "cannot write the swept key %s", s->axis[a].path);
      return -1;
    }
    H5Dclose(ds);
  }
  return 0;
}

/*
 * The per-case datasets are written a case at a time, in whatever order
 * the cases end: reopened with a chunk cache (CASE_CACHE bytes each), so
 * that a chunk is read, checksummed and written once per flush rather
 * than at every case (the runner's datasets have none: output.h).  A
 * sweep of 3000 cases of 11 samples: 8.9 s without, 4.9 s with.
 */
#define CASE_CACHE (1 << 20)

static int reopen_cached(sim_file *f, int i) {
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  int rc = -1;
  if (dapl >= 0 && H5Pset_chunk_cache(dapl, 521, CASE_CACHE, 1.0) >= 0 &&
      H5Dclose(f->ds[i]) >= 0) {
    f->ds[i] = H5Dopen2(f->file, fields[i].name, dapl);
    rc = f->ds[i] < 0 ? -1 : 0;
  }
  if (dapl >= 0) H5Pclose(dapl);
  return rc;
}

sim_file *sim_file_create(const char *path, const scene *s, size_t nt,
                          const double *times, size_t points, int gzip,
                          const char *command_line, char *err, size_t errsz) {
  const double fnan = (double)NAN;
  const int32_t fneg = -1, fnotrun = OUT_STATUS_NOT_COMPUTED;
  const int64_t fneg64 = -1;
  sim_file *f = calloc(1, sizeof *f);
  hid_t sc[3] = {-1, -1, -1};
  hsize_t dims[3], chunk[3];
  char *coords[2] = {NULL, NULL};
  int i, r;
  if (!f) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  f->case_time = -1;
  for (i = 0; i < OUT_NFIELD; i++) f->ds[i] = -1;
  f->str = H5Tcopy(H5T_C_S1);
  if (f->str < 0 || H5Tset_size(f->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(f->str, H5T_CSET_UTF8) < 0) {
    out_fail(err, errsz, "cannot make the string type");
    goto fail;
  }
  f->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f->file < 0) {
    out_fail(err, errsz, "cannot create %s", path);
    goto fail;
  }
  if (root_attrs(f, command_line) < 0) {
    out_fail(err, errsz, "cannot write the root attributes");
    goto fail;
  }
  if (create_axes(f, s, nt, times, sc, err, errsz) < 0) goto fail;
  /* the per-case variables' coordinates are the swept keys; the
     per-sample ones' also case_time when the grid differs (times NULL) */
  coords[0] = out_h5_coordinates(s, 0);
  coords[1] = out_h5_coordinates(s, times == NULL);
  if (!coords[0] || !coords[1]) {
    snprintf(err, errsz, "out of memory");
    goto fail;
  }
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &fields[i];
    int rank = fi->shape == OUT_C ? 1 : fi->shape == OUT_CT ? 2 : 3;
    if (!sim_field(i)) continue;
    dims[0] = s->ncase;
    chunk[0] = fi->shape == OUT_C
                   ? (s->ncase < CASE_CHUNK ? s->ncase : CASE_CHUNK)
                   : 1;
    dims[1] = nt;
    chunk[1] = points;
    dims[2] = chunk[2] = 3;
    f->ds[i] =
        dataset(f, fi->name, mem_type(f, fi->type), rank, dims, chunk, gzip,
                fi->type == OUT_F64   ? (const void *)&fnan
                : i == OUT_sim_status ? (const void *)&fnotrun
                : fi->type == OUT_I32 ? (const void *)&fneg
                : fi->type == OUT_I64 ? (const void *)&fneg64
                                      : NULL,
                fi->units, fi->long_name, fi->doc);
    if (f->ds[i] < 0 ||
        (i == OUT_sim_status && out_cf_status(f->ds[i], f->str) < 0) ||
        (coords[fi->shape != OUT_C][0] &&
         attr_str(f, f->ds[i], "coordinates", coords[fi->shape != OUT_C]) <
             0)) {
      out_fail(err, errsz, "cannot create dataset %s", fi->name);
      goto fail;
    }
    for (r = 0; r < rank; r++)
      if (H5DSattach_scale(f->ds[i], sc[r], (unsigned)r) < 0) {
        out_fail(err, errsz, "cannot attach the dimension scales of %s",
                 fi->name);
        goto fail;
      }
    if (fi->shape == OUT_C && reopen_cached(f, i) < 0) {
      out_fail(err, errsz, "cannot open dataset %s", fi->name);
      goto fail;
    }
  }
  if (!times) {
    dims[0] = s->ncase;
    chunk[0] = 1;
    f->case_time = dataset(f, "case_time", H5T_NATIVE_DOUBLE, 2, dims, chunk,
                           gzip, &fnan, "s", "time of the sample",
                           "time of each sample of each case (the time grid "
                           "differs between cases); NaN past a case's last "
                           "sample");
    if (f->case_time < 0 || H5DSattach_scale(f->case_time, sc[0], 0) < 0 ||
        H5DSattach_scale(f->case_time, sc[1], 1) < 0) {
      out_fail(err, errsz, "cannot create dataset case_time");
      goto fail;
    }
  }
  for (r = 0; r < 3; r++) H5Dclose(sc[r]);
  free(coords[0]);
  free(coords[1]);
  return f;
fail:
  free(coords[0]);
  free(coords[1]);
  for (r = 0; r < 3; r++)
    if (sc[r] >= 0) H5Dclose(sc[r]);
  sim_file_close(f, NULL, 0);
  return NULL;
}

int sim_file_window(sim_file *f, const sim_window *w, size_t c, size_t k0,
                    size_t nk, const double *times, char *err, size_t errsz) {
  hsize_t start[3] = {0, 0, 0}, count[3] = {1, 0, 3};
  int i;
  start[0] = c;
  start[1] = k0;
  count[1] = nk;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &fields[i];
    if (fi->shape == OUT_C || !sim_field(i)) continue;
    if (write_slab(f->ds[i], H5T_NATIVE_DOUBLE, fi->shape == OUT_CT ? 2 : 3,
                   start, count, w->buf[i]) < 0) {
      out_fail(err, errsz, "cannot write %s of case %zu", fi->name, c);
      return -1;
    }
  }
  if (f->case_time >= 0 && times &&
      write_slab(f->case_time, H5T_NATIVE_DOUBLE, 2, start, count, times) < 0) {
    out_fail(err, errsz, "cannot write case_time of case %zu", c);
    return -1;
  }
  return 0;
}

int sim_file_case(sim_file *f, const sim_case_values *v, size_t c, char *err,
                  size_t errsz) {
  hsize_t start = c, count = 1;
  const char *msg = v->message;
  const void *src[OUT_NFIELD];
  int i;
  memset(src, 0, sizeof src);
  src[OUT_tracking_error_max] = &v->tracking_error_max;
  src[OUT_failed_time] = &v->failed_time;
  src[OUT_sim_status] = &v->status;
  src[OUT_sim_failed_at] = &v->failed_at;
  src[OUT_nsteps] = &v->nsteps;
  src[OUT_nevals] = &v->nevals;
  src[OUT_nticks] = &v->nticks;
  src[OUT_nsat] = &v->nsat;
  src[OUT_message] = &msg;
  src[OUT_scene_resolved] = &v->scene_resolved;
  for (i = 0; i < OUT_NFIELD; i++) {
    if (fields[i].shape != OUT_C || !sim_field(i)) continue;
    if (!src[i] || write_slab(f->ds[i], mem_type(f, fields[i].type), 1, &start,
                              &count, src[i]) < 0) {
      out_fail(err, errsz, "cannot write %s of case %zu", fields[i].name, c);
      return -1;
    }
  }
  return 0;
}

int sim_file_close(sim_file *f, char *err, size_t errsz) {
  int i, rc = 0;
  if (!f) return 0;
  for (i = 0; i < OUT_NFIELD; i++)
    if (f->ds[i] >= 0 && H5Dclose(f->ds[i]) < 0) rc = -1;
  if (f->case_time >= 0 && H5Dclose(f->case_time) < 0) rc = -1;
  if (f->str >= 0) H5Tclose(f->str);
  if (f->file > 0 && H5Fclose(f->file) < 0) rc = -1;
  if (rc < 0 && err) out_fail(err, errsz, "cannot close the file");
  free(f);
  return rc;
}

double sim_file_bytes(size_t ncase, size_t npoint) {
  double per_point = 0, per_case = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (!sim_field(i))
      continue;
    else if (fields[i].shape == OUT_C)
      per_case += fields[i].type == OUT_STR ? 512.0 : 8.0;
    else
      per_point += 8.0 * (double)columns(fields[i].shape);
  /* the scene, the scales and HDF5's metadata: a bound */
  return per_point * (double)npoint + per_case * (double)ncase + 65536.0;
}
