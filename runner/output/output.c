/*
 * output.c - create a runner file (output.h), self-describing (netCDF-4
 * style: dimension scales on every axis, units and description on every
 * dataset), readable by h5py and by xarray through h5netcdf; and its
 * writes.
 */
#include "output.h"
#include "scene/design.h"
#include "scene/inputs.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <yaml.h>

/* bytes of HDF5's type conversion buffer per write */
#define OUT_TCONV_BUF 65536

static hid_t out_field_type(const out_file *f, const out_field_info *fi) {
  return fi->type == OUT_F64   ? H5T_NATIVE_DOUBLE
         : fi->type == OUT_I32 ? H5T_NATIVE_INT32
         : fi->type == OUT_I64 ? H5T_NATIVE_INT64
                               : f->str;
}

/* the root attributes: versions, time of creation, command line, CF's,
   title and content, and (not in a simulation's file) the fields, the
   input files and the shard */
static int root_attrs(const out_file *f, const out_spec *sp,
                      const out_meta *meta) {
  char now[32], h5v[32], fields[1024];
  unsigned maj, min, rel;
  const char *const kv[][2] = {
      {"rps3_version", rps3_version()},
      {"created_utc", now},
      {"command_line", meta->command_line},
      {"gsl_version", gsl_version},
      {"hdf5_version", h5v},
      {"yaml_version", yaml_get_version_string()},
      {"title", sp->title},
      {"content", sp->content},
      {"fields",
       out_fields_attr(sp->files, meta->fields, fields, sizeof fields)},
      {INPUTS_ATTR, meta->inputs ? meta->inputs : ""},
      {"shard", meta->shard}};
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (out_h5_attrs(f->file, f->str, kv, 6) < 0 ||
          out_cf_root(f->file, f->str, now, meta->command_line) < 0 ||
          out_h5_attrs(f->file, f->str, kv + 6, f->files & OUT_SIM ? 2 : 5) < 0)
             ? -1
             : 0;
}

/* the scene file, verbatim */
static int write_scene_text(out_file *f, const scene *s, char *err,
                            size_t errsz) {
  hid_t ds = out_h5_dataset(f->file, f->str, "scene", f->str, 0, NULL, NULL, 0,
                            NULL, "1", "the scene file (YAML), verbatim");
  const char *text = s->text;
  int rc = 0;
  if (ds < 0 || out_cf_long_name(ds, f->str, "scene file") < 0 ||
      H5Dwrite(ds, f->str, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) < 0) {
    out_fail(err, errsz, "cannot write the scene text");
    rc = -1;
  }
  if (ds >= 0) H5Dclose(ds);
  return rc;
}

/* the file's dimension scales: a dataset (or -1) and extent per axis */
typedef struct {
  hid_t id[OUT_NAXIS];
  size_t len[OUT_NAXIS];
  rps3_design_grid gr; /* a design study's pose grid */
  const out_spec *sp;
  int ax; /* the axis scale_fill writes */
} scales;

#define POSE_DOC                                                        \
  "pose grid: the centre of each cell of design.alpha, design.beta or " \
  "design.z_c"

/* units, long_name and description of the axes (%s: what a case is; a
   common time grid's time axis is the spec's) */
static const struct {
  const char *units, *long_name, *doc;
} axis_info[OUT_NAXIS] = {
    {"1", "%s number",
     "%s number; row-major over the sweep keys in file order, the last key "
     "fastest"},
    {"1", "sample index",
     "sample index: the time grid differs between cases, the time of each "
     "sample is case_time"},
    {"1", "link number",
     "link (leg) number i; link i is pinned at angle 2 pi (i - 1) / 3 from "
     "X"},
    {"1", "constraint number",
     "constraint k of eqs. (8), (9), (10): ball joints 1-2, 2-3, 3-1"},
    {"1", "physical effect", "physical effect, as named by rps3_effect_name"},
    {"1", "reachability flag",
     "reachability flag: bit k of pose_flags is flag k "
     "(rps3_design_flag_name)"},
    {"rad", "precession angle alpha of the pose", POSE_DOC},
    {"rad", "nutation angle beta of the pose", POSE_DOC},
    {"m", "height z_c of the platform centre", POSE_DOC}};

/* value k of axis sc->ax: the case number or sample index, the time of
   the common grid, the link or constraint number, the centre of cell k of
   the pose grid as rps3_design_grid_pose gives it (alpha fastest) */
static double axis_value(const void *ctx, size_t k) {
  const scales *sc = ctx;
  double pose[3];
  int p = sc->ax - OUT_AX_ALPHA;
  if (sc->ax == OUT_AX_TIME && sc->sp->grid_common)
    return sc->sp->time(sc->sp->time_ctx, k);
  if (sc->ax == OUT_AX_LINK || sc->ax == OUT_AX_CON) return (double)(k + 1);
  if (p < 0) return (double)k;
  k *= p == 0 ? 1 : p == 1 ? sc->gr.n[0] : sc->gr.n[0] * sc->gr.n[1];
  return rps3_design_grid_pose(&sc->gr, k, pose) == RPS3_OK ? pose[p]
                                                            : (double)NAN;
}

/* the values of a 1-D scale in runs of OUT_AXIS_RUN, so that memory does
   not grow with the sweep (the case numbers and sample indices, whole
   numbers below 2^53, convert exactly to the scale's integers); 0 or -1 */
static int scale_fill(hid_t ds, scales *sc) {
  double *v = malloc(OUT_AXIS_RUN * sizeof *v);
  size_t c0, m, k, n = sc->len[sc->ax];
  int rc = v ? 0 : -1;
  for (c0 = 0; rc == 0 && c0 < n; c0 += m) {
    m = n - c0 < OUT_AXIS_RUN ? n - c0 : OUT_AXIS_RUN;
    for (k = 0; k < m; k++) v[k] = axis_value(sc, c0 + k);
    rc = out_h5_tile(ds, H5P_DEFAULT, H5T_NATIVE_DOUBLE, 0, m, 1, v, c0, m, 0,
                     1);
  }
  free(v);
  return rc;
}

/* the scale of axis ax, its values and attributes; 0 or -1 */
static int make_scale(out_file *f, scales *sc, int ax) {
  const out_spec *sp = sc->sp;
  const char *names[RPS3_NEFFECT + RPS3_DESIGN_NFLAG];
  char doc_buf[128], ln[64];
  const char *units = axis_info[ax].units, *doc = doc_buf;
  int k, text = ax == OUT_AX_EFF || ax == OUT_AX_FLAG;
  hid_t type = ax == OUT_AX_CASE  ? H5T_NATIVE_INT64
               : ax <= OUT_AX_CON ? H5T_NATIVE_INT32
               : text             ? f->str
                                  : H5T_NATIVE_DOUBLE;
  for (k = 0; ax == OUT_AX_EFF && k < sp->neffect; k++)
    names[k] = rps3_effect_name(sp->effect[k]);
  for (k = 0; ax == OUT_AX_FLAG && k < RPS3_DESIGN_NFLAG; k++)
    names[k] = rps3_design_flag_name(k);
  snprintf(ln, sizeof ln, axis_info[ax].long_name, f->row);
  snprintf(doc_buf, sizeof doc_buf, axis_info[ax].doc, f->row);
  if (ax == OUT_AX_TIME && sp->grid_common) {
    type = H5T_NATIVE_DOUBLE;
    units = OUT_CF_TIME_UNITS;
    snprintf(ln, sizeof ln, "time");
    doc = sp->time_doc;
  }
  sc->ax = ax;
  sc->id[ax] =
      out_h5_scale(f->file, f->str,
                   ax == OUT_AX_TIME ? OUT_CF_SAMPLE_DIM(sp->grid_common)
                                     : out_axis_name[ax],
                   type, sc->len[ax], text ? names : NULL, units, doc);
  return (sc->id[ax] < 0 || out_cf_long_name(sc->id[ax], f->str, ln) < 0 ||
          (ax == OUT_AX_TIME && sp->grid_common &&
           out_cf_time(sc->id[ax], f->str) < 0) ||
          (!text && scale_fill(sc->id[ax], sc) < 0))
             ? -1
             : 0;
}

/* the scales of the axes a field of the file's kinds has */
static int make_scales(out_file *f, const scene *s, scales *sc, char *err,
                       size_t errsz) {
  const out_spec *sp = sc->sp;
  int ax, i, has;
  if (sp->files & OUT_POSE) design_grid(s, &sc->gr);
  sc->len[OUT_AX_CASE] = s->ncase;
  sc->len[OUT_AX_TIME] = sp->nt;
  sc->len[OUT_AX_LINK] = sc->len[OUT_AX_CON] = 3;
  sc->len[OUT_AX_EFF] = (size_t)sp->neffect;
  sc->len[OUT_AX_FLAG] = RPS3_DESIGN_NFLAG;
  for (ax = 0; ax < 3; ax++) sc->len[OUT_AX_ALPHA + ax] = sc->gr.n[ax];
  for (ax = 0; ax < OUT_NAXIS; ax++) {
    for (i = 0, has = 0; i < OUT_NFIELD && !has; i++)
      has = (out_field_table[i].files & sp->files) &&
            out_shape_has(out_field_table[i].shape, ax);
    if (has && make_scale(f, sc, ax) < 0) {
      out_fail(err, errsz, "cannot write the dimension scales");
      return -1;
    }
  }
  return 0;
}

/* the per-case datasets of a file written a case at a time (in any order)
   get a chunk cache (CASE_CACHE bytes each): a chunk is checksummed and
   written once per flush, not at every case (3000 simulated cases of 11
   samples: 8.9 s without, 4.9 s with) */
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

/* schema field i: its dataset, chunked [case, time, ...] on the scales
   (along case, a tile's or a per-case chunk's cases; along time,
   chunk_points samples; the other axes whole) */
static int make_field(out_file *f, int i, const out_meta *meta,
                      const scales *sc, const char *const coords[2], char *err,
                      size_t errsz) {
  const out_field_info *fi = &out_field_table[i];
  const out_spec *sp = sc->sp;
  const int *a = out_shape_axes[fi->shape];
  const char *cs;
  hid_t axes[4];
  hsize_t dims[4], chunk[4];
  int rank, r;
  for (rank = 0; a[rank] >= 0; rank++) {
    dims[rank] = chunk[rank] = sc->len[a[rank]];
    axes[rank] = sc->id[a[rank]];
  }
  chunk[0] = fi->shape == OUT_C ? sp->case_chunk : sp->tile_cases;
  if (rank > 1 && a[1] == OUT_AX_TIME && sp->chunk_points < sp->nt)
    chunk[1] = sp->chunk_points;
  f->ds[i] =
      out_h5_dataset(f->file, f->str, fi->name, out_field_type(f, fi), rank,
                     dims, chunk, meta->gzip, out_fill(i), fi->units, fi->doc);
  /* coords[0] of a per-case variable, coords[1] of a per-sample one;
     scene_resolved reruns a case alone: with the data its files held */
  cs = coords[fi->shape != OUT_C];
  if (f->ds[i] < 0 || out_cf_field(f->ds[i], f->str, i) < 0 ||
      (cs[0] && out_h5_attr(f->ds[i], f->str, "coordinates", cs) < 0) ||
      (!strcmp(fi->name, "scene_resolved") && !(f->files & OUT_SIM) &&
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
static int make_case_time(out_file *f, const out_meta *meta, const scales *sc,
                          char *err, size_t errsz) {
  const out_spec *sp = sc->sp;
  const double fnan = (double)NAN;
  hsize_t dims[2], chunk[2];
  dims[0] = sc->len[OUT_AX_CASE];
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
      H5DSattach_scale(f->case_time, sc->id[OUT_AX_CASE], 0) < 0 ||
      H5DSattach_scale(f->case_time, sc->id[OUT_AX_TIME], 1) < 0) {
    out_fail(err, errsz, "cannot create dataset case_time");
    return -1;
  }
  return 0;
}

/* the file itself, its string type and root attributes; the layout */
static out_file *file_open(const char *path, const out_spec *sp,
                           const out_meta *meta, char *err, size_t errsz) {
  out_file *f = calloc(1, sizeof *f);
  int i;
  if (!f) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  f->files = sp->files;
  f->row = sp->files & OUT_DES ? "design" : "case";
  f->file = f->str = f->case_time = f->dxpl = -1;
  for (i = 0; i < OUT_NFIELD; i++) f->ds[i] = -1;
  f->layout.tc = sp->tile_cases;
  f->layout.q = sp->chunk_points < sp->nt ? sp->chunk_points : sp->nt;
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

/* 1 when the file of sp and meta has field i: a field of its kinds, and
   of an inverse sweep's file one of --fields */
static int wanted(const out_spec *sp, const out_meta *meta, int i) {
  return (out_field_table[i].files & sp->files) &&
         (!(sp->files & OUT_INV) || OUT_HAS(meta->fields, i));
}

out_file *out_open(const char *path, const scene *s, const out_spec *sp,
                   const out_meta *meta, char *err, size_t errsz) {
  scales sc;
  char *coords[2] = {NULL, NULL};
  size_t a = 0;
  int i, rc = -1;
  out_file *f = file_open(path, sp, meta, err, errsz);
  if (!f) return NULL;
  memset(&sc, 0, sizeof sc);
  for (i = 0; i < OUT_NAXIS; i++) sc.id[i] = -1;
  sc.sp = sp;
  if (write_scene_text(f, s, err, errsz) == 0 &&
      make_scales(f, s, &sc, err, errsz) == 0) {
    /* the swept keys, [case], each on the case scale */
    if (out_cf_swept_keys(f->file, f->str, s, sc.id[OUT_AX_CASE], &a) < 0)
      out_fail(err, errsz, "cannot write the swept key %s", s->axis[a].path);
    /* the per-case variables' coordinates are the swept keys; the
       per-sample ones' also case_time when the grid differs */
    else if (!(coords[0] = out_h5_coordinates(s, 0)) ||
             !(coords[1] = out_h5_coordinates(s, !sp->grid_common)))
      snprintf(err, errsz, "out of memory");
    else
      rc = 0;
    for (i = 0; rc == 0 && i < OUT_NFIELD; i++)
      if (wanted(sp, meta, i))
        rc = make_field(f, i, meta, &sc, (const char *const *)coords, err,
                        errsz);
    if (rc == 0 && !sp->grid_common)
      rc = make_case_time(f, meta, &sc, err, errsz);
  }
  free(coords[0]);
  free(coords[1]);
  for (i = 0; i < OUT_NAXIS; i++)
    if (sc.id[i] >= 0) H5Dclose(sc.id[i]);
  if (rc == 0) return f;
  out_close(f, NULL, 0);
  return NULL;
}

static double inv_time(const void *first, size_t k) {
  return scene_case_time(first, k);
}

static double axis_time(const void *times, size_t k) {
  return ((const double *)times)[k];
}

/* cases per chunk of a simulation's per-case datasets: each case's values
   are written alone (the cases end in any order), and HDF5 rewrites (and
   checksums) the whole chunk: small, with a chunk cache */
#define CASE_CHUNK 64

out_file *out_create(const char *path, const scene *s, int files, size_t nt,
                     const void *axis, size_t chunk_points, const out_block *b,
                     const out_meta *meta, char *err, size_t errsz) {
  out_spec sp;
  int sim = files == OUT_SIM;
  memset(&sp, 0, sizeof sp);
  sp.files = files;
  sp.title = sim ? "rps3: closed-loop simulation of the Lee & Shah 3-RPS "
                   "manipulator along a trajectory, per case of a sweep"
                 : "rps3: inverse dynamics of the Lee & Shah 3-RPS manipulator "
                   "along a trajectory, per case of a sweep";
  sp.content = sim ? "simulation" : NULL;
  sp.time_doc = sim ? "simulated time since the start of the trajectory, in s "
                      "(the reference date of the units is nominal)"
                    : "time since the start of the trajectory, in s (the "
                      "reference date of the units is nominal)";
  sp.nt = nt;
  sp.grid_common = axis != NULL;
  sp.time = sim ? axis_time : inv_time;
  sp.time_ctx = axis;
  /* a simulation writes a window of one case at a time */
  sp.tile_cases = sim ? 1 : b->cases < s->ncase ? b->cases : s->ncase;
  sp.case_chunk = !sim                    ? sp.tile_cases
                  : s->ncase < CASE_CHUNK ? s->ncase
                                          : CASE_CHUNK;
  sp.chunk_points = chunk_points;
  sp.case_cache = sim;
  sp.neffect = sim ? 0 : b->neffect;
  sp.effect = sim ? NULL : b->effect;
  return out_open(path, s, &sp, meta, err, errsz);
}

/* write the chunks out_pack made, as they are */
static int write_packed(out_file *f, const out_block *b, char *err,
                        size_t errsz) {
  size_t i;
  for (i = 0; i < b->npk; i++) {
    const out_chunk *ck = &b->pk[i];
    hid_t ds = ck->field < OUT_NFIELD ? f->ds[ck->field] : f->case_time;
    const unsigned char *data = !ck->direct ? b->pk_buf
                                : ck->field < OUT_NFIELD
                                    ? (const unsigned char *)b->buf[ck->field]
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

/* a write of field `name` failed: of which cases */
static void rows_fail(const out_file *f, const char *name, size_t c0, size_t nc,
                      char *err, size_t errsz) {
  if (nc == 1)
    out_fail(err, errsz, "cannot write %s of %s %zu", name, f->row, c0);
  else
    out_fail(err, errsz, "cannot write %s of %ss %zu-%zu", name, f->row, c0,
             c0 + nc - 1);
}

/* the fields of f with a time axis (timed 1) or those without (0) from
   buf[i], [cases][points][the other axes] (a NULL string written empty),
   into cases c0 .. c0 + nc - 1, samples k0 .. k0 + nk - 1; and case_time
   from t, when the file has it and t is not NULL */
static int write_fields(out_file *f, const void *const buf[], const double *t,
                        int timed, size_t cases, size_t points, size_t c0,
                        size_t nc, size_t k0, size_t nk, char *err,
                        size_t errsz) {
  const char **str = timed ? NULL : malloc(cases * sizeof *str);
  size_t j;
  int i, rc = timed || str ? 0 : -1;
  for (i = 0; rc == 0 && i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    const void *v = buf[i];
    if (out_shape_has(fi->shape, OUT_AX_TIME) != timed || f->ds[i] < 0)
      continue;
    for (j = 0; v && fi->type == OUT_STR && j < nc; j++)
      str[j] = ((const char *const *)v)[j] ? ((const char *const *)v)[j] : "";
    if (v && fi->type == OUT_STR) v = str;
    if (!v || out_h5_tile(f->ds[i], f->dxpl, out_field_type(f, fi), timed,
                          cases, points, v, c0, nc, k0, nk) < 0) {
      rows_fail(f, fi->name, c0, nc, err, errsz);
      rc = -1;
    }
  }
  if (rc == 0 && f->case_time >= 0 && t &&
      out_h5_tile(f->case_time, f->dxpl, H5T_NATIVE_DOUBLE, 1, cases, points, t,
                  c0, nc, k0, nk) < 0) {
    rows_fail(f, "case_time", c0, nc, err, errsz);
    rc = -1;
  }
  if (!timed && !str) snprintf(err, errsz, "out of memory");
  free(str);
  return rc;
}

int out_write(out_file *f, const out_block *b, const out_tile *t, char *err,
              size_t errsz) {
  const void *buf[OUT_NFIELD];
  size_t k;
  int i;
  for (i = 0; i < OUT_NFIELD; i++) buf[i] = b->buf[i];
  for (k = 0; k < t->blank_below; k += b->points)
    if (write_fields(f, buf, b->t, 1, b->cases, b->points, t->c0, 1, k,
                     b->points, err, errsz))
      return -1;
  return (b->packed && write_packed(f, b, err, errsz)) ||
                 (t->with_case &&
                  write_fields(f, buf, NULL, 0, b->cases, 1, t->c0, t->nc, 0, 1,
                               err, errsz)) ||
                 (!b->packed && t->nk > 0 &&
                  write_fields(f, buf, b->t, 1, b->cases, b->points, t->c0,
                               t->nc, t->k0, t->nk, err, errsz))
             ? -1
             : 0;
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
