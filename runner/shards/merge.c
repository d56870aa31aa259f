/*
 * merge.c - see merge.h.  Chunks are copied with H5Dread_chunk and
 * H5Dwrite_chunk: as stored, compressed or not, so merging costs a read and
 * a write of the bytes and nothing else.  Two cases go by value, through
 * the memory type, one chunk at a time: variable-length strings (message,
 * scene_resolved), which live on the file's global heap and not in the
 * chunk, and a part whose filters differ from the merged file's (parts run
 * with different --gzip).  Memory is one chunk.
 */
#include "merge.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "output/output.h"
#include "scene/inputs.h"
#include "verify.h"

/* H5Ovisit: the chunked datasets, by name */
static herr_t collect_chunked(hid_t root, const char *name,
                              const H5O_info_t *oi, void *data) {
  merge_chunked *l = data;
  hid_t ds, dcpl;
  int rc = 0;
  if (oi->type != H5O_TYPE_DATASET) return 0;
  if ((ds = H5Dopen2(root, name, H5P_DEFAULT)) < 0) return -1;
  dcpl = H5Dget_create_plist(ds);
  if (dcpl >= 0 && H5Pget_layout(dcpl) == H5D_CHUNKED) {
    if (l->n == MERGE_MAX_CHUNKED || strlen(name) >= sizeof l->name[0])
      rc = -1;
    else
      strcpy(l->name[l->n++], name);
  }
  shard_h5_close(2, dcpl, ds);
  return rc;
}

/* the file at path opened with flags, or -1 with err set */
static hid_t open_file(const char *path, unsigned flags, char *err,
                       size_t errsz) {
  hid_t f = H5Fopen(path, flags, H5P_DEFAULT);
  if (f < 0) out_fail(err, errsz, "%s: cannot open", path);
  return f;
}

int merge_shard_of(const char *path, size_t *k, size_t *n, char *err,
                   size_t errsz) {
  hid_t f = open_file(path, H5F_ACC_RDONLY, err, errsz);
  char *v, *content, tail;
  unsigned long kk, nn;
  int rc = -1;
  if (f < 0) return -1;
  v = out_h5_read_text(f, MERGE_SHARD_ATTR, 1);
  content = out_h5_read_text(f, "content", 1);
  H5Fclose(f);
  /* a simulation (output.h) is never a part: say so by name */
  if (content && strcmp(content, "simulation") == 0)
    snprintf(err, errsz,
             "%s: a simulation file (its scene has a simulate section): "
             "simulated scenes are not sharded, there is nothing to merge",
             path);
  else if (!v || sscanf(v, "%lu/%lu%c", &kk, &nn, &tail) != 2 || nn < 1 ||
           kk >= nn)
    snprintf(err, errsz,
             "%s: not a part file (no root attribute %s = \"K/N\"; write parts "
             "with rps3-run --shard K/N)",
             path, MERGE_SHARD_ATTR);
  else {
    *k = kk;
    *n = nn;
    rc = 0;
  }
  free(v);
  free(content);
  return rc;
}

/* shape and chunk shape of a dataset; rank or -1 */
static int shape_of(hid_t ds, hsize_t dims[H5S_MAX_RANK],
                    hsize_t chunk[H5S_MAX_RANK]) {
  hid_t sp = H5Dget_space(ds), dcpl = H5Dget_create_plist(ds);
  int rank = -1;
  if (sp >= 0 && dcpl >= 0) {
    rank = H5Sget_simple_extent_dims(sp, dims, NULL);
    if (rank < 1 || H5Pget_chunk(dcpl, rank, chunk) != rank) rank = -1;
  }
  shard_h5_close(2, sp, dcpl);
  return rank;
}

/* The rank of dataset `name` of the open files fa and fb when both have it
   with the same shape and chunks (*dims, *chunk: fa's), else -1 with err
   saying that b_path (file fb) is not a part of the same run. */
static int same_layout(hid_t fa, hid_t fb, const char *name,
                       hsize_t dims[H5S_MAX_RANK], hsize_t chunk[H5S_MAX_RANK],
                       const char *b_path, char *err, size_t errsz) {
  hid_t a = H5Dopen2(fa, name, H5P_DEFAULT), b = -1;
  hsize_t bdims[H5S_MAX_RANK], bchunk[H5S_MAX_RANK];
  int rank = -1;
  if (a >= 0 && H5Lexists(fb, name, H5P_DEFAULT) > 0 &&
      (b = H5Dopen2(fb, name, H5P_DEFAULT)) >= 0) {
    rank = shape_of(a, dims, chunk);
    if (rank < 1 || shape_of(b, bdims, bchunk) != rank ||
        memcmp(dims, bdims, (size_t)rank * sizeof *dims) ||
        memcmp(chunk, bchunk, (size_t)rank * sizeof *chunk))
      rank = -1;
  }
  if (rank < 0) {
    H5Eclear2(H5E_DEFAULT);
    snprintf(err, errsz,
             "%s: dataset %s missing or of another shape or chunks: not a part "
             "of the same run",
             b_path, name);
  }
  shard_h5_close(2, b, a);
  return rank;
}

/* what a merge copies into, and the chunk buffer, grown as needed */
typedef struct {
  hid_t dst;
  void *p;
  size_t size;
} copy_ctx;

/* 1 when two datasets have the same filters (the same chunk encoding) */
static int same_filters(hid_t a, hid_t b) {
  hid_t pa = H5Dget_create_plist(a), pb = H5Dget_create_plist(b);
  int i, n = -1, same = 0;
  if (pa >= 0 && pb >= 0) {
    n = H5Pget_nfilters(pa);
    same = n >= 0 && n == H5Pget_nfilters(pb);
  }
  for (i = 0; same && i < n; i++) {
    unsigned fa, fb, va[8], vb[8];
    size_t na = 8, nb = 8;
    H5Z_filter_t ia =
        H5Pget_filter2(pa, (unsigned)i, &fa, &na, va, 0, NULL, NULL);
    H5Z_filter_t ib =
        H5Pget_filter2(pb, (unsigned)i, &fb, &nb, vb, 0, NULL, NULL);
    same = ia >= 0 && ia == ib && na == nb && na <= 8 &&
           memcmp(va, vb, na * sizeof *va) == 0;
  }
  shard_h5_close(2, pa, pb);
  return same;
}

/* copy the chunk at `off` if src has it: as stored when `raw`, else by
   value */
static int copy_chunk(hid_t dst, hid_t src, const merge_rows *r,
                      const hsize_t *off, int raw, copy_ctx *cb) {
  unsigned mask = 0;
  uint32_t filters = 0;
  haddr_t addr;
  hsize_t size = 0, count[H5S_MAX_RANK];
  int d;
  if (H5Dget_chunk_info_by_coord(src, off, &mask, &addr, &size) < 0) return -1;
  if (size == 0) return 0;
  if (!raw) {
    /* by value (see the top): the chunk's region, cut at the dataset's edge */
    hid_t ftype = H5Dget_type(src), fd = H5Dget_space(dst), type = -1, ms = -1;
    int rc = -1;
    for (d = 0; d < r->rank; d++)
      count[d] =
          r->dims[d] - off[d] < r->chunk[d] ? r->dims[d] - off[d] : r->chunk[d];
    if (ftype >= 0) type = H5Tget_native_type(ftype, H5T_DIR_ASCEND);
    if (type >= 0)
      ms = verify_read_block(src, type, r->rank, off, count, &cb->p, &cb->size);
    if (ms >= 0 && fd >= 0 &&
        H5Sselect_hyperslab(fd, H5S_SELECT_SET, off, NULL, count, NULL) >= 0)
      rc = H5Dwrite(dst, type, ms, fd, H5P_DEFAULT, cb->p) < 0 ? -1 : 0;
    if (ms >= 0 && H5Tis_variable_str(type) > 0)
      H5Dvlen_reclaim(type, ms, H5P_DEFAULT, cb->p);
    shard_h5_close(4, type, ftype, fd, ms);
    return rc;
  }
  if ((size_t)size > cb->size) {
    void *p = realloc(cb->p, (size_t)size);
    if (!p) return -1;
    cb->p = p;
    cb->size = (size_t)size;
  }
  if (H5Dread_chunk(src, H5P_DEFAULT, off, &filters, cb->p) < 0 ||
      H5Dwrite_chunk(dst, H5P_DEFAULT, filters, off, (size_t)size, cb->p) < 0)
    return -1;
  return 0;
}

/* the next chunk of the row at off[0], an odometer over the other axes;
   0 after the row's last */
static int next_chunk(hsize_t *off, const merge_rows *r) {
  int d;
  for (d = r->rank - 1; d >= 1; d--) {
    off[d] += r->chunk[d];
    if (off[d] < r->dims[d]) return 1;
    off[d] = 0;
  }
  return 0;
}

/* merge_rows_fn of a merge: the chunk rows r % n == k of the dataset, each
   chunk of them, into dst */
static int copy_rows(void *ctx, const merge_rows *r, char *err, size_t errsz) {
  copy_ctx *c = ctx;
  hid_t dst = H5Dopen2(c->dst, r->name, H5P_DEFAULT);
  hid_t src = H5Dopen2(r->part, r->name, H5P_DEFAULT);
  hid_t type = src >= 0 ? H5Dget_type(src) : -1;
  hsize_t off[H5S_MAX_RANK] = {0}, row;
  hsize_t nrow = (r->dims[0] + r->chunk[0] - 1) / r->chunk[0];
  int rc = dst >= 0 && type >= 0 ? 0 : -1, raw;
  /* chunks as stored when both encode them alike; strings by value */
  raw = rc == 0 && H5Tis_variable_str(type) == 0 && same_filters(dst, src);
  for (row = r->k; rc == 0 && row < nrow; row += r->n) {
    off[0] = row * r->chunk[0];
    /* windows after a failing sample are never written: they read as the
       fill value */
    do {
      if (copy_chunk(dst, src, r, off, raw, c) < 0) {
        out_fail(err, errsz, "%s: cannot copy a chunk of %s at case %llu",
                 r->path, r->name, (unsigned long long)off[0]);
        rc = -1;
      }
    } while (rc == 0 && next_chunk(off, r));
  }
  shard_h5_close(3, type, src, dst);
  return rc;
}

/* the statuses of the chunk rows r % n == k, read a block of rows at a
   time: one chunk row when n > 1, else chunk rows up to RUN_ROWS rows */
int merge_count_failed(hid_t file, size_t k, size_t n, size_t *nfailed,
                       size_t *nunset, size_t *first_unset) {
  enum { RUN_ROWS = 65536 };
  hid_t ds = H5Dopen2(file, "status", H5P_DEFAULT), fs = -1, pl = -1, ms;
  hsize_t dims = 0, c0 = 0, span, start, count;
  void *buf = NULL;
  size_t cap = 0, i;
  int rc = -1;
  *nfailed = *nunset = 0;
  if (ds < 0 || (fs = H5Dget_space(ds)) < 0 ||
      (pl = H5Dget_create_plist(ds)) < 0 ||
      H5Sget_simple_extent_dims(fs, &dims, NULL) != 1)
    goto done;
  /* a joined file's status is virtual: no chunks, read in runs */
  if (H5Pget_layout(pl) != H5D_CHUNKED)
    c0 = RUN_ROWS;
  else if (H5Pget_chunk(pl, 1, &c0) != 1 || c0 < 1)
    goto done;
  span = n > 1 || c0 >= RUN_ROWS ? c0 : c0 * (RUN_ROWS / c0);
  for (start = k * c0; start < dims; start += n * span) {
    const int32_t *st;
    count = dims - start < span ? dims - start : span;
    ms = verify_read_block(ds, H5T_NATIVE_INT32, 1, &start, &count, &buf, &cap);
    if (ms < 0) goto done;
    H5Sclose(ms);
    for (st = buf, i = 0; i < (size_t)count; i++) {
      *nfailed += st[i] != 0;
      if (st[i] == OUT_STATUS_NOT_COMPUTED && (*nunset)++ == 0 && first_unset)
        *first_unset = (size_t)start + i;
    }
  }
  rc = 0;
done:
  free(buf);
  shard_h5_close(3, pl, fs, ds);
  return rc;
}

int merge_part_check(const char *path, size_t k, size_t n, const char *text0,
                     char *err, size_t errsz) {
  size_t kk, nn, nfailed, unset, first = 0;
  hid_t f;
  char *text = NULL;
  int rc = -1;
  if (merge_shard_of(path, &kk, &nn, err, errsz)) return -1;
  if (kk != k || nn != n) {
    snprintf(err, errsz, "%s is shard %zu/%zu, not %zu/%zu", path, kk, nn, k,
             n);
    return -1;
  }
  if ((f = open_file(path, H5F_ACC_RDONLY, err, errsz)) < 0) return -1;
  if (text0 &&
      (!(text = out_h5_read_text(f, "scene", 0)) || strcmp(text, text0) != 0))
    snprintf(err, errsz, "%s: not a part of the same scene", path);
  else if (merge_count_failed(f, k, n, &nfailed, &unset, &first) < 0)
    out_fail(err, errsz, "%s: cannot read status", path);
  /* every case of the part has a status: OUT_STATUS_NOT_COMPUTED is the
     fill value of a case never written (a part killed before its end) */
  else if (unset)
    snprintf(err, errsz,
             "%s: case %zu was never written: the part is incomplete", path,
             first);
  else
    rc = 0;
  free(text);
  H5Fclose(f);
  return rc;
}

int merge_each_part(hid_t ref, const char *ref_path, const char *rec_is,
                    const char *const *part, size_t k0, size_t n,
                    merge_chunked *list, merge_rows_fn fn, void *ctx, char *err,
                    size_t errsz) {
  char *text = out_h5_read_text(ref, "scene", 0);
  char *inputs = out_h5_read_text(ref, INPUTS_ATTR, 1);
  merge_rows r;
  size_t k;
  int rc = -1;
  list->n = 0;
  if (!text ||
      H5Ovisit(ref, H5_INDEX_NAME, H5_ITER_INC, collect_chunked, list) < 0 ||
      list->n == 0) {
    out_fail(err, errsz, "%s: not an rps3-run file", ref_path);
    goto done;
  }
  /* complete, of the same scene byte for byte and the same content of
     every file it reads (inputs.h) */
  for (k = k0; k < n; k++)
    if (merge_part_check(part[k], k, n, text, err, errsz) ||
        verify_inputs_as(part[k], inputs, rec_is, err, errsz))
      goto done;
  for (r.n = n, k = k0; k < n; k++) {
    r.k = k;
    r.path = part[k];
    if ((r.part = open_file(part[k], H5F_ACC_RDONLY, err, errsz)) < 0)
      goto done;
    for (r.j = 0; r.j < list->n; r.j++) {
      r.name = list->name[r.j];
      r.rank =
          same_layout(ref, r.part, r.name, r.dims, r.chunk, r.path, err, errsz);
      if (r.rank < 1 || fn(ctx, &r, err, errsz) < 0) break;
    }
    if (H5Fclose(r.part) < 0 && r.j == list->n) {
      out_fail(err, errsz, "%s: cannot close", part[k]);
      goto done;
    }
    if (r.j < list->n) goto done;
  }
  rc = 0;
done:
  free(text);
  free(inputs);
  return rc;
}

int merge_parts(const char *dst, const char *const *part, size_t n,
                const char *command_line, size_t *nfailed, char *err,
                size_t errsz) {
  merge_chunked list;
  copy_ctx c = {-1, NULL, 0};
  size_t unset;
  int rc = -1;
  if ((c.dst = open_file(dst, H5F_ACC_RDWR, err, errsz)) < 0) return -1;
  if (merge_each_part(c.dst, dst, "part 0 read", part, 1, n, &list, copy_rows,
                      &c, err, errsz))
    goto done;
  /* a whole file now: not a part, made by this command */
  if ((H5Aexists(c.dst, MERGE_SHARD_ATTR) > 0 &&
       H5Adelete(c.dst, MERGE_SHARD_ATTR) < 0) ||
      out_stamp(c.dst, command_line) < 0) {
    out_fail(err, errsz, "%s: cannot write the root attributes", dst);
    goto done;
  }
  if (merge_count_failed(c.dst, 0, 1, nfailed, &unset, NULL) < 0) {
    out_fail(err, errsz, "%s: cannot read status", dst);
    goto done;
  }
  rc = 0;
done:
  free(c.p);
  if (H5Fclose(c.dst) < 0 && rc == 0) {
    out_fail(err, errsz, "%s: cannot close", dst);
    rc = -1;
  }
  return rc;
}

int merge_copy_file(const char *from, const char *to, char *err, size_t errsz) {
  FILE *in = fopen(from, "rb"), *out = in ? fopen(to, "wb") : NULL;
  char buf[1 << 16];
  size_t got = 0;
  int rc = -1;
  if (!in)
    snprintf(err, errsz, "%s: %s", from, strerror(errno));
  else if (!out)
    snprintf(err, errsz, "cannot create %s: %s", to, strerror(errno));
  else {
    while ((got = fread(buf, 1, sizeof buf, in)) > 0 &&
           fwrite(buf, 1, got, out) == got)
      continue;
    if (got > 0)
      snprintf(err, errsz, "cannot write %s: %s", to, strerror(errno));
    else if (ferror(in))
      snprintf(err, errsz, "cannot read %s", from);
    else
      rc = 0;
  }
  if (out && fclose(out) != 0 && rc == 0) {
    snprintf(err, errsz, "cannot write %s: %s", to, strerror(errno));
    rc = -1;
  }
  if (in) fclose(in);
  return rc;
}
