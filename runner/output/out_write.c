/* out_write.c - the writes of a runner file (output.h). */
#include "output.h"

#include <stdio.h>
#include <stdlib.h>

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
