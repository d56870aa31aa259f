/*
 * output.c - write a sweep as a self-describing HDF5 file (netCDF-4 style:
 * dimension scales on every axis, units and description on every dataset),
 * readable by h5py and by xarray through h5netcdf.
 */
#include "output.h"
#include "core/h5err.h"
#include "out_cf.h"
#include "scene/inputs.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <yaml.h>

/* ------------------------------------------------------------ HDF5 bits */

/* bytes of HDF5's type conversion buffer per write */
#define OUT_TCONV_BUF 65536

struct out_file {
  int files; /* OUT_INV or OUT_SIM: the rows of the schema it holds */
  hid_t file;
  hid_t ds[OUT_NFIELD];
  hid_t case_time; /* [case, time] when the grid differs, else -1 */
  hid_t str;       /* variable-length UTF-8 string type */
  hid_t dxpl;      /* the tiles' transfer properties */
  size_t ncase;
  size_t nt;
  int neffect;
  out_layout layout; /* for out_pack */
};

/* the HDF5 memory/file type of a schema field */
static hid_t field_type(const out_file *f, const out_field_info *fi) {
  return fi->type == OUT_F64   ? H5T_NATIVE_DOUBLE
         : fi->type == OUT_I32 ? H5T_NATIVE_INT32
         : fi->type == OUT_I64 ? H5T_NATIVE_INT64
                               : f->str;
}

/* the rank of a schema field's dataset */
static int field_rank(const out_field_info *fi) {
  return fi->shape == OUT_C      ? 1
         : fi->shape == OUT_CT   ? 2
         : fi->shape == OUT_CTEL ? 4
                                 : 3;
}

/* the root attributes of an inverse sweep's file: its fields, its input
   files, the shard */
static int root_attrs_inv(hid_t file, hid_t str, const out_meta *meta) {
  char fields[1024];
  const char *const kv[][2] = {
      {"fields", out_fields_text(meta->fields, fields, sizeof fields)},
      {INPUTS_ATTR, meta->inputs ? meta->inputs : ""},
      {"shard", meta->shard}};
  return out_h5_attrs(file, str, kv, 3);
}

/* the root attributes: versions, time of creation, command line, CF's,
   title and content, and those of an inverse sweep */
static int root_attrs(const out_file *f, const out_spec *sp,
                      const out_meta *meta) {
  char now[32], h5v[32];
  unsigned maj, min, rel;
  hid_t file = f->file, str = f->str;
  const char *const kv[][2] = {{"rps3_version", rps3_version()},
                               {"created_utc", now},
                               {"command_line", meta->command_line},
                               {"gsl_version", gsl_version},
                               {"hdf5_version", h5v},
                               {"yaml_version", yaml_get_version_string()}};
  const char *const kv2[][2] = {{"title", sp->title}, {"content", sp->content}};
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (out_h5_attrs(file, str, kv, 6) < 0 ||
          out_cf_root(file, str, now, meta->command_line) < 0 ||
          out_h5_attrs(file, str, kv2, 2) < 0 ||
          (f->files == OUT_INV && root_attrs_inv(file, str, meta) < 0))
             ? -1
             : 0;
}

/* the file's dimension scales */
typedef struct {
  hid_t dcase, dtime, dlink, dcon, deff;
} scales;

static void scales_close(scales *sc) {
  hid_t h[5];
  int i;
  h[0] = sc->dcase;
  h[1] = sc->dtime;
  h[2] = sc->dlink;
  h[3] = sc->dcon;
  h[4] = sc->deff;
  for (i = 0; i < 5; i++)
    if (h[i] >= 0) H5Dclose(h[i]);
}

/* the scene file, verbatim */
static int write_scene_text(out_file *f, const scene *s, char *err,
                            size_t errsz) {
  hid_t ds = out_h5_dataset(f->file, f->str, "scene", f->str, 0, NULL, NULL, 0,
                            NULL, "1", "the scene file (YAML), verbatim");
  const char *text = s->text;
  int rc = 0;
  if (ds < 0 || out_cf_long_name(ds, f->str, "scene file") < 0 ||
      out_h5_write_all(ds, f->str, &text) < 0) {
    out_fail(err, errsz, "cannot write the scene text");
    rc = -1;
  }
  if (ds >= 0) H5Dclose(ds);
  return rc;
}

/* values 0 .. n - 1 of a 1-D scale, val(ctx, k), in runs of OUT_AXIS_RUN
   so that memory does not grow with n (the case numbers and sample
   indices, whole numbers below 2^53, convert exactly to the scale's
   integers); 0 or -1 */
static int scale_fill(hid_t ds, size_t n, double (*val)(const void *, size_t),
                      const void *ctx) {
  double *v = malloc(OUT_AXIS_RUN * sizeof *v);
  size_t c0, m, k;
  int rc = v ? 0 : -1;
  for (c0 = 0; rc == 0 && c0 < n; c0 += m) {
    m = n - c0 < OUT_AXIS_RUN ? n - c0 : OUT_AXIS_RUN;
    for (k = 0; k < m; k++) v[k] = val(ctx, c0 + k);
    rc = out_h5_rows(ds, H5T_NATIVE_DOUBLE, c0, m, v);
  }
  free(v);
  return rc;
}

/* the k-th case number or sample index */
static double index_of(const void *ctx, size_t k) {
  (void)ctx;
  return (double)k;
}

/* the case scale 0, 1, ...: -1 on failure */
static hid_t case_scale(out_file *f, size_t ncase) {
  hid_t ds =
      out_h5_scale(f->file, f->str, "case", H5T_NATIVE_INT64, ncase, NULL, "1",
                   "case number; row-major over the sweep keys in "
                   "file order, the last key fastest");
  if (ds >= 0 && scale_fill(ds, ncase, index_of, NULL) < 0) {
    H5Dclose(ds);
    ds = -1;
  }
  return ds;
}

/* the time scale: the times of the shared grid, or the sample index when
   the grid differs between cases: -1 on failure */
static hid_t time_scale(out_file *f, const out_spec *sp) {
  hid_t ds = sp->grid_common
                 ? out_h5_scale(f->file, f->str, OUT_CF_SAMPLE_DIM(1),
                                H5T_NATIVE_DOUBLE, sp->nt, NULL,
                                OUT_CF_TIME_UNITS, sp->time_doc)
                 : out_h5_scale(f->file, f->str, OUT_CF_SAMPLE_DIM(0),
                                H5T_NATIVE_INT32, sp->nt, NULL, "1",
                                "sample index: the time grid differs between "
                                "cases, the time of each sample is "
                                "case_time");
  if (ds >= 0 && ((sp->grid_common && out_cf_time(ds, f->str) < 0) ||
                  scale_fill(ds, sp->nt, sp->grid_common ? sp->time : index_of,
                             sp->time_ctx) < 0)) {
    H5Dclose(ds);
    ds = -1;
  }
  return ds;
}

/* 1 when a field of the files `files` has shape sh */
static int has_shape(int files, out_shape sh) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if ((out_field_table[i].files & files) && out_field_table[i].shape == sh)
      return 1;
  return 0;
}

/* the scale constraint, when a field of the file is per constraint */
static int make_constraint(out_file *f, const out_spec *sp, scales *sc) {
  static const int32_t one23[3] = {1, 2, 3};
  if (!has_shape(sp->files, OUT_CTK)) return 0;
  sc->dcon = out_h5_scale(f->file, f->str, "constraint", H5T_NATIVE_INT32, 3,
                          one23, "1",
                          "constraint k of eqs. (8), (9), (10): ball joints "
                          "1-2, 2-3, 3-1");
  return sc->dcon < 0 ? -1
                      : out_cf_long_name(sc->dcon, f->str, "constraint number");
}

/* the scale effect, when a field of the file is per effect */
static int make_effect(out_file *f, const out_spec *sp, scales *sc) {
  const char *names[RPS3_NEFFECT];
  int i;
  if (!has_shape(sp->files, OUT_CTEL)) return 0;
  for (i = 0; i < sp->neffect; i++) names[i] = rps3_effect_name(sp->effect[i]);
  sc->deff =
      out_h5_scale(f->file, f->str, "effect", f->str, (size_t)sp->neffect,
                   names, "1", "physical effect, as named by rps3_effect_name");
  return sc->deff < 0 ? -1
                      : out_cf_long_name(sc->deff, f->str, "physical effect");
}

/* the dimension scales case, time and link, and constraint and effect
   when the file has fields along them */
static int make_scales(out_file *f, const scene *s, const out_spec *sp,
                       scales *sc, char *err, size_t errsz) {
  static const int32_t one23[3] = {1, 2, 3};
  sc->dcase = case_scale(f, s->ncase);
  sc->dtime = time_scale(f, sp);
  sc->dlink =
      out_h5_scale(f->file, f->str, "link", H5T_NATIVE_INT32, 3, one23, "1",
                   "link (leg) number i; link i is pinned at angle "
                   "2 pi (i - 1) / 3 from X");
  if (sc->dcase < 0 || sc->dtime < 0 || sc->dlink < 0 ||
      out_cf_long_name(sc->dcase, f->str, "case number") < 0 ||
      out_cf_long_name(sc->dtime, f->str,
                       sp->grid_common ? "time" : "sample index") < 0 ||
      out_cf_long_name(sc->dlink, f->str, "link number") < 0 ||
      make_constraint(f, sp, sc) < 0 || make_effect(f, sp, sc) < 0) {
    out_fail(err, errsz, "cannot write the dimension scales");
    return -1;
  }
  return 0;
}

/* the swept keys, [case], each on the case scale */
static int write_swept_keys(out_file *f, const scene *s, const scales *sc,
                            char *err, size_t errsz) {
  size_t a = 0;
  if (out_cf_swept_keys(f->file, f->str, s, sc->dcase, &a) < 0) {
    out_fail(err, errsz, "cannot write the swept key %s", s->axis[a].path);
    return -1;
  }
  return 0;
}

/* the fill value of schema field i: NaN, -1, not computed; NULL for the
   strings (HDF5's, empty) */
static const void *fill_value(int i) {
  static const double fnan = (double)NAN;
  static const int32_t fneg = -1, fnotrun = OUT_STATUS_NOT_COMPUTED;
  static const int64_t fneg64 = -1;
  const out_field_info *fi = &out_field_table[i];
  return fi->type == OUT_F64             ? (const void *)&fnan
         : fi->flags == OUT_FLAGS_STATUS ? (const void *)&fnotrun
         : fi->type == OUT_I32           ? (const void *)&fneg
         : fi->type == OUT_I64           ? (const void *)&fneg64
                                         : NULL;
}

/*
 * The per-case datasets of a file written a case at a time (in whatever
 * order the cases end) are reopened with a chunk cache (CASE_CACHE bytes
 * each), so that a chunk is read, checksummed and written once per flush
 * rather than at every case (out_h5_dataset gives none).  A simulated
 * sweep of 3000 cases of 11 samples: 8.9 s without, 4.9 s with.
 */
#define CASE_CACHE (1 << 20)

static int reopen_cached(out_file *f, int i) {
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  int rc = -1;
  if (dapl >= 0 && H5Pset_chunk_cache(dapl, 521, CASE_CACHE, 1.0) >= 0 &&
      H5Dclose(f->ds[i]) >= 0) {
    f->ds[i] = H5Dopen2(f->file, out_field_table[i].name, dapl);
    rc = f->ds[i] < 0 ? -1 : 0;
  }
  if (dapl >= 0) H5Pclose(dapl);
  return rc;
}

/* the rank, extents, chunk and scales of schema field i */
static int field_dims(const out_field_info *fi, const scene *s,
                      const out_spec *sp, const scales *sc, hsize_t dims[4],
                      hsize_t chunk[4], hid_t axes[4]) {
  int rank = 0;
  dims[rank] = s->ncase;
  chunk[rank] = fi->shape == OUT_C ? sp->case_chunk : sp->tile_cases;
  axes[rank++] = sc->dcase;
  if (fi->shape != OUT_C) {
    dims[rank] = sp->nt;
    chunk[rank] = sp->chunk_points < sp->nt ? sp->chunk_points : sp->nt;
    axes[rank++] = sc->dtime;
  }
  if (fi->shape == OUT_CTEL) {
    dims[rank] = chunk[rank] = (hsize_t)sp->neffect;
    axes[rank++] = sc->deff;
  }
  if (fi->shape == OUT_CTL || fi->shape == OUT_CTEL) {
    dims[rank] = chunk[rank] = 3;
    axes[rank++] = sc->dlink;
  }
  if (fi->shape == OUT_CTK) {
    dims[rank] = chunk[rank] = 3;
    axes[rank++] = sc->dcon;
  }
  return rank;
}

/* schema field i: its dataset, chunked [case, time, ...] on the scales */
static int make_field(out_file *f, int i, const scene *s, const out_spec *sp,
                      const out_meta *meta, const scales *sc,
                      const char *const coords[2], char *err, size_t errsz) {
  const out_field_info *fi = &out_field_table[i];
  const char *cs;
  hid_t axes[4];
  hsize_t dims[4], chunk[4];
  int rank = field_dims(fi, s, sp, sc, dims, chunk, axes), r;
  f->ds[i] =
      out_h5_dataset(f->file, f->str, fi->name, field_type(f, fi), rank, dims,
                     chunk, meta->gzip, fill_value(i), fi->units, fi->doc);
  /* coords[0] of a per-case variable, coords[1] of a per-sample one;
     scene_resolved reruns a case alone: with the data its files held */
  cs = coords[fi->shape != OUT_C];
  if (f->ds[i] < 0 || out_cf_field(f->ds[i], f->str, i) < 0 ||
      (cs[0] && out_h5_attr(f->ds[i], f->str, "coordinates", cs) < 0) ||
      (i == OUT_scene_resolved && f->files == OUT_INV &&
       out_h5_attr(f->ds[i], f->str, INPUTS_ATTR,
                   meta->inputs ? meta->inputs : "") < 0)) {
    out_fail(err, errsz, "cannot create dataset %s", fi->name);
    return -1;
  }
  for (r = 0; r < rank; r++)
    if (H5DSattach_scale(f->ds[i], axes[r], (unsigned)r) < 0) {
      out_fail(err, errsz, "cannot attach the dimension scales of %s",
               fi->name);
      return -1;
    }
  if (fi->shape == OUT_C && sp->case_cache && reopen_cached(f, i) < 0) {
    out_fail(err, errsz, "cannot open dataset %s", fi->name);
    return -1;
  }
  return 0;
}

/* case_time [case, time], when the time grid differs between cases */
static int make_case_time(out_file *f, const scene *s, const out_spec *sp,
                          const out_meta *meta, const scales *sc, char *err,
                          size_t errsz) {
  const double fnan = (double)NAN;
  hsize_t dims[2], chunk[2];
  dims[0] = s->ncase;
  dims[1] = sp->nt;
  chunk[0] = sp->tile_cases;
  chunk[1] = sp->chunk_points < sp->nt ? sp->chunk_points : sp->nt;
  f->case_time = out_h5_dataset(
      f->file, f->str, "case_time", H5T_NATIVE_DOUBLE, 2, dims, chunk,
      meta->gzip, &fnan, "s",
      "time of each sample of each case (the time grid differs between "
      "cases); NaN past a case's last sample");
  if (f->case_time < 0 ||
      out_cf_long_name(f->case_time, f->str, "time of the sample") < 0 ||
      H5DSattach_scale(f->case_time, sc->dcase, 0) < 0 ||
      H5DSattach_scale(f->case_time, sc->dtime, 1) < 0) {
    out_fail(err, errsz, "cannot create dataset case_time");
    return -1;
  }
  return 0;
}

/* the file itself, its string type and root attributes; the layout */
static out_file *file_open(const char *path, const scene *s, const out_spec *sp,
                           const out_meta *meta, char *err, size_t errsz) {
  out_file *f = calloc(1, sizeof *f);
  int i;
  if (!f) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  f->files = sp->files;
  f->file = f->str = f->case_time = f->dxpl = -1;
  for (i = 0; i < OUT_NFIELD; i++) f->ds[i] = -1;
  f->ncase = s->ncase;
  f->nt = sp->nt;
  f->neffect = sp->neffect;
  f->layout.ncase = s->ncase;
  f->layout.nt = sp->nt;
  f->layout.tc = sp->tile_cases;
  f->layout.q = sp->chunk_points < sp->nt ? sp->chunk_points : sp->nt;
  f->layout.neffect = sp->neffect;
  f->layout.gzip = meta->gzip;
  f->layout.fields = meta->fields;
  f->layout.case_time = !sp->grid_common;

  f->str = H5Tcopy(H5T_C_S1);
  /* the type conversion buffer of a write (the strings of a tile's
     cases): HDF5 allocates and zeroes its size, 1 MiB by default, at
     every write; OUT_TCONV_BUF bytes convert in pieces */
  f->dxpl = H5Pcreate(H5P_DATASET_XFER);
  if (f->str < 0 || H5Tset_size(f->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(f->str, H5T_CSET_UTF8) < 0)
    out_fail(err, errsz, "cannot make the string type");
  else if (f->dxpl < 0 || H5Pset_buffer(f->dxpl, OUT_TCONV_BUF, NULL, NULL) < 0)
    out_fail(err, errsz, "cannot make the transfer properties");
  else if ((f->file =
                H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT)) < 0)
    out_fail(err, errsz, "cannot create %s", path);
  else if (root_attrs(f, sp, meta) < 0)
    out_fail(err, errsz, "cannot write the root attributes");
  else
    return f;
  out_close(f, NULL, 0);
  return NULL;
}

out_file *out_open(const char *path, const scene *s, const out_spec *sp,
                   const out_meta *meta, char *err, size_t errsz) {
  scales sc = {-1, -1, -1, -1, -1};
  char *coords[2] = {NULL, NULL};
  int i, rc = -1;
  out_file *f = file_open(path, s, sp, meta, err, errsz);
  if (!f) return NULL;
  if (write_scene_text(f, s, err, errsz) == 0 &&
      make_scales(f, s, sp, &sc, err, errsz) == 0 &&
      write_swept_keys(f, s, &sc, err, errsz) == 0) {
    /* the per-case variables' coordinates are the swept keys; the
       per-sample ones' also case_time when the grid differs */
    coords[0] = out_h5_coordinates(s, 0);
    coords[1] = out_h5_coordinates(s, !sp->grid_common);
    if (!coords[0] || !coords[1]) snprintf(err, errsz, "out of memory");
    rc = coords[0] && coords[1] ? 0 : -1;
    /* the fields of the schema that are asked for (--fields) */
    for (i = 0; rc == 0 && i < OUT_NFIELD; i++)
      if ((meta->fields >> i & 1) && (out_field_table[i].files & sp->files))
        rc = make_field(f, i, s, sp, meta, &sc, (const char *const *)coords,
                        err, errsz);
    if (rc == 0 && !sp->grid_common)
      rc = make_case_time(f, s, sp, meta, &sc, err, errsz);
  }
  free(coords[0]);
  free(coords[1]);
  scales_close(&sc);
  if (rc == 0) return f;
  out_close(f, NULL, 0);
  return NULL;
}

/* the time of sample k of the inverse sweep's common grid */
static double inv_time(const void *first, size_t k) {
  return scene_case_time(first, k);
}

out_file *out_create(const char *path, const scene *s, const scene_case *first,
                     size_t nt, int grid_common, size_t chunk_points,
                     const out_block *b, const out_meta *meta, char *err,
                     size_t errsz) {
  out_spec sp;
  memset(&sp, 0, sizeof sp);
  sp.files = OUT_INV;
  sp.title =
      "rps3: inverse dynamics of the Lee & Shah 3-RPS manipulator "
      "along a trajectory, per case of a sweep";
  sp.time_doc =
      "time since the start of the trajectory, in s (the "
      "reference date of the units is nominal)";
  sp.nt = nt;
  sp.grid_common = grid_common;
  sp.time = inv_time;
  sp.time_ctx = first;
  sp.tile_cases = sp.case_chunk = b->cases < s->ncase ? b->cases : s->ncase;
  sp.chunk_points = chunk_points;
  sp.neffect = b->neffect;
  sp.effect = b->effect;
  return out_open(path, s, &sp, meta, err, errsz);
}

/* write slots [0, nc) x samples [0, nk) of a [cases, points, cols] buffer
   to rows [c0, c0 + nc) x [k0, k0 + nk) of a dataset of rank `rank` */
static int write_tile(hid_t ds, hid_t dxpl, hid_t type, int rank, size_t cases,
                      size_t points, const void *buf, size_t c0, size_t nc,
                      size_t k0, size_t nk) {
  hsize_t mdims[4], start[4] = {0, 0, 0, 0}, count[4], fstart[4] = {0};
  hid_t fs = H5Dget_space(ds), ms;
  int r, rc = -1;
  mdims[0] = cases;
  count[0] = nc;
  fstart[0] = c0;
  if (rank >= 2) {
    mdims[1] = points;
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
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, fstart, NULL, count, NULL) >= 0 &&
      H5Dwrite(ds, type, ms, fs, dxpl, buf) >= 0)
    rc = 0;
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

void out_file_layout(const out_file *f, out_layout *L) { *L = f->layout; }

/* write the chunks out_pack made, as they are */
static int write_packed(out_file *f, const out_block *b, char *err,
                        size_t errsz) {
  size_t i;
  for (i = 0; i < b->npk; i++) {
    const out_chunk *ck = &b->pk[i];
    hid_t ds = ck->field < OUT_NFIELD ? f->ds[ck->field] : f->case_time;
    const unsigned char *data =
        !ck->direct ? b->pk_buf
        : ck->field < OUT_NFIELD
            ? (const unsigned char *)out_block_field(b, ck->field)
            : (const unsigned char *)b->t;
    hsize_t off[4] = {0, 0, 0, 0};
    off[0] = ck->c0;
    off[1] = ck->k0;
    if (H5Dwrite_chunk(ds, H5P_DEFAULT, 0, off, ck->size, data + ck->off) < 0) {
      out_fail(err, errsz, "cannot write %s of cases %zu-",
               ck->field < OUT_NFIELD ? out_field_table[ck->field].name
                                      : "case_time",
               ck->c0);
      return -1;
    }
  }
  return 0;
}

int out_write(out_file *f, const out_block *b, size_t c0, size_t nc, size_t k0,
              size_t nk, int with_case, char *err, size_t errsz) {
  int i;
  if (b->packed && write_packed(f, b, err, errsz)) return -1;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    hid_t type = field_type(f, fi);
    int rank = field_rank(fi);
    if ((fi->shape == OUT_C && !with_case) || f->ds[i] < 0 ||
        (fi->shape != OUT_C && b->packed))
      continue;
    if (write_tile(f->ds[i], f->dxpl, type, rank, b->cases, b->points,
                   out_block_field(b, i), c0, nc, k0, nk) < 0) {
      out_fail(err, errsz, "cannot write %s of cases %zu-%zu", fi->name, c0,
               c0 + nc - 1);
      return -1;
    }
  }
  if (f->case_time >= 0 && !b->packed &&
      write_tile(f->case_time, f->dxpl, H5T_NATIVE_DOUBLE, 2, b->cases,
                 b->points, b->t, c0, nc, k0, nk) < 0) {
    out_fail(err, errsz, "cannot write case_time of cases %zu-%zu", c0,
             c0 + nc - 1);
    return -1;
  }
  return 0;
}

int out_write_window(out_file *f, void *const buf[], size_t points, size_t c,
                     size_t k0, size_t nk, const double *times, char *err,
                     size_t errsz) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    if (fi->shape == OUT_C || f->ds[i] < 0) continue;
    if (write_tile(f->ds[i], f->dxpl, field_type(f, fi), field_rank(fi), 1,
                   points, buf[i], c, 1, k0, nk) < 0) {
      out_fail(err, errsz, "cannot write %s of case %zu", fi->name, c);
      return -1;
    }
  }
  if (f->case_time >= 0 && times &&
      write_tile(f->case_time, f->dxpl, H5T_NATIVE_DOUBLE, 2, 1, points, times,
                 c, 1, k0, nk) < 0) {
    out_fail(err, errsz, "cannot write case_time of case %zu", c);
    return -1;
  }
  return 0;
}

int out_write_case(out_file *f, const void *const val[], size_t c, char *err,
                   size_t errsz) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    if (fi->shape != OUT_C || f->ds[i] < 0) continue;
    if (!val[i] || write_tile(f->ds[i], f->dxpl, field_type(f, fi), 1, 1, 1,
                              val[i], c, 1, 0, 1) < 0) {
      out_fail(err, errsz, "cannot write %s of case %zu", fi->name, c);
      return -1;
    }
  }
  return 0;
}

int out_close(out_file *f, char *err, size_t errsz) {
  int i, rc = 0;
  if (!f) return 0;
  for (i = 0; i < OUT_NFIELD; i++)
    if (f->ds[i] >= 0 && H5Dclose(f->ds[i]) < 0) rc = -1;
  if (f->case_time >= 0 && H5Dclose(f->case_time) < 0) rc = -1;
  if (f->str >= 0) H5Tclose(f->str);
  if (f->dxpl >= 0) H5Pclose(f->dxpl);
  if (f->file >= 0 && H5Fclose(f->file) < 0) rc = -1;
  if (rc < 0 && err) out_fail(err, errsz, "cannot close the file");
  free(f);
  return rc;
}
