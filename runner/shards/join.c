/*
 * join.c - join_vds (merge.h).  The objects of part 0 are walked once: groups
 * are made again, datasets without chunks are copied (H5Ocopy, without their
 * attributes), chunked ones become virtual; then every attribute is copied
 * but the dimension-scale bookkeeping (CLASS, NAME, DIMENSION_LIST,
 * REFERENCE_LIST), whose object references only mean something inside
 * their own file: a second walk makes the same scales again
 * (H5DSset_scale) and attaches them to the same dimensions.
 */
/* realpath() and dirname() are XSI */
#define _XOPEN_SOURCE 700

#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>
#include <hdf5_hl.h>

#include "merge.h"
#include "output/output.h"
#include "verify.h"

/* what a walk over part 0 needs */
typedef struct {
  hid_t src;               /* part 0 */
  hid_t dst;               /* the joined file */
  const char *const *part; /* the part files, by shard */
  char **link;             /* their names as stored in the virtual maps */
  const char *link_dir;    /* the directory of dst */
  char *err;
  size_t errsz;
  merge_chunked list;            /* the chunked datasets */
  hid_t dcpl[MERGE_MAX_CHUNKED]; /* their virtual maps, by list index */
} walk;

/* copy attribute `name` of object `from` to object `to` (H5Aiterate) */
static herr_t copy_attr(hid_t from, const char *name, const H5A_info_t *ai,
                        void *to) {
  hid_t a = -1, ftype = -1, mtype = -1, sp = -1, b = -1;
  hssize_t npt;
  void *buf = NULL;
  herr_t rc = -1;
  (void)ai;
  if (strcmp(name, "CLASS") == 0 || strcmp(name, "NAME") == 0 ||
      strcmp(name, "DIMENSION_LIST") == 0 ||
      strcmp(name, "REFERENCE_LIST") == 0 ||
      strcmp(name, MERGE_SHARD_ATTR) == 0)
    return 0;
  if ((a = H5Aopen(from, name, H5P_DEFAULT)) < 0 ||
      (ftype = H5Aget_type(a)) < 0 ||
      (mtype = H5Tget_native_type(ftype, H5T_DIR_ASCEND)) < 0 ||
      (sp = H5Aget_space(a)) < 0 ||
      (npt = H5Sget_simple_extent_npoints(sp)) < 0)
    goto done;
  buf = calloc(npt > 0 ? (size_t)npt : 1, H5Tget_size(mtype));
  if (!buf || H5Aread(a, mtype, buf) < 0) goto done;
  b = H5Acreate2(*(hid_t *)to, name, ftype, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (b >= 0 && H5Awrite(b, mtype, buf) >= 0) rc = 0;
  if (H5Tdetect_class(mtype, H5T_VLEN) > 0 || H5Tis_variable_str(mtype) > 0)
    H5Dvlen_reclaim(mtype, sp, H5P_DEFAULT, buf);
done:
  free(buf);
  shard_h5_close(5, b, sp, mtype, ftype, a);
  return rc;
}

static int copy_attrs(hid_t from, hid_t to) {
  hsize_t idx = 0;
  return H5Aiterate2(from, H5_INDEX_NAME, H5_ITER_INC, &idx, copy_attr, &to) < 0
             ? -1
             : 0;
}

/* the name of `path` as the joined file in `dir` stores it: relative to
   dir when below it, else absolute (malloc'd; NULL when it cannot be
   resolved) */
static char *link_name(const char *path, const char *dir) {
  char *p = realpath(path, NULL), *d = realpath(dir, NULL);
  size_t nd = d ? strlen(d) : 0;
  if (p && !d) {
    free(p);
    p = NULL;
  }
  if (p && nd > 1 && strncmp(p, d, nd) == 0 && p[nd] == '/')
    memmove(p, p + nd + 1, strlen(p + nd));
  free(d);
  return p;
}

/* map rows [r0 c0, ...) of part k, `count` blocks of `block` rows every
   n c0 rows and the other axes whole, to the same rows of the virtual
   dataset */
static int map_block(hid_t dcpl, hid_t vsp, hid_t ssp, const merge_rows *r,
                     hsize_t r0, hsize_t count, hsize_t block, const walk *w) {
  hsize_t start[H5S_MAX_RANK] = {0}, stride[H5S_MAX_RANK], cnt[H5S_MAX_RANK],
          blk[H5S_MAX_RANK];
  int d;
  for (d = 0; d < r->rank; d++) {
    stride[d] = 1;
    cnt[d] = 1;
    blk[d] = r->dims[d];
  }
  start[0] = r0 * r->chunk[0];
  stride[0] = (hsize_t)r->n * r->chunk[0];
  cnt[0] = count;
  blk[0] = block;
  return H5Sselect_hyperslab(vsp, H5S_SELECT_SET, start, stride, cnt, blk) <
                     0 ||
                 H5Sselect_hyperslab(ssp, H5S_SELECT_SET, start, stride, cnt,
                                     blk) < 0 ||
                 H5Pset_virtual(dcpl, vsp, w->link[r->k], r->name, ssp) < 0
             ? -1
             : 0;
}

/* a virtual dataset's dcpl with the fill value of the part's dataset ds,
   so that what no part holds reads as "not run" (there is none once every
   part is checked); or -1 */
static hid_t virtual_dcpl(hid_t ds) {
  hid_t type = H5Dget_type(ds), spl = H5Dget_create_plist(ds), mtype = -1;
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5D_fill_value_t fv;
  void *fill = NULL;
  int ok = type >= 0 && spl >= 0 && dcpl >= 0;
  if (ok && H5Pfill_value_defined(spl, &fv) >= 0 &&
      fv == H5D_FILL_VALUE_USER_DEFINED)
    ok = (mtype = H5Tget_native_type(type, H5T_DIR_ASCEND)) >= 0 &&
         (fill = calloc(1, H5Tget_size(mtype))) != NULL &&
         H5Pget_fill_value(spl, mtype, fill) >= 0 &&
         H5Pset_fill_value(dcpl, mtype, fill) >= 0;
  if (fill && mtype >= 0 && H5Tis_variable_str(mtype) > 0)
    H5free_memory(*(char **)fill);
  free(fill);
  shard_h5_close(3, mtype, spl, type);
  if (!ok) shard_h5_close(1, dcpl);
  return ok ? dcpl : -1;
}

/* merge_rows_fn of a join: shard k's rows of the dataset into its virtual
   map (merge.h) */
static int map_rows(void *ctx, const merge_rows *r, char *err, size_t errsz) {
  walk *w = ctx;
  hid_t ds = H5Dopen2(r->part, r->name, H5P_DEFAULT);
  hid_t vsp = ds >= 0 ? H5Dget_space(ds) : -1, ssp = H5Scopy(vsp);
  hid_t *dcpl = &w->dcpl[r->j];
  hsize_t c0 = r->chunk[0], n = (hsize_t)r->n, k = (hsize_t)r->k;
  hsize_t nrow = (r->dims[0] + c0 - 1) / c0;
  hsize_t tail = r->dims[0] - (nrow - 1) * c0; /* rows of the last one */
  hsize_t full = nrow - (tail < c0);           /* chunk rows of c0 rows */
  hsize_t nfull = full > k ? (full - k + n - 1) / n : 0;
  int rc = -1;
  if (r->j == 0 && !(w->link[k] = link_name(r->path, w->link_dir)))
    snprintf(err, errsz, "%s: cannot resolve its path", r->path);
  else if (ssp >= 0 && (*dcpl >= 0 || (*dcpl = virtual_dcpl(ds)) >= 0) &&
           (nfull == 0 ||
            map_block(*dcpl, vsp, ssp, r, k, nfull, c0, w) == 0) &&
           (tail == c0 || (nrow - 1) % n != k ||
            map_block(*dcpl, vsp, ssp, r, nrow - 1, 1, tail, w) == 0))
    rc = 0;
  else
    out_fail(err, errsz, "cannot make the virtual dataset %s", r->name);
  shard_h5_close(3, ssp, vsp, ds);
  return rc;
}

/* the chunked dataset o of part 0 as a virtual dataset over the parts, by
   its map (map_rows); or -1 */
static hid_t make_virtual(const walk *w, hid_t o, const char *name) {
  hid_t type = H5Dget_type(o), sp = H5Dget_space(o), ds = -1;
  int j = 0;
  while (j < w->list.n && strcmp(w->list.name[j], name) != 0) j++;
  if (j < w->list.n && type >= 0 && sp >= 0)
    ds = H5Dcreate2(w->dst, name, type, sp, H5P_DEFAULT, w->dcpl[j],
                    H5P_DEFAULT);
  if (ds < 0)
    out_fail(w->err, w->errsz, "cannot make the virtual dataset %s", name);
  shard_h5_close(2, sp, type);
  return ds;
}

/* first walk: every object of part 0 into the joined file (H5Ovisit) */
static herr_t make_object(hid_t root, const char *name, const H5O_info_t *oi,
                          void *data) {
  const walk *w = data;
  hid_t o, d = -1, pl = -1;
  int rc = -1;
  if (strcmp(name, ".") == 0) return 0;
  if (oi->type != H5O_TYPE_GROUP && oi->type != H5O_TYPE_DATASET) {
    snprintf(w->err, w->errsz, "%s: object %s is neither a group nor a dataset",
             w->part[0], name);
    return -1;
  }
  if ((o = H5Oopen(root, name, H5P_DEFAULT)) < 0) goto io;
  if (oi->type == H5O_TYPE_GROUP)
    d = H5Gcreate2(w->dst, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  else if ((pl = H5Dget_create_plist(o)) >= 0 &&
           H5Pget_layout(pl) == H5D_CHUNKED) {
    if ((d = make_virtual(w, o, name)) < 0) goto done;
  } else {
    hid_t cp = H5Pcreate(H5P_OBJECT_COPY);
    if (cp >= 0 && H5Pset_copy_object(cp, H5O_COPY_WITHOUT_ATTR_FLAG) >= 0 &&
        H5Ocopy(root, name, w->dst, name, cp, H5P_DEFAULT) >= 0)
      d = H5Oopen(w->dst, name, H5P_DEFAULT);
    if (cp >= 0) H5Pclose(cp);
  }
  if (d >= 0 && copy_attrs(o, d) == 0) rc = 0;
io:
  if (rc < 0)
    out_fail(w->err, w->errsz, "cannot copy %s of %s", name, w->part[0]);
done:
  shard_h5_close(3, pl, d, o);
  return rc < 0 ? -1 : 0;
}

/* H5DSiterate_scales: the same scale on the same dimension of the joined
   file's dataset, to[0] the joined file and to[1] the dataset */
static herr_t attach_scale(hid_t ds, unsigned dim, hid_t scale, void *data) {
  const hid_t *to = data;
  char path[1024], sname[256];
  hid_t s = -1;
  herr_t rc = -1;
  ssize_t len;
  (void)ds;
  if (H5Iget_name(scale, path, sizeof path) <= 0 ||
      (s = H5Dopen2(to[0], path, H5P_DEFAULT)) < 0)
    return -1;
  if (H5DSis_scale(s) <= 0) {
    len = H5DSget_scale_name(scale, sname, sizeof sname);
    if (len < 0 || (size_t)len >= sizeof sname ||
        H5DSset_scale(s, len > 0 ? sname : NULL) < 0)
      goto done;
  }
  rc = H5DSattach_scale(to[1], s, dim) < 0 ? -1 : 0;
done:
  H5Dclose(s);
  return rc;
}

/* second walk: the scales, attached where part 0 has them (H5Ovisit) */
static herr_t make_scales(hid_t root, const char *name, const H5O_info_t *oi,
                          void *data) {
  const walk *w = data;
  hid_t ds = -1, sp = -1, to[2] = {w->dst, -1};
  int rank = 0, dim, rc = 0;
  if (oi->type != H5O_TYPE_DATASET) return 0;
  if ((ds = H5Dopen2(root, name, H5P_DEFAULT)) < 0 ||
      (sp = H5Dget_space(ds)) < 0 ||
      (rank = H5Sget_simple_extent_ndims(sp)) < 0 ||
      (to[1] = H5Dopen2(w->dst, name, H5P_DEFAULT)) < 0)
    rc = -1;
  for (dim = 0; rc == 0 && dim < rank; dim++)
    if (H5DSget_num_scales(ds, (unsigned)dim) > 0 &&
        H5DSiterate_scales(ds, (unsigned)dim, NULL, attach_scale, to) < 0)
      rc = -1;
  if (rc < 0)
    out_fail(w->err, w->errsz, "cannot attach the dimension scales of %s",
             name);
  shard_h5_close(3, to[1], sp, ds);
  return rc;
}

/* the joined file dst: part 0's objects, virtual datasets over the parts
   and part 0's root attributes, stamped; 0 or -1 with w->err */
static int joined_write(walk *w, const char *dst, const char *command_line) {
  /* the 1.10 file format, whatever the library: 1.12 and later encode
     hyperslab selections (the virtual maps) in a form 1.10 cannot read */
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  int ok = fapl >= 0 &&
           H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110) >= 0 &&
           (w->dst = H5Fcreate(dst, H5F_ACC_TRUNC, H5P_DEFAULT, fapl)) >= 0;
  if (fapl >= 0) H5Pclose(fapl);
  if (!ok) {
    out_fail(w->err, w->errsz, "cannot create %s", dst);
    return -1;
  }
  if (H5Ovisit(w->src, H5_INDEX_NAME, H5_ITER_INC, make_object, w) < 0 ||
      H5Ovisit(w->src, H5_INDEX_NAME, H5_ITER_INC, make_scales, w) < 0)
    return -1;
  if (copy_attrs(w->src, w->dst) < 0 || out_stamp(w->dst, command_line) < 0) {
    out_fail(w->err, w->errsz, "%s: cannot write the root attributes", dst);
    return -1;
  }
  return 0;
}

/* the failed cases, counted through the virtual datasets (the parts); 0
   or -1 with err */
static int joined_count(hid_t file, const char *dst, const char *link_dir,
                        size_t *nfailed, char *err, size_t errsz) {
  size_t unset = 0;
  if (merge_count_failed(file, 0, 1, nfailed, &unset, NULL) < 0) {
    out_fail(err, errsz, "%s: cannot read status through the parts", dst);
    return -1;
  }
  /* every part has all its statuses (checked before): a case never
     written here is a part HDF5 could not open through the virtual
     dataset (it then reads the fill value, silently) */
  if (unset) {
    snprintf(err, errsz,
             "%s: %zu cases unreadable through the virtual datasets (a part "
             "that cannot be opened from %s)",
             dst, unset, link_dir);
    return -1;
  }
  return 0;
}

int join_vds(const char *dst, const char *const *part, size_t n,
             const char *command_line, size_t *nfailed, char *err,
             size_t errsz) {
  /* the directory of dst ("." when it has none) */
  char *copy = strdup(dst), *link_dir = copy ? strdup(dirname(copy)) : NULL;
  char is0[4200];
  walk w = {-1, -1, part, NULL, link_dir, err, errsz, {{""}, 0}, {0}};
  size_t k;
  int j, rc = -1;
  w.link = calloc(n, sizeof *w.link);
  for (j = 0; j < MERGE_MAX_CHUNKED; j++) w.dcpl[j] = -1;
  snprintf(is0, sizeof is0, "%s read", part[0]);
  if (!w.link || !link_dir)
    snprintf(err, errsz, "out of memory");
  else if ((w.src = H5Fopen(part[0], H5F_ACC_RDONLY, H5P_DEFAULT)) < 0)
    out_fail(err, errsz, "%s: not an rps3-run file", part[0]);
  /* every part checked and mapped, then the file */
  else if (merge_each_part(w.src, part[0], is0, part, 0, n, &w.list, map_rows,
                           &w, err, errsz) == 0 &&
           joined_write(&w, dst, command_line) == 0) {
    H5Fclose(w.src);
    w.src = -1;
    rc = joined_count(w.dst, dst, link_dir, nfailed, err, errsz);
  }
  for (k = 0; w.link && k < n; k++) free(w.link[k]);
  for (j = 0; j < MERGE_MAX_CHUNKED; j++) shard_h5_close(1, w.dcpl[j]);
  free(w.link);
  free(link_dir);
  free(copy);
  if (w.src >= 0) H5Fclose(w.src);
  if (w.dst >= 0 && H5Fclose(w.dst) < 0 && rc == 0) {
    out_fail(err, errsz, "%s: cannot close", dst);
    rc = -1;
  }
  return rc;
}
