/*
 * design_output.c - the HDF5 file of a design study (design_output.h).
 */
#include "design_output.h"
#include "out_cf.h"
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

#define DESIGN_ROW(ID, NAME, SHAPE, TYPE, WHEN, UNITS, LONG, DOC) \
  {NAME, SHAPE, TYPE, WHEN, UNITS, LONG, DOC},
const design_field_info design_field_table[DESIGN_NFIELD] = {
    DESIGN_OUT_FIELDS(DESIGN_ROW)};
#undef DESIGN_ROW

/* ----------------------------------------------------------------- tiles */

int design_field_written(const design_tile *t, int i) {
  int w = design_field_table[i].when;
  return w == DW_ALL || (w == DW_TASK && t->task) ||
         (w == DW_POSE && t->per_pose);
}

size_t design_field_inner(const design_tile *t, int i) {
  switch (design_field_table[i].shape) {
  case DS_CL: return 3;
  case DS_CF: return RPS3_DESIGN_NFLAG;
  case DS_CP: return t->npose;
  default: return 1;
  }
}

static size_t elem_size(int type) {
  return type == DT_F64   ? sizeof(double)
         : type == DT_I32 ? sizeof(int32_t)
         : type == DT_I64 ? sizeof(int64_t)
                          : sizeof(char *);
}

size_t design_bytes_per_design(const design_tile *t) {
  size_t b = 0;
  int i;
  for (i = 0; i < DESIGN_NFIELD; i++)
    if (design_field_written(t, i))
      b += design_field_inner(t, i) *
           (design_field_table[i].type == DT_STR
                ? 64
                : elem_size(design_field_table[i].type));
  return b;
}

int design_tile_alloc(design_tile *t, size_t cap, size_t npose, int task,
                      int per_pose) {
  int i;
  size_t j;
  memset(t, 0, sizeof *t);
  t->cap = cap;
  t->npose = npose;
  t->task = task;
  t->per_pose = per_pose;
  for (i = 0; i < DESIGN_NFIELD; i++) {
    if (!design_field_written(t, i)) continue;
    t->buf[i] = calloc(cap * design_field_inner(t, i),
                       elem_size(design_field_table[i].type));
    if (!t->buf[i]) {
      design_tile_free(t);
      return -1;
    }
  }
  for (j = 0; j < cap; j++) design_tile_clear(t, j);
  return 0;
}

void design_tile_clear(design_tile *t, size_t j) {
  int i;
  size_t k;
  for (i = 0; i < DESIGN_NFIELD; i++) {
    size_t n = design_field_inner(t, i);
    if (!t->buf[i]) continue;
    switch (design_field_table[i].type) {
    case DT_F64:
      for (k = 0; k < n; k++) ((double *)t->buf[i])[j * n + k] = (double)NAN;
      break;
    case DT_I32:
      for (k = 0; k < n; k++)
        ((int32_t *)t->buf[i])[j * n + k] =
            (i == DO_status || i == DO_task_status) ? OUT_STATUS_NOT_COMPUTED
                                                    : -1;
      break;
    case DT_I64:
      for (k = 0; k < n; k++) ((int64_t *)t->buf[i])[j * n + k] = -1;
      break;
    default: free(((char **)t->buf[i])[j]); ((char **)t->buf[i])[j] = NULL;
    }
  }
}

void design_tile_free(design_tile *t) {
  int i;
  size_t j;
  if (!t) return;
  for (i = 0; i < DESIGN_NFIELD; i++) {
    if (t->buf[i] && design_field_table[i].type == DT_STR)
      for (j = 0; j < t->cap; j++) free(((char **)t->buf[i])[j]);
    free(t->buf[i]);
  }
  memset(t, 0, sizeof *t);
}

/* ------------------------------------------------------------------ file */

struct design_file {
  hid_t file;
  hid_t str;
  hid_t ds[DESIGN_NFIELD];
  size_t ncase;
  size_t n[3]; /* cells of alpha, beta, z_c */
};

static hid_t type_of(const design_file *f, int type) {
  return type == DT_F64   ? H5T_NATIVE_DOUBLE
         : type == DT_I32 ? H5T_NATIVE_INT32
         : type == DT_I64 ? H5T_NATIVE_INT64
                          : f->str;
}

/* the root attributes, as a sweep's file has them (merge and --resume
   read them), with content "design" */
static int root_attrs(hid_t file, hid_t str, const out_meta *meta,
                      const design_tile *t) {
  char now[32], h5v[32];
  unsigned maj, min, rel;
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (out_h5_attr(file, str, "rps3_version", rps3_version()) < 0 ||
          out_h5_attr(file, str, "created_utc", now) < 0 ||
          out_h5_attr(file, str, "command_line", meta->command_line) < 0 ||
          out_h5_attr(file, str, "gsl_version", gsl_version) < 0 ||
          out_h5_attr(file, str, "hdf5_version", h5v) < 0 ||
          out_h5_attr(file, str, "yaml_version", yaml_get_version_string()) <
              0 ||
          out_h5_attr(file, str, "title",
                      "rps3: design study of the Lee & Shah 3-RPS "
                      "manipulator, indices per design over a grid of "
                      "poses") < 0 ||
          out_h5_attr(file, str, "content", "design") < 0 ||
          out_h5_attr(file, str, "fields", design_fields_text(t)) < 0 ||
          out_h5_attr(file, str, INPUTS_ATTR,
                      meta->inputs ? meta->inputs : "") < 0 ||
          out_cf_root(file, str, now, meta->command_line) < 0 ||
          (meta->shard && out_h5_attr(file, str, "shard", meta->shard) < 0))
             ? -1
             : 0;
}

const char *design_fields_text(const design_tile *t) {
  return t->per_pose ? (t->task ? "design task per_pose" : "design per_pose")
                     : (t->task ? "design task" : "design");
}

/* the dimension scales of the file */
enum { SC_CASE, SC_LINK, SC_FLAG, SC_ALPHA, SC_BETA, SC_Z_C, NSC };

static int make_scales(design_file *f, const scene *s, const design_tile *t,
                       hid_t sc[NSC]) {
  static const int32_t one23[3] = {1, 2, 3};
  static const char *const axis_name[3] = {"alpha", "beta", "z_c"};
  static const char *const axis_units[3] = {"rad", "rad", "m"};
  static const char *const axis_long[3] = {"precession angle alpha of the pose",
                                           "nutation angle beta of the pose",
                                           "height z_c of the platform centre"};
  const char *flag[RPS3_DESIGN_NFLAG];
  rps3_design_grid gr;
  int64_t *idx;
  double *v;
  size_t c0, n, k;
  int ax, rc = 0;
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
    flag[k] = rps3_design_flag_name((int)k);
  sc[SC_CASE] = out_h5_scale(f->file, f->str, "case", H5T_NATIVE_INT64,
                             f->ncase, NULL, "1",
                             "design number; row-major over the sweep keys "
                             "in file order, the last key fastest");
  /* link: the dimension of the task's variables, only with them */
  sc[SC_LINK] = !t->task
                    ? -1
                    : out_h5_scale(f->file, f->str, "link", H5T_NATIVE_INT32, 3,
                                   one23, "1",
                                   "link (leg) number i; link i is pinned at "
                                   "angle 2 pi (i - 1) / 3 from X");
  sc[SC_FLAG] = out_h5_scale(f->file, f->str, "flag", f->str, RPS3_DESIGN_NFLAG,
                             flag, "1",
                             "reachability flag: bit k of pose_flags is "
                             "flag k (rps3_design_flag_name)");
  if (sc[SC_CASE] < 0 || (t->task && sc[SC_LINK] < 0) || sc[SC_FLAG] < 0 ||
      out_cf_long_name(sc[SC_CASE], f->str, "design number") < 0 ||
      (t->task && out_cf_long_name(sc[SC_LINK], f->str, "link number") < 0) ||
      out_cf_long_name(sc[SC_FLAG], f->str, "reachability flag") < 0)
    return -1;
  idx = malloc(OUT_AXIS_RUN * sizeof *idx);
  for (c0 = 0; idx && c0 < f->ncase; c0 += n) {
    n = f->ncase - c0 < OUT_AXIS_RUN ? f->ncase - c0 : OUT_AXIS_RUN;
    for (k = 0; k < n; k++) idx[k] = (int64_t)(c0 + k);
    if (out_h5_rows(sc[SC_CASE], H5T_NATIVE_INT64, c0, n, idx) < 0) break;
  }
  if (!idx || c0 < f->ncase) rc = -1;
  free(idx);
  /* the grid's cell centres, as rps3_design_grid_pose gives them: the
     dimensions of the per-pose variables (only with them: a scale that no
     variable uses would be a dimension of nothing) */
  design_grid(s, &gr);
  for (ax = 0; ax < 3 && rc == 0 && t->per_pose; ax++) {
    double pose[3];
    size_t i, stride = ax == 0 ? 1 : ax == 1 ? gr.n[0] : gr.n[0] * gr.n[1];
    v = malloc(gr.n[ax] * sizeof *v);
    for (i = 0; v && i < gr.n[ax]; i++) {
      if (rps3_design_grid_pose(&gr, i * stride, pose) != RPS3_OK) break;
      v[i] = pose[ax];
    }
    sc[SC_ALPHA + ax] =
        v && i == gr.n[ax]
            ? out_h5_scale(f->file, f->str, axis_name[ax], H5T_NATIVE_DOUBLE,
                           gr.n[ax], v, axis_units[ax],
                           "pose grid: the centre of each cell of "
                           "design.alpha, design.beta or design.z_c")
            : -1;
    free(v);
    if (sc[SC_ALPHA + ax] < 0 ||
        out_cf_long_name(sc[SC_ALPHA + ax], f->str, axis_long[ax]) < 0)
      rc = -1;
  }
  return rc;
}

/* the swept keys, [case], on the case scale (as a sweep's file) */
static int write_swept_keys(design_file *f, const scene *s, hid_t dcase) {
  return out_cf_swept_keys(f->file, f->str, s, dcase, NULL);
}

/* flag_masks and flag_meanings of a variable of reachability flags */
static int flag_attrs(hid_t ds, hid_t str) {
  int32_t mask[RPS3_DESIGN_NFLAG];
  hsize_t n = RPS3_DESIGN_NFLAG;
  char words[256];
  size_t len = 0;
  int k, rc = -1;
  hid_t sp, a;
  words[0] = '\0';
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++) {
    mask[k] = 1 << k;
    len += (size_t)snprintf(words + len, sizeof words - len, "%s%s",
                            k ? " " : "", rps3_design_flag_name(k));
  }
  sp = H5Screate_simple(1, &n, NULL);
  if (sp < 0) return -1;
  a = H5Acreate2(ds, "flag_masks", H5T_NATIVE_INT32, sp, H5P_DEFAULT,
                 H5P_DEFAULT);
  if (a >= 0 && H5Awrite(a, H5T_NATIVE_INT32, mask) >= 0 &&
      out_h5_attr(ds, str, "flag_meanings", words) >= 0)
    rc = 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(sp);
  return rc;
}

/* variable i: chunked [unit, ...] on the scales */
static int make_field(design_file *f, int i, const design_tile *t, size_t unit,
                      const out_meta *meta, const hid_t sc[NSC],
                      const char *coords) {
  const design_field_info *fi = &design_field_table[i];
  const double fnan = (double)NAN;
  const int32_t fneg = -1, fnotrun = OUT_STATUS_NOT_COMPUTED;
  const int64_t fneg64 = -1;
  hid_t axes[4];
  hsize_t dims[4], chunk[4];
  int rank = 0, r;
  (void)t;
  dims[0] = f->ncase;
  chunk[0] = unit < f->ncase ? unit : f->ncase;
  axes[rank++] = sc[SC_CASE];
  if (fi->shape == DS_CL) {
    dims[rank] = chunk[rank] = 3;
    axes[rank++] = sc[SC_LINK];
  } else if (fi->shape == DS_CF) {
    dims[rank] = chunk[rank] = RPS3_DESIGN_NFLAG;
    axes[rank++] = sc[SC_FLAG];
  } else if (fi->shape == DS_CP) {
    /* alpha fastest: [z_c, beta, alpha] */
    for (r = 2; r >= 0; r--) {
      dims[rank] = chunk[rank] = f->n[r];
      axes[rank++] = sc[SC_ALPHA + r];
    }
  }
  f->ds[i] = out_h5_dataset(f->file, f->str, fi->name, type_of(f, fi->type),
                            rank, dims, chunk, meta->gzip,
                            fi->type == DT_F64 ? (const void *)&fnan
                            : (i == DO_status || i == DO_task_status)
                                ? (const void *)&fnotrun
                            : fi->type == DT_I32 ? (const void *)&fneg
                            : fi->type == DT_I64 ? (const void *)&fneg64
                                                 : NULL,
                            fi->units, fi->doc);
  if (f->ds[i] < 0 || out_cf_long_name(f->ds[i], f->str, fi->long_name) < 0 ||
      (coords[0] && out_h5_attr(f->ds[i], f->str, "coordinates", coords) < 0))
    return -1;
  if ((i == DO_status || i == DO_task_status) &&
      out_cf_status(f->ds[i], f->str) < 0)
    return -1;
  if ((i == DO_flags_any || i == DO_pose_flags || i == DO_task_fail_flags) &&
      flag_attrs(f->ds[i], f->str) < 0)
    return -1;
  if (i == DO_scene_resolved &&
      out_h5_attr(f->ds[i], f->str, INPUTS_ATTR,
                  meta->inputs ? meta->inputs : "") < 0)
    return -1;
  for (r = 0; r < rank; r++)
    if (H5DSattach_scale(f->ds[i], axes[r], (unsigned)r) < 0) return -1;
  return 0;
}

design_file *design_out_create(const char *path, const scene *s,
                               const design_tile *t, size_t unit,
                               const out_meta *meta, char *err, size_t errsz) {
  design_file *f = calloc(1, sizeof *f);
  hid_t sc[NSC], ds;
  char *coords = NULL;
  const char *text = s->text;
  rps3_design_grid gr;
  int i, rc = -1;
  if (!f) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  for (i = 0; i < NSC; i++) sc[i] = -1;
  for (i = 0; i < DESIGN_NFIELD; i++) f->ds[i] = -1;
  f->ncase = s->ncase;
  design_grid(s, &gr);
  for (i = 0; i < 3; i++) f->n[i] = gr.n[i];
  f->file = -1;
  f->str = H5Tcopy(H5T_C_S1);
  if (f->str < 0 || H5Tset_size(f->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(f->str, H5T_CSET_UTF8) < 0) {
    out_fail(err, errsz, "cannot make the string type");
    goto done;
  }
  if ((f->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT)) <
      0) {
    out_fail(err, errsz, "cannot create %s", path);
    goto done;
  }
  if (root_attrs(f->file, f->str, meta, t) < 0) {
    out_fail(err, errsz, "cannot write the root attributes");
    goto done;
  }
  ds = out_h5_dataset(f->file, f->str, "scene", f->str, 0, NULL, NULL, 0, NULL,
                      "1", "the scene file (YAML), verbatim");
  i = ds < 0 || out_cf_long_name(ds, f->str, "scene file") < 0 ||
      out_h5_write_all(ds, f->str, &text) < 0;
  if (ds >= 0) H5Dclose(ds);
  if (i) {
    out_fail(err, errsz, "cannot write the scene text");
    goto done;
  }
  if (make_scales(f, s, t, sc) < 0) {
    out_fail(err, errsz, "cannot write the dimension scales");
    goto done;
  }
  if (write_swept_keys(f, s, sc[SC_CASE]) < 0) {
    out_fail(err, errsz, "cannot write the swept keys");
    goto done;
  }
  if (!(coords = out_h5_coordinates(s, 0))) {
    snprintf(err, errsz, "out of memory");
    goto done;
  }
  for (i = 0; i < DESIGN_NFIELD; i++)
    if (design_field_written(t, i) &&
        make_field(f, i, t, unit, meta, sc, coords) < 0) {
      out_fail(err, errsz, "cannot create dataset %s",
               design_field_table[i].name);
      goto done;
    }
  rc = 0;
done:
  free(coords);
  for (i = 0; i < NSC; i++)
    if (sc[i] >= 0) H5Dclose(sc[i]);
  if (rc == 0) return f;
  design_out_close(f, NULL, 0);
  return NULL;
}

int design_out_write(design_file *f, const design_tile *t, size_t c0, size_t nc,
                     char *err, size_t errsz) {
  int i;
  for (i = 0; i < DESIGN_NFIELD; i++) {
    hsize_t start[4] = {0, 0, 0, 0}, count[4];
    hid_t fs, ms;
    int rank, r, rc;
    if (f->ds[i] < 0) continue;
    fs = H5Dget_space(f->ds[i]);
    if (fs < 0) {
      out_fail(err, errsz, "cannot write %s", design_field_table[i].name);
      return -1;
    }
    rank = H5Sget_simple_extent_dims(fs, count, NULL);
    start[0] = c0;
    count[0] = nc;
    for (r = 1; r < rank; r++) start[r] = 0;
    ms = H5Screate_simple(rank, count, NULL);
    rc = ms >= 0 &&
         H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0;
    if (rc && design_field_table[i].type == DT_STR) {
      /* empty strings, not NULL pointers, where nothing was said */
      char **p = t->buf[i];
      size_t j;
      for (j = 0; j < nc; j++)
        if (!p[j]) {
          p[j] = calloc(1, 1);
          if (!p[j]) rc = 0;
        }
    }
    rc = rc && H5Dwrite(f->ds[i], type_of(f, design_field_table[i].type), ms,
                        fs, H5P_DEFAULT, t->buf[i]) >= 0;
    if (ms >= 0) H5Sclose(ms);
    H5Sclose(fs);
    if (!rc) {
      out_fail(err, errsz, "cannot write %s of designs %zu-%zu",
               design_field_table[i].name, c0, c0 + nc - 1);
      return -1;
    }
  }
  return 0;
}

int design_out_close(design_file *f, char *err, size_t errsz) {
  int i, rc = 0;
  if (!f) return 0;
  for (i = 0; i < DESIGN_NFIELD; i++)
    if (f->ds[i] >= 0 && H5Dclose(f->ds[i]) < 0) rc = -1;
  if (f->file >= 0 && H5Fclose(f->file) < 0) rc = -1;
  if (f->str >= 0) H5Tclose(f->str);
  if (rc < 0 && err) out_fail(err, errsz, "cannot close the file");
  free(f);
  return rc;
}

void design_schema_print(void) {
  static const char *const dims[] = {"case", "case, link", "case, flag",
                                     "case, z_c, beta, alpha"};
  static const char *const types[] = {"float64", "int32", "int64", "string"};
  static const char *const when[] = {"always", "with a trajectory",
                                     "design.per_pose"};
  int i;
  printf(
      "| design variable | dimensions | type | units | written | "
      "description |\n");
  printf("|---|---|---|---|---|---|\n");
  for (i = 0; i < DESIGN_NFIELD; i++) {
    const design_field_info *fi = &design_field_table[i];
    printf("| `%s` | %s | %s | %s | %s | %s |\n", fi->name, dims[fi->shape],
           types[fi->type], fi->units, when[fi->when], fi->doc);
  }
}
