/* out_h5.c - see out_h5.h (the time stamp and history are CF's,
   out_cf.c). */
#include "out_h5.h"
#include "core/h5err.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <hdf5.h>
#include <hdf5_hl.h>

void out_fail(char *err, size_t errsz, const char *fmt, ...) {
  char h5[600], what[256];
  va_list ap;
  h5_cause(h5, sizeof h5);
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  snprintf(err, errsz, "%s%s%s", what, h5[0] ? ": HDF5: " : "", h5);
}

int out_h5_attr_n(hid_t obj, const char *name, hid_t type, size_t n,
                  const void *v) {
  hsize_t dim = n;
  hid_t sp = n ? H5Screate_simple(1, &dim, NULL) : H5Screate(H5S_SCALAR), a;
  int rc = -1;
  if (sp < 0) return -1;
  a = H5Acreate2(obj, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    rc = H5Awrite(a, type, v) < 0 ? -1 : 0;
    H5Aclose(a);
  }
  H5Sclose(sp);
  return rc;
}

int out_h5_attr(hid_t obj, hid_t str, const char *name, const char *value) {
  return out_h5_attr_n(obj, name, str, 0, &value);
}

int out_h5_attrs(hid_t obj, hid_t str, const char *const (*kv)[2], size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (kv[i][1] &&
        ((H5Aexists(obj, kv[i][0]) > 0 && H5Adelete(obj, kv[i][0]) < 0) ||
         out_h5_attr(obj, str, kv[i][0], kv[i][1]) < 0))
      return -1;
  return 0;
}

/* the files' strings are UTF-8; HDF5 converts no character sets */
char *out_h5_read_text(hid_t loc, const char *name, int is_attr) {
  hid_t obj, str = H5Tcopy(H5T_C_S1);
  char *v = NULL, *copy = NULL;
  herr_t rc;
  if (str < 0 || H5Tset_size(str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(str, H5T_CSET_UTF8) < 0 ||
      (is_attr ? H5Aexists(loc, name) : H5Lexists(loc, name, H5P_DEFAULT)) <=
          0 ||
      (obj = is_attr ? H5Aopen(loc, name, H5P_DEFAULT)
                     : H5Dopen2(loc, name, H5P_DEFAULT)) < 0) {
    H5Tclose(str);
    return NULL;
  }
  if (is_attr) {
    rc = H5Aread(obj, str, &v);
    H5Aclose(obj);
  } else {
    rc = H5Dread(obj, str, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v);
    H5Dclose(obj);
  }
  if (rc >= 0 && v) {
    copy = malloc(strlen(v) + 1);
    if (copy) strcpy(copy, v);
  }
  /* the library allocated v: give it back with the library's free */
  if (v) H5free_memory(v);
  H5Tclose(str);
  return copy;
}

hid_t out_h5_dataset(hid_t file, hid_t str, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const hsize_t *chunk,
                     int gzip, const void *fill, const char *units,
                     const char *doc) {
  hid_t sp = rank ? H5Screate_simple(rank, dims, NULL) : H5Screate(H5S_SCALAR);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE), lcpl = H5Pcreate(H5P_LINK_CREATE);
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  hid_t ds = -1;
  if (sp < 0 || dcpl < 0 || lcpl < 0 || dapl < 0) goto done;
  /* tiles are whole chunks, written once: no chunk cache, so that memory
     does not hold a chunk per dataset */
  if (H5Pset_chunk_cache(dapl, 0, 0, 1.0) < 0) goto done;
  /* names such as manipulator.rho are plain names, no groups */
  if (chunk && H5Pset_chunk(dcpl, rank, chunk) < 0) goto done;
  if (chunk && gzip > 0 && H5Pset_deflate(dcpl, (unsigned)gzip) < 0) goto done;
  /* a checksum of each stored chunk (after deflate: of the bytes on disk),
     checked by every read: merge refuses a damaged part (verify.h); the
     strings' chunks hold heap references, which HDF5 does not checksum */
  if (chunk && H5Tis_variable_str(type) <= 0 && H5Pset_fletcher32(dcpl) < 0)
    goto done;
  if (fill && H5Pset_fill_value(dcpl, type, fill) < 0) goto done;
  if (H5Pset_char_encoding(lcpl, H5T_CSET_UTF8) < 0) goto done;
  ds = H5Dcreate2(file, name, type, sp, lcpl, dcpl, dapl);
  if (ds >= 0 && (out_h5_attr(ds, str, "units", units) < 0 ||
                  out_h5_attr(ds, str, "description", doc) < 0)) {
    H5Dclose(ds);
    ds = -1;
  }
done:
  if (sp >= 0) H5Sclose(sp);
  if (dcpl >= 0) H5Pclose(dcpl);
  if (lcpl >= 0) H5Pclose(lcpl);
  if (dapl >= 0) H5Pclose(dapl);
  return ds;
}

int out_h5_tile(hid_t ds, hid_t dxpl, hid_t type, int timed, size_t cases,
                size_t points, const void *buf, size_t c0, size_t nc, size_t k0,
                size_t nk) {
  hsize_t mdims[4], start[4] = {0, 0, 0, 0}, count[4], fstart[4] = {0, 0, 0, 0};
  hid_t fs = H5Dget_space(ds), ms = -1;
  int r, rank = fs < 0 ? -1 : H5Sget_simple_extent_dims(fs, count, NULL);
  int rc = -1;
  for (r = 0; r < rank; r++) mdims[r] = count[r];
  mdims[0] = cases;
  count[0] = nc;
  fstart[0] = c0;
  if (timed) {
    mdims[1] = points;
    count[1] = nk;
    fstart[1] = k0;
  }
  if (rank > 0) ms = H5Screate_simple(rank, mdims, NULL);
  if (ms >= 0 &&
      H5Sselect_hyperslab(ms, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, fstart, NULL, count, NULL) >= 0 &&
      H5Dwrite(ds, type, ms, fs, dxpl, buf) >= 0)
    rc = 0;
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

hid_t out_h5_scale(hid_t file, hid_t str, const char *name, hid_t type,
                   size_t n, const void *data, const char *units,
                   const char *doc) {
  hsize_t dim = n;
  hid_t ds =
      out_h5_dataset(file, str, name, type, 1, &dim, NULL, 0, NULL, units, doc);
  if (ds < 0) return -1;
  if ((data && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) ||
      H5DSset_scale(ds, name) < 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

void out_utc_now(char now[32]) {
  time_t t = time(NULL);
  struct tm tm;
  gmtime_r(&t, &tm);
  strftime(now, 32, "%Y-%m-%dT%H:%M:%SZ", &tm);
}
