/*
 * outblock.c - the schema of the output (RPS3_OUTPUT_FIELDS as a table),
 * the tile buffers a sweep fills, and the selection of fields (--fields).
 * No HDF5 here: output.c writes what this describes.
 */
#include "outblock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ the schema */

#define OUT_FIELD_ROW(id, name, files, shape, type, flags, units, long_name, \
                      doc)                                                   \
  {#name, files, shape, type, flags, units, long_name, doc},
const out_field_info out_field_table[OUT_NFIELD] = {
    RPS3_OUTPUT_FIELDS(OUT_FIELD_ROW)};
#undef OUT_FIELD_ROW

size_t out_columns(out_shape shape, int neffect) {
  switch (shape) {
  case OUT_C:
  case OUT_CT: return 1;
  case OUT_CTL:
  case OUT_CTK: return 3;
  case OUT_CTEL: return 3 * (size_t)neffect;
  }
  return 1;
}

static size_t type_size(out_type type) {
  return type == OUT_F64   ? sizeof(double)
         : type == OUT_I32 ? sizeof(int32_t)
         : type == OUT_I64 ? sizeof(int64_t)
                           : sizeof(char *);
}

/* 1 when field i is in the inverse sweep's file (a member of out_block) */
static int inv(int i) { return (out_field_table[i].files & OUT_INV) != 0; }

/* the buffer of field i of b */
void *out_block_field(const out_block *b, int i) {
  switch (i) {
#define OUT_BLOCK_CASE(id, name, files, ...) OUT_CASE_##files(id)
#define OUT_CASE_OUT_INV(id) \
  case OUT_##id: return b->id;
#define OUT_CASE_OUT_BOTH OUT_CASE_OUT_INV
#define OUT_CASE_OUT_SIM(id)
    RPS3_OUTPUT_FIELDS(OUT_BLOCK_CASE)
  default: break;
  }
  return NULL;
}

static void block_field_set(out_block *b, int i, void *p) {
  switch (i) {
#undef OUT_CASE_OUT_INV
#define OUT_CASE_OUT_INV(id) \
  case OUT_##id: b->id = p; break;
    RPS3_OUTPUT_FIELDS(OUT_BLOCK_CASE)
#undef OUT_CASE_OUT_INV
#undef OUT_CASE_OUT_BOTH
#undef OUT_CASE_OUT_SIM
#undef OUT_BLOCK_CASE
  default: break;
  }
}

/* elements of field i per slot */
static size_t slot_elems(const out_block *b, int i) {
  return out_field_table[i].shape == OUT_C
             ? 1
             : b->points * out_columns(out_field_table[i].shape, b->neffect);
}

int out_block_alloc(out_block *b, size_t cases, size_t points, int effects) {
  int i, e;
  memset(b, 0, sizeof *b);
  b->cases = cases;
  b->points = points;
  for (e = 0; e < RPS3_NEFFECT; e++)
    if (effects & (1 << e)) b->effect[b->neffect++] = e;
  /* the per-sample buffers with OUT_SLACK bytes more (out_pack) */
  for (i = 0; i < OUT_NFIELD; i++) {
    void *p;
    if (!inv(i)) continue;
    p = calloc(
        1, cases * slot_elems(b, i) * type_size(out_field_table[i].type) +
               OUT_SLACK);
    if (!p) goto fail;
    block_field_set(b, i, p);
  }
  b->t = calloc(1, cases * points * sizeof *b->t + OUT_SLACK);
  b->yaml = calloc(cases, sizeof *b->yaml);
  b->msg = calloc(cases, sizeof *b->msg);
  b->bx = calloc(OUT_BATCH * OUT_BATCH_DOUBLES, sizeof *b->bx);
  b->bi = calloc(OUT_BATCH * OUT_BATCH_INTS, sizeof *b->bi);
  b->fields = out_fields_all();
  if (!b->t || !b->yaml || !b->msg || !b->bx || !b->bi) goto fail;
  return 0;
fail:
  out_block_free(b);
  return -1;
}

void out_block_free(out_block *b) {
  size_t s;
  int i;
  if (!b) return;
  for (i = 0; i < OUT_NFIELD; i++) free(out_block_field(b, i));
  if (b->yaml)
    for (s = 0; s < b->cases; s++) scene_text_free(&b->yaml[s]);
  free(b->yaml);
  free(b->t);
  free(b->msg);
  free(b->pk_buf);
  free(b->pk);
  free(b->pk_tmp);
  free(b->bx);
  free(b->bi);
  memset(b, 0, sizeof *b);
}

void out_block_blank(out_block *b, size_t slot, size_t k) {
  size_t j;
  int i;
  for (i = 0; i < OUT_NFIELD; i++) {
    size_t cols = out_columns(out_field_table[i].shape, b->neffect);
    size_t lo = (slot * b->points + k) * cols,
           hi = (slot + 1) * b->points * cols;
    if (out_field_table[i].shape == OUT_C || !inv(i)) continue;
    if (out_field_table[i].type == OUT_F64) {
      double *p = out_block_field(b, i);
      for (j = lo; j < hi; j++) p[j] = (double)NAN;
    } else if (out_field_table[i].type == OUT_I32) {
      int32_t *p = out_block_field(b, i);
      for (j = lo; j < hi; j++) p[j] = -1;
    }
  }
  for (j = slot * b->points + k; j < (slot + 1) * b->points; j++)
    b->t[j] = (double)NAN;
}

void out_schema_print(int files) {
  static const char *const dims[] = {"case", "case, time", "case, time, link",
                                     "case, time, constraint",
                                     "case, time, effect, link"};
  static const char *const types[] = {"float64", "int32", "int64", "string"};
  int i;
  printf("| dataset | dimensions | type | units | description |\n");
  printf("|---|---|---|---|---|\n");
  for (i = 0; i < OUT_NFIELD; i++)
    if (out_field_table[i].files & files)
      printf("| `%s` | %s | %s | %s | %s |\n", out_field_table[i].name,
             dims[out_field_table[i].shape], types[out_field_table[i].type],
             out_field_table[i].units, out_field_table[i].doc);
}

/* ---------------------------------------------------------------- fields */

out_mask out_fields_of(int files) {
  out_mask m = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (out_field_table[i].files & files) m |= (out_mask)1 << i;
  return m;
}

out_mask out_fields_all(void) { return out_fields_of(OUT_INV); }

/* 1 when field i is per case and sample of the inverse sweep (a --fields
   choice), 0 when it is per case (always written: what a reader needs to
   read the rest) or not the inverse sweep's */
static int per_point(int i) {
  return out_field_table[i].shape != OUT_C && inv(i);
}

int out_fields_parse(const char *list, out_mask *mask, char *err,
                     size_t errsz) {
  const char *p = list;
  out_mask m = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (inv(i) && !per_point(i)) m |= (out_mask)1 << i;
  for (;;) {
    size_t len = strcspn(p, ",");
    int found = -1;
    for (i = 0; i < OUT_NFIELD && found < 0; i++)
      if (per_point(i) && strlen(out_field_table[i].name) == len &&
          strncmp(out_field_table[i].name, p, len) == 0)
        found = i;
    if (found < 0) {
      char names[1024];
      out_fields_text(out_fields_all(), names, sizeof names);
      snprintf(err, errsz,
               "--fields: '%.*s' is not a per-sample field; the fields are "
               "%s (status, failed_at, message, scene_resolved and the "
               "coordinates are always written)",
               (int)(len > 64 ? 64 : len), p, names);
      return -1;
    }
    m |= (out_mask)1 << found;
    if (p[len] == '\0') break;
    p += len + 1;
  }
  *mask = m;
  return 0;
}

const char *out_fields_text(out_mask mask, char *buf, size_t sz) {
  size_t n = 0;
  int i;
  buf[0] = '\0';
  for (i = 0; i < OUT_NFIELD; i++)
    if (per_point(i) && (mask >> i & 1) && n < sz)
      n += (size_t)snprintf(buf + n, sz - n, "%s%s", n ? "," : "",
                            out_field_table[i].name);
  return buf;
}
