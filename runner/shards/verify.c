/*
 * verify.c - see verify.h.
 */
#include "verify.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/h5err.h"
#include "output/out_h5.h"
#include "scene/inputs.h"

/* bytes read at a time at most, for datasets without chunks */
#define BLOCK_BYTES (16u << 20)

typedef struct {
  char *err;
  size_t errsz;
  const char *path;
  void *buf;
  size_t cap;
} verify_ctx;

void shard_h5_close(int n, ...) {
  va_list ap;
  va_start(ap, n);
  while (n-- > 0) {
    hid_t id = va_arg(ap, hid_t);
    /* H5Idec_ref closes an id of any kind once it is the last reference */
    if (id >= 0) H5Idec_ref(id);
  }
  va_end(ap);
}

hid_t verify_read_block(hid_t ds, hid_t type, int rank, const hsize_t *off,
                        const hsize_t *count, void **buf, size_t *cap) {
  hid_t fs = H5Dget_space(ds), ms = H5Screate_simple(rank, count, NULL);
  size_t n = H5Tget_size(type);
  int r, ok;
  for (r = 0; r < rank; r++) n *= (size_t)count[r];
  if (n > *cap) {
    void *p = realloc(*buf, n);
    if (p) {
      *buf = p;
      *cap = n;
    }
  }
  ok = n <= *cap && fs >= 0 && ms >= 0 &&
       H5Sselect_hyperslab(fs, H5S_SELECT_SET, off, NULL, count, NULL) >= 0 &&
       H5Dread(ds, type, ms, fs, H5P_DEFAULT, *buf) >= 0;
  shard_h5_close(1, fs);
  if (!ok) shard_h5_close(1, ms);
  return ok ? ms : -1;
}

/* the rows read at a time: a chunk row when chunked, else as many rows as
   fit the block */
static hsize_t step_of(hid_t dcpl, int rank, const hsize_t *dims,
                       size_t esize) {
  hsize_t chunk[H5S_MAX_RANK], step;
  size_t row = 1;
  int r;
  if (H5Pget_layout(dcpl) == H5D_CHUNKED &&
      H5Pget_chunk(dcpl, rank, chunk) == rank)
    return chunk[0];
  for (r = 1; r < rank; r++) row *= (size_t)dims[r];
  step = BLOCK_BYTES / (row * esize);
  return step < 1 ? 1 : step;
}

static int verify_dataset(verify_ctx *c, hid_t ds, const char *name) {
  hid_t fs = H5Dget_space(ds), ftype = H5Dget_type(ds), type = -1;
  hid_t dcpl = H5Dget_create_plist(ds);
  hsize_t dims[H5S_MAX_RANK], start[H5S_MAX_RANK] = {0}, count[H5S_MAX_RANK];
  hsize_t step;
  size_t esize = 0;
  int rank = -1, rc = -1, r;
  if (fs >= 0) rank = H5Sget_simple_extent_dims(fs, dims, NULL);
  if (ftype >= 0) type = H5Tget_native_type(ftype, H5T_DIR_ASCEND);
  if (type >= 0) esize = H5Tget_size(type);
  if (rank < 0 || esize == 0 || dcpl < 0) goto done;
  if (rank == 0) {
    /* a scalar: the scene text (a string: one pointer) */
    void *v[1] = {NULL};
    if (esize <= sizeof v &&
        H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0) {
      rc = 0;
      if (H5Tis_variable_str(type) > 0)
        H5Dvlen_reclaim(type, fs, H5P_DEFAULT, v);
    }
    goto done;
  }
  step = step_of(dcpl, rank, dims, esize);
  for (r = 0; r < rank; r++) count[r] = dims[r];
  for (start[0] = 0; start[0] < dims[0]; start[0] += step) {
    hsize_t r0 = start[0];
    hid_t ms;
    count[0] = dims[0] - r0 < step ? dims[0] - r0 : step;
    ms = verify_read_block(ds, type, rank, start, count, &c->buf, &c->cap);
    if (ms >= 0 && H5Tis_variable_str(type) > 0)
      H5Dvlen_reclaim(type, ms, H5P_DEFAULT, c->buf);
    shard_h5_close(1, ms);
    if (ms < 0) {
      char cause[600];
      h5_cause(cause, sizeof cause);
      snprintf(c->err, c->errsz,
               "%s: dataset %s is damaged at rows %llu-%llu (%s): the part "
               "cannot be trusted; compute that shard again",
               c->path, name, (unsigned long long)r0,
               (unsigned long long)(r0 + count[0] - 1),
               cause[0] ? cause : "cannot be read");
      goto done;
    }
  }
  rc = 0;
done:
  if (rc < 0 && !c->err[0])
    snprintf(c->err, c->errsz, "%s: cannot read dataset %s", c->path, name);
  shard_h5_close(4, type, ftype, fs, dcpl);
  return rc;
}

static herr_t verify_cb(hid_t root, const char *name, const H5L_info_t *li,
                        void *data) {
  H5O_info_t oi;
  hid_t ds;
  int rc;
  (void)li;
  if (H5Oget_info_by_name(root, name, &oi, H5P_DEFAULT) < 0) return -1;
  if (oi.type != H5O_TYPE_DATASET) return 0;
  if ((ds = H5Dopen2(root, name, H5P_DEFAULT)) < 0) return -1;
  rc = verify_dataset(data, ds, name);
  H5Dclose(ds);
  return rc < 0 ? -1 : 0;
}

int verify_file(const char *path, char *err, size_t errsz) {
  verify_ctx c = {err, errsz, path, NULL, 0};
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  int rc;
  err[0] = '\0';
  if (f < 0) {
    char cause[600];
    h5_cause(cause, sizeof cause);
    snprintf(err, errsz, "%s: cannot open: HDF5: %s", path, cause);
    return -1;
  }
  rc = H5Literate(f, H5_INDEX_NAME, H5_ITER_INC, NULL, verify_cb, &c) < 0 ? -1
                                                                          : 0;
  if (rc < 0 && !err[0])
    snprintf(err, errsz, "%s: cannot read its datasets", path);
  free(c.buf);
  H5Fclose(f);
  return rc;
}

char *verify_root_attr(const char *path, const char *name) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  char *v = f >= 0 ? out_h5_read_text(f, name, 1) : NULL;
  if (f >= 0) H5Fclose(f);
  return v;
}

int verify_same_versions(const char *const *path, size_t n, char *err,
                         size_t errsz) {
  static const char *const attrs[] = {"rps3_version", "gsl_version",
                                      "hdf5_version", "yaml_version", "fields"};
  size_t a, i;
  int same = 1;
  for (a = 0; same && a < sizeof attrs / sizeof attrs[0]; a++) {
    char *v0 = verify_root_attr(path[0], attrs[a]);
    for (i = 1; same && i < n; i++) {
      char *v = verify_root_attr(path[i], attrs[a]);
      same = (!v0 && !v) || (v0 && v && strcmp(v0, v) == 0);
      if (!same)
        snprintf(err, errsz, "%s has %s %s, %s has %s %s: %s", path[0],
                 attrs[a], v0 ? v0 : "(none)", path[i], attrs[a],
                 v ? v : "(none)",
                 strcmp(attrs[a], "fields") == 0
                     ? "parts with different --fields are not merged "
                       "(compute them with the same --fields)"
                     : "parts written by different versions are not merged "
                       "(compute them with one build)");
      free(v);
    }
    free(v0);
  }
  return same ? 0 : -1;
}

/* a digest field for a message: "SHA-256 " and its first 16 digits, or
   what stands for none ("none": the record lacks the file; "not
   recorded": the file has no record) */
static const char *digest_text(const char *dig, char *buf, size_t sz) {
  if (strncmp(dig, "sha256:", 7) == 0 && strlen(dig) == 7 + 64)
    snprintf(buf, sz, "SHA-256 %.16s...", dig + 7);
  else if (strcmp(dig, "not recorded") == 0)
    snprintf(buf, sz, "unknown content (not recorded)");
  else if (strcmp(dig, "none") == 0)
    snprintf(buf, sz, "no such file read");
  else
    snprintf(buf, sz, "%s", dig);
  return buf;
}

int verify_inputs_as(const char *path, const char *rec, const char *rec_is,
                     char *err, size_t errsz) {
  char *have = verify_root_attr(path, INPUTS_ATTR);
  char key[128], file[512], dh[80], dr[80], th[96], tr[96];
  int differ = inputs_differ(have, rec, key, sizeof key, file, sizeof file, dh,
                             dr, sizeof dh);
  free(have);
  if (!differ) return 0;
  snprintf(err, errsz,
           "%s read %s %s of %s, %s %s: computed from another "
           "content of that file",
           path, key, file, digest_text(dh, th, sizeof th), rec_is,
           digest_text(dr, tr, sizeof tr));
  return -1;
}

/* the digest of key in the record rec into d: "none" when the record
   lacks the file, "not recorded" when there is no record */
static const char *digest_of(const char *rec, const char *key, char *d,
                             size_t sz) {
  char p[8];
  if (!inputs_find(rec, key, d, sz, p, sizeof p))
    snprintf(d, sz, "%s", rec ? "none" : "not recorded");
  return d;
}

/* the names of the parts i whose digest of the key is dig (at most 8,
   then how many more) on out */
static void list_parts(FILE *out, const char *const *path, char **rec, size_t n,
                       const char *key, const char *dig) {
  char d[80];
  size_t i, m = 0;
  for (i = 0; i < n; i++) {
    if (strcmp(digest_of(rec[i], key, d, sizeof d), dig) != 0) continue;
    if (m < 8) fprintf(out, "%s%s", m ? ", " : "", path[i]);
    m++;
  }
  if (m > 8) fprintf(out, " and %zu more", m - 8);
}

int verify_parts_inputs(const char *const *path, size_t n, int *bad,
                        const char *who, FILE *out) {
  char **rec = calloc(n, sizeof *rec);
  char key[128], file[512], d0[80], di[80], now[80], hex[INPUTS_HEX];
  char err[600], t[96];
  size_t i, j;
  int rc = 0, matched = 0;
  if (!rec) {
    fprintf(out, "%s: out of memory\n", who);
    return -1;
  }
  for (i = 0; i < n; i++) rec[i] = verify_root_attr(path[i], INPUTS_ATTR);
  for (i = 1; i < n; i++)
    if (inputs_differ(rec[0], rec[i], key, sizeof key, file, sizeof file, d0,
                      di, sizeof d0))
      break;
  if (i == n) goto done;
  rc = -1;
  fprintf(out,
          "%s: %s %s: the parts were computed from different "
          "contents of it, so they are not parts of one run:\n",
          who, key, file);
  /* one line a content: its digest and the parts that read it */
  for (i = 0; i < n; i++) {
    digest_of(rec[i], key, di, sizeof di);
    for (j = 0; j < i; j++)
      if (strcmp(digest_of(rec[j], key, d0, sizeof d0), di) == 0) break;
    if (j < i) continue;
    fprintf(out, "  %s: ", digest_text(di, t, sizeof t));
    list_parts(out, path, rec, n, key, di);
    fputc('\n', out);
  }
  /* the parts to compute again: those of another content than now */
  if (!file[0] || inputs_sha256(file, hex, err, sizeof err) != 0) {
    fprintf(out, "  %s now: %s\n", file[0] ? file : key,
            file[0] ? err : "not recorded");
    goto done;
  }
  snprintf(now, sizeof now, "sha256:%s", hex);
  for (i = 0; i < n; i++) {
    bad[i] = strcmp(digest_of(rec[i], key, di, sizeof di), now) != 0;
    matched |= !bad[i];
  }
  fprintf(out, "  the file now: %s%s\n", digest_text(now, t, sizeof t),
          matched ? "" : " (no part's)");
done:
  for (i = 0; i < n; i++) free(rec[i]);
  free(rec);
  return rc;
}
