/* out_h5.h - the HDF5 helpers of the runner's files: datasets with units
   and descriptions, dimension scales, a tile's hyperslab, errors. */
#ifndef RPS3_RUNNER_OUT_H5_H
#define RPS3_RUNNER_OUT_H5_H

#include <stddef.h>

#include <hdf5.h>

#include "scene/scene.h"

/* err = the message (printf-style) and the innermost HDF5 error, which is
   then cleared */
void out_fail(char *err, size_t errsz, const char *fmt, ...);

/* now = the time now, ISO 8601 in UTC ("2026-01-31T12:00:00Z") */
void out_utc_now(char now[32]);

/* a scalar string attribute (str: the file's UTF-8 string type); 0 or -1 */
int out_h5_attr(hid_t obj, hid_t str, const char *name, const char *value);

/* an attribute of n values of type at v, 1-D (n 0: a scalar); 0 or -1 */
int out_h5_attr_n(hid_t obj, const char *name, hid_t type, size_t n,
                  const void *v);

/* the n string attributes kv[i][0] = kv[i][1], in order, each replacing
   one of the same name; a NULL value writes none.  0 or -1 */
int out_h5_attrs(hid_t obj, hid_t str, const char *const (*kv)[2], size_t n);

/* a string attribute (is_attr 1) or the scalar string dataset `name` of
   obj, as a malloc'd string (NULL when absent or not a string) */
char *out_h5_read_text(hid_t obj, const char *name, int is_attr);

/* a dataset with units and description attributes, as the runner's own:
   chunk NULL for contiguous, else Fletcher-32 (and deflate at gzip) on
   every chunk, fill value fill (NULL: HDF5's), no chunk cache; or -1 */
hid_t out_h5_dataset(hid_t file, hid_t str, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const hsize_t *chunk,
                     int gzip, const void *fill, const char *units,
                     const char *doc);

/* a 1-D dimension scale of n values (data NULL: written later); or -1 */
hid_t out_h5_scale(hid_t file, hid_t str, const char *name, hid_t type,
                   size_t n, const void *data, const char *units,
                   const char *doc);

/* rows [c0, c0 + nc) of a dataset from slots [0, nc) of a buffer
   [cases][points][the other axes]: along axis 1 (timed 1) samples
   [k0, k0 + nk) of `points`, the other axes whole; 0 or -1 */
int out_h5_tile(hid_t ds, hid_t dxpl, hid_t type, int timed, size_t cases,
                size_t points, const void *buf, size_t c0, size_t nc, size_t k0,
                size_t nk);

/* the case and time scales and the swept values are written in runs of
   this many values: memory does not grow with the sweep */
#define OUT_AXIS_RUN 65536

#endif /* RPS3_RUNNER_OUT_H5_H */
