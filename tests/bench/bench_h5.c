/*
 * bench_h5.c - the benchmark table as an HDF5 file that describes itself:
 * one 1-D dataset per column along the dimension `case` (a dimension scale
 * holding the case names), a `units` and a `doc` attribute on every
 * dataset, and what was run (machine, compiler, trajectory, scenes, library
 * version, time) as root attributes.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <hdf5.h>
#include <hdf5_hl.h>

#include "bench.h"
#include "rps3.h"

/* a variable-length UTF-8 string type; caller closes it */
static hid_t vlen_str(void) {
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  if (H5Tset_size(t, H5T_VARIABLE) < 0 || H5Tset_cset(t, H5T_CSET_UTF8) < 0) {
    H5Tclose(t);
    return -1;
  }
  return t;
}

static int attr_str(hid_t obj, const char *name, const char *value) {
  hid_t t = vlen_str(), s = H5Screate(H5S_SCALAR), a = -1;
  int ok = 0;
  if (t >= 0 && s >= 0) a = H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) ok = H5Awrite(a, t, &value) >= 0;
  if (a >= 0) H5Aclose(a);
  if (s >= 0) H5Sclose(s);
  if (t >= 0) H5Tclose(t);
  return ok ? 0 : -1;
}

/* a 1-D dataset of n values of memory type mtype stored as ftype, with its
   units and doc; returns the open dataset or -1 */
static hid_t dataset(hid_t file, const char *name, hid_t ftype, hid_t mtype,
                     const void *buf, int n, const char *units,
                     const char *doc) {
  hsize_t dim = (hsize_t)n;
  hid_t s = H5Screate_simple(1, &dim, NULL), ds = -1;
  if (s < 0) return -1;
  ds = H5Dcreate2(file, name, ftype, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Sclose(s);
  if (ds < 0) return -1;
  if (H5Dwrite(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0 ||
      attr_str(ds, "units", units) != 0 || attr_str(ds, "doc", doc) != 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

/* the numeric columns: name, units, doc, and where the value sits in a row */
typedef struct {
  const char *name, *units, *doc;
  int kind; /* 0 double, 1 long */
  size_t off;
} column;

#define COL_D(f, u, doc) {#f, u, doc, 0, offsetof(bench_row, f)}
#define COL_L(f, u, doc) {#f, u, doc, 1, offsetof(bench_row, f)}
static const column columns[] = {
    COL_D(median_ns, "ns", "median over batches of the time per call"),
    COL_D(p10_ns, "ns", "10th percentile over batches of the time per call"),
    COL_D(p90_ns, "ns", "90th percentile over batches of the time per call"),
    COL_D(min_ns, "ns", "fastest batch, time per call"),
    COL_D(max_ns, "ns", "slowest batch, time per call"),
    COL_D(cpu_median_ns, "ns",
          "median over batches of the thread CPU time per call"),
    COL_D(target_ns, "ns", "goal time per call (docs/performance.md); NaN: none"),
    COL_D(mean_iter, "1",
          "theta-solve iterations per call, mean over the timed calls; NaN: "
          "no theta solve"),
    COL_L(calls, "1", "calls per batch"),
    COL_L(batches, "1", "timed batches"),
    COL_L(failures, "1", "calls that did not return RPS3_OK"),
};
#undef COL_D
#undef COL_L

int bench_write_h5(const char *path, const bench_info *info,
                   const bench_row *rows, int nrows) {
  hid_t file, st = -1, scale = -1;
  const char **names = NULL, **docs = NULL;
  double *ratio = NULL, *vd = NULL;
  long *vl = NULL;
  char when[64];
  time_t now = time(NULL);
  struct tm tmv;
  size_t c;
  int i, ok = 1;

  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* report failures ourselves */
  file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) {
    fprintf(stderr, "rps3-bench: cannot create %s (does its folder exist?)\n",
            path);
    return -1;
  }
  names = malloc((size_t)nrows * sizeof(*names));
  docs = malloc((size_t)nrows * sizeof(*docs));
  ratio = malloc((size_t)nrows * sizeof(*ratio));
  vd = malloc((size_t)nrows * sizeof(*vd));
  vl = malloc((size_t)nrows * sizeof(*vl));
  st = vlen_str();
  if (!names || !docs || !ratio || !vd || !vl || st < 0) ok = 0;

  /* the dimension: case names as a dimension scale */
  for (i = 0; ok && i < nrows; i++) {
    names[i] = rows[i].name;
    docs[i] = rows[i].doc;
    ratio[i] = isnan(rows[i].target_ns) ? BENCH_NONE
                                        : rows[i].median_ns / rows[i].target_ns;
  }
  if (ok) {
    scale = dataset(file, "case", st, st, names, nrows, "1",
                    "benchmark case (dimension scale)");
    ok = scale >= 0 && H5DSset_scale(scale, "case") >= 0;
  }
  if (ok) {
    hid_t ds = dataset(file, "description", st, st, docs, nrows, "1",
                       "what one call of the case does");
    ok = ds >= 0 && H5DSattach_scale(ds, scale, 0) >= 0;
    if (ds >= 0) H5Dclose(ds);
  }
  for (c = 0; ok && c < sizeof(columns) / sizeof(columns[0]); c++) {
    const column *col = &columns[c];
    hid_t ds;
    for (i = 0; i < nrows; i++) {
      const char *row = (const char *)&rows[i];
      if (col->kind == 0)
        memcpy(&vd[i], row + col->off, sizeof(double));
      else
        memcpy(&vl[i], row + col->off, sizeof(long));
    }
    if (col->kind == 0)
      ds = dataset(file, col->name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, vd,
                   nrows, col->units, col->doc);
    else
      ds = dataset(file, col->name, H5T_STD_I64LE, H5T_NATIVE_LONG, vl, nrows,
                   col->units, col->doc);
    ok = ds >= 0 && H5DSattach_scale(ds, scale, 0) >= 0;
    if (ds >= 0) H5Dclose(ds);
  }
  if (ok) {
    hid_t ds = dataset(file, "ratio_to_target", H5T_IEEE_F64LE,
                       H5T_NATIVE_DOUBLE, ratio, nrows, "1",
                       "median_ns / target_ns; <= 1 meets the target; NaN: "
                       "no target");
    ok = ds >= 0 && H5DSattach_scale(ds, scale, 0) >= 0;
    if (ds >= 0) H5Dclose(ds);
  }

  /* what was run */
  gmtime_r(&now, &tmv);
  strftime(when, sizeof(when), "%Y-%m-%dT%H:%M:%SZ", &tmv);
  if (ok)
    ok = attr_str(file, "title", "rps3-bench: time per call of the library's "
                                 "stages") == 0 &&
         attr_str(file, "rps3_version", rps3_version()) == 0 &&
         attr_str(file, "machine", info->machine) == 0 &&
         attr_str(file, "compiler", info->compiler) == 0 &&
         attr_str(file, "trajectory", info->trajectory) == 0 &&
         attr_str(file, "scene_full", info->scene_full) == 0 &&
         attr_str(file, "scene_gravity", info->scene_gravity) == 0 &&
         attr_str(file, "scene_general", info->scene_general) == 0 &&
         attr_str(file, "clock", info->clock) == 0 &&
         attr_str(file, "created", when) == 0;

  if (scale >= 0) H5Dclose(scale);
  if (st >= 0) H5Tclose(st);
  if (H5Fclose(file) < 0) ok = 0;
  free(names);
  free(docs);
  free(ratio);
  free(vd);
  free(vl);
  if (!ok) fprintf(stderr, "rps3-bench: writing %s failed\n", path);
  return ok ? 0 : -1;
}
