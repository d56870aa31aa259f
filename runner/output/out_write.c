/*
 * out_write.c - the writes of a runner file (output.h): a sweep's tiles,
 * a window of one case's samples, the per-case values of a run of cases.
 */
#include "output.h"

#include <stdio.h>
#include <stdlib.h>

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
    if ((fi->shape == OUT_C && !with_case) || f->ds[i] < 0 ||
        (fi->shape != OUT_C && b->packed))
      continue;
    if (out_h5_tile(f->ds[i], f->dxpl, out_field_type(f, fi),
                    fi->shape != OUT_C, b->cases, b->points,
                    out_block_field(b, i), c0, nc, k0, nk) < 0) {
      out_fail(err, errsz, "cannot write %s of cases %zu-%zu", fi->name, c0,
               c0 + nc - 1);
      return -1;
    }
  }
  if (f->case_time >= 0 && !b->packed &&
      out_h5_tile(f->case_time, f->dxpl, H5T_NATIVE_DOUBLE, 1, b->cases,
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
    if (out_h5_tile(f->ds[i], f->dxpl, out_field_type(f, fi), 1, 1, points,
                    buf[i], c, 1, k0, nk) < 0) {
      out_fail(err, errsz, "cannot write %s of case %zu", fi->name, c);
      return -1;
    }
  }
  if (f->case_time >= 0 && times &&
      out_h5_tile(f->case_time, f->dxpl, H5T_NATIVE_DOUBLE, 1, 1, points, times,
                  c, 1, k0, nk) < 0) {
    out_fail(err, errsz, "cannot write case_time of case %zu", c);
    return -1;
  }
  return 0;
}

int out_write_case(out_file *f, const void *const val[], size_t c0, size_t nc,
                   char *err, size_t errsz) {
  const char **str = malloc(nc * sizeof *str);
  size_t j;
  int i, rc = str ? 0 : -1;
  for (i = 0; rc == 0 && i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    const void *v = val[i];
    if (out_shape_has(fi->shape, OUT_AX_TIME) || f->ds[i] < 0) continue;
    /* empty strings, not NULL pointers, where nothing was said */
    for (j = 0; v && fi->type == OUT_STR && j < nc; j++)
      str[j] = ((const char *const *)val[i])[j]
                   ? ((const char *const *)val[i])[j]
                   : "";
    if (v && fi->type == OUT_STR) v = str;
    if (!v || out_h5_tile(f->ds[i], f->dxpl, out_field_type(f, fi), 0, nc, 1, v,
                          c0, nc, 0, 1) < 0) {
      if (nc == 1)
        out_fail(err, errsz, "cannot write %s of %s %zu", fi->name, f->row, c0);
      else
        out_fail(err, errsz, "cannot write %s of %ss %zu-%zu", fi->name, f->row,
                 c0, c0 + nc - 1);
      rc = -1;
    }
  }
  if (!str) snprintf(err, errsz, "out of memory");
  free(str);
  return rc;
}
