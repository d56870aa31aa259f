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
  if (dcpl >= 0) H5Pclose(dcpl);
  H5Dclose(ds);
  return rc;
}

int merge_list_chunked(hid_t file, merge_chunked *l) {
  l->n = 0;
  return H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC, collect_chunked, l) < 0
             ? -1
             : 0;
}

int merge_shard_of(const char *path, size_t *k, size_t *n, char *err,
                   size_t errsz) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  char *v, tail;
  unsigned long kk, nn;
  if (f < 0) {
    out_fail(err, errsz, "%s: cannot open", path);
    return -1;
  }
  v = out_h5_read_text(f, MERGE_SHARD_ATTR, 1);
  {
    /* a simulation (output.h) is never a part: say so by name */
    char *content = out_h5_read_text(f, "content", 1);
    int sim = content && strcmp(content, "simulation") == 0;
    free(content);
    if (sim) {
      H5Fclose(f);
      free(v);
      snprintf(err, errsz,
               "%s: a simulation file (its scene has a simulate "
               "section): simulated scenes are not sharded, "
               "there is nothing to merge",
               path);
      return -1;
    }
  }
  H5Fclose(f);
  if (!v || sscanf(v, "%lu/%lu%c", &kk, &nn, &tail) != 2 || nn < 1 ||
      kk >= nn) {
    snprintf(err, errsz,
             "%s: not a part file (no root attribute %s = \"K/N\"; write "
             "parts with rps3-run --shard K/N)",
             path, MERGE_SHARD_ATTR);
    free(v);
    return -1;
  }
  free(v);
  *k = kk;
  *n = nn;
  return 0;
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
  if (sp >= 0) H5Sclose(sp);
  if (dcpl >= 0) H5Pclose(dcpl);
  return rank;
}

int merge_same_layout(hid_t fa, hid_t fb, const char *name,
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
             "%s: dataset %s missing or of another shape or chunks: not a "
             "part of the same run",
             b_path, name);
  }
  if (b >= 0) H5Dclose(b);
  if (a >= 0) H5Dclose(a);
  return rank;
}

/* copy the region [off, off + count) by value: through the memory type,
   so across filters (a compressed part into a plain file) and for the
   variable-length strings, whose chunks hold heap addresses */
static int copy_region(hid_t dst, hid_t src, int rank, const hsize_t *off,
                       const hsize_t *count) {
  hid_t ftype = H5Dget_type(src), type = -1, fs = H5Dget_space(src);
  hid_t fd = H5Dget_space(dst), ms = H5Screate_simple(rank, count, NULL);
  size_t n = 1, size = 0;
  void *buf = NULL;
  int r, rc = -1;
  for (r = 0; r < rank; r++) n *= (size_t)count[r];
  if (ftype >= 0) type = H5Tget_native_type(ftype, H5T_DIR_ASCEND);
  if (type >= 0) size = H5Tget_size(type);
  if (size > 0) buf = calloc(n, size);
  if (buf && fs >= 0 && fd >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, off, NULL, count, NULL) >= 0 &&
      H5Sselect_hyperslab(fd, H5S_SELECT_SET, off, NULL, count, NULL) >= 0 &&
      H5Dread(src, type, ms, fs, H5P_DEFAULT, buf) >= 0) {
    rc = H5Dwrite(dst, type, ms, fd, H5P_DEFAULT, buf) < 0 ? -1 : 0;
    if (H5Tis_variable_str(type) > 0)
      H5Dvlen_reclaim(type, ms, H5P_DEFAULT, buf);
  }
  free(buf);
  if (type >= 0) H5Tclose(type);
  if (ftype >= 0) H5Tclose(ftype);
  if (fs >= 0) H5Sclose(fs);
  if (fd >= 0) H5Sclose(fd);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

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
  if (pa >= 0) H5Pclose(pa);
  if (pb >= 0) H5Pclose(pb);
  return same;
}

/* the chunk buffer, grown as needed */
typedef struct {
  void *p;
  size_t size;
} chunk_buf;

/* copy the chunk at `off` if src has it: as stored when `raw`, else by
   value */
static int copy_chunk(hid_t dst, hid_t src, int rank, const hsize_t *off,
                      const hsize_t *dims, const hsize_t *chunk, int raw,
                      chunk_buf *cb) {
  unsigned mask = 0;
  uint32_t filters = 0;
  haddr_t addr;
  hsize_t size = 0, count[H5S_MAX_RANK];
  int r;
  if (H5Dget_chunk_info_by_coord(src, off, &mask, &addr, &size) < 0) return -1;
  if (size == 0) return 0;
  if (!raw) {
    /* the chunk's region, cut at the dataset's edge */
    for (r = 0; r < rank; r++)
      count[r] = dims[r] - off[r] < chunk[r] ? dims[r] - off[r] : chunk[r];
    return copy_region(dst, src, rank, off, count);
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

/* copy the chunk rows r % n == k of dataset `name` from src to dst */
static int copy_dataset(hid_t fdst, hid_t fsrc, const char *name,
                        const char *src_path, size_t k, size_t n, chunk_buf *cb,
                        char *err, size_t errsz) {
  hid_t dst = -1, src = -1, type = -1;
  hsize_t ddims[H5S_MAX_RANK], dchunk[H5S_MAX_RANK], off[H5S_MAX_RANK];
  hsize_t row, nrow;
  int rank, r, raw, rc = -1;

  rank = merge_same_layout(fdst, fsrc, name, ddims, dchunk, src_path, err,
                           errsz);
  if (rank < 1 || (dst = H5Dopen2(fdst, name, H5P_DEFAULT)) < 0 ||
      (src = H5Dopen2(fsrc, name, H5P_DEFAULT)) < 0)
    goto done;
  /* chunks as stored when both encode them alike; strings by value */
  type = H5Dget_type(src);
  raw = type >= 0 && H5Tis_variable_str(type) == 0 && same_filters(dst, src);
  nrow = (ddims[0] + dchunk[0] - 1) / dchunk[0];
  for (row = k; row < nrow; row += n) {
    off[0] = row * dchunk[0];
    /* every chunk of the row: odometer over the other axes */
    for (r = 1; r < rank; r++) off[r] = 0;
    for (;;) {
      /* windows after a failing sample are never written: they read as
         the fill value */
      if (copy_chunk(dst, src, rank, off, ddims, dchunk, raw, cb) < 0) {
        out_fail(err, errsz, "%s: cannot copy a chunk of %s at case %llu",
                 src_path, name, (unsigned long long)off[0]);
        goto done;
      }
      for (r = rank - 1; r >= 1; r--) {
        off[r] += dchunk[r];
        if (off[r] < ddims[r]) break;
        off[r] = 0;
      }
      if (r < 1) break;
    }
  }
  rc = 0;
done:
  if (type >= 0) H5Tclose(type);
  if (src >= 0) H5Dclose(src);
  if (dst >= 0) H5Dclose(dst);
  return rc;
}

/* the statuses of the chunk rows r % n == k, read a block of rows at a
   time: one chunk row when n > 1, else chunk rows up to RUN_ROWS rows */
int merge_count_failed(hid_t file, size_t k, size_t n, size_t *nfailed,
                       size_t *nunset, size_t *first_unset) {
  enum { RUN_ROWS = 65536 };
  hid_t ds = H5Dopen2(file, "status", H5P_DEFAULT), fs = -1, pl = -1, ms = -1;
  hsize_t dims = 0, c0 = 0, span, start, count;
  int32_t *buf = NULL;
  int rc = -1;
  size_t i;
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
  if (!(buf = malloc((size_t)span * sizeof *buf))) goto done;
  for (start = k * c0; start < dims; start += n * span) {
    count = dims - start < span ? dims - start : span;
    if ((ms = H5Screate_simple(1, &count, NULL)) < 0 ||
        H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &count, NULL) <
            0 ||
        H5Dread(ds, H5T_NATIVE_INT32, ms, fs, H5P_DEFAULT, buf) < 0)
      goto done;
    H5Sclose(ms);
    ms = -1;
    for (i = 0; i < (size_t)count; i++) {
      *nfailed += buf[i] != 0;
      if (buf[i] == OUT_STATUS_NOT_COMPUTED && (*nunset)++ == 0 && first_unset)
        *first_unset = (size_t)start + i;
    }
  }
  rc = 0;
done:
  free(buf);
  if (ms >= 0) H5Sclose(ms);
  if (pl >= 0) H5Pclose(pl);
  if (fs >= 0) H5Sclose(fs);
  if (ds >= 0) H5Dclose(ds);
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
  if ((f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT)) < 0) {
    out_fail(err, errsz, "%s: cannot open", path);
    return -1;
  }
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

int merge_parts(const char *dst, const char *const *src, const size_t *k,
                size_t nsrc, size_t n, const char *command_line,
                size_t *nfailed, char *err, size_t errsz) {
  hid_t fd = H5Fopen(dst, H5F_ACC_RDWR, H5P_DEFAULT);
  merge_chunked list;
  chunk_buf cb = {NULL, 0};
  char *text = NULL, *inputs0 = NULL;
  size_t i, unset;
  int j, rc = -1;

  if (fd < 0) {
    out_fail(err, errsz, "%s: cannot open", dst);
    return -1;
  }
  text = out_h5_read_text(fd, "scene", 0);
  inputs0 = out_h5_read_text(fd, INPUTS_ATTR, 1);
  if (!text || merge_list_chunked(fd, &list) < 0 || list.n == 0) {
    out_fail(err, errsz, "%s: not an rps3-run file", dst);
    goto done;
  }
  for (i = 0; i < nsrc; i++) {
    hid_t fs;
    /* complete, of the same scene byte for byte and the same content of
       every file it reads (inputs.h) */
    if (merge_part_check(src[i], k[i], n, text, err, errsz) ||
        verify_inputs_as(src[i], inputs0, "part 0 read", err, errsz))
      goto done;
    if ((fs = H5Fopen(src[i], H5F_ACC_RDONLY, H5P_DEFAULT)) < 0) {
      out_fail(err, errsz, "%s: cannot open", src[i]);
      goto done;
    }
    for (j = 0; j < list.n; j++)
      if (copy_dataset(fd, fs, list.name[j], src[i], k[i], n, &cb, err, errsz) <
          0) {
        H5Fclose(fs);
        goto done;
      }
    if (H5Fclose(fs) < 0) {
      out_fail(err, errsz, "%s: cannot close", src[i]);
      goto done;
    }
  }
  /* a whole file now: not a part, made by this command */
  if ((H5Aexists(fd, MERGE_SHARD_ATTR) > 0 &&
       H5Adelete(fd, MERGE_SHARD_ATTR) < 0) ||
      out_stamp(fd, command_line) < 0) {
    out_fail(err, errsz, "%s: cannot write the root attributes", dst);
    goto done;
  }
  if (merge_count_failed(fd, 0, 1, nfailed, &unset, NULL) < 0) {
    out_fail(err, errsz, "%s: cannot read status", dst);
    goto done;
  }
  rc = 0;
done:
  free(cb.p);
  free(text);
  free(inputs0);
  if (H5Fclose(fd) < 0 && rc == 0) {
    out_fail(err, errsz, "%s: cannot close", dst);
    rc = -1;
  }
  return rc;
}

int merge_copy_file(const char *from, const char *to, char *err, size_t errsz) {
  enum { BUF = 1 << 20 };
  FILE *in = fopen(from, "rb"), *out = NULL;
  char *buf = malloc(BUF);
  size_t got;
  int rc = -1;
  if (!in || !buf) {
    snprintf(err, errsz, "%s: %s", from,
             in ? "out of memory" : strerror(errno));
    goto done;
  }
  out = fopen(to, "wb");
  if (!out) {
    snprintf(err, errsz, "cannot create %s: %s", to, strerror(errno));
    goto done;
  }
  while ((got = fread(buf, 1, BUF, in)) > 0)
    if (fwrite(buf, 1, got, out) != got) {
      snprintf(err, errsz, "cannot write %s: %s", to, strerror(errno));
      goto done;
    }
  if (ferror(in)) {
    snprintf(err, errsz, "cannot read %s", from);
    goto done;
  }
  rc = 0;
done:
  if (out && fclose(out) != 0 && rc == 0) {
    snprintf(err, errsz, "cannot write %s: %s", to, strerror(errno));
    rc = -1;
  }
  if (in) fclose(in);
  free(buf);
  return rc;
}
