/* outblock.c - the schema as a table, the tile buffers and the
   selection of fields (--fields); no HDF5 (output.c writes). */
#include "outblock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OUT_FIELD_ROW(id, name, files, shape, type, flags, units, long_name, \
                      doc)                                                   \
  {#name, files, shape, type, flags, units, long_name, doc},
const out_field_info out_field_table[OUT_NFIELD] = {
    RPS3_OUTPUT_FIELDS(OUT_FIELD_ROW)};
#undef OUT_FIELD_ROW

const int out_shape_axes[][5] = {
    {OUT_AX_CASE, -1},
    {OUT_AX_CASE, OUT_AX_TIME, -1},
    {OUT_AX_CASE, OUT_AX_TIME, OUT_AX_LINK, -1},
    {OUT_AX_CASE, OUT_AX_TIME, OUT_AX_CON, -1},
    {OUT_AX_CASE, OUT_AX_TIME, OUT_AX_EFF, OUT_AX_LINK, -1},
    {OUT_AX_CASE, OUT_AX_LINK, -1},
    {OUT_AX_CASE, OUT_AX_FLAG, -1},
    {OUT_AX_CASE, OUT_AX_Z_C, OUT_AX_BETA, OUT_AX_ALPHA, -1}};

const char *const out_axis_name[OUT_NAXIS] = {"case",       "time",   "link",
                                              "constraint", "effect", "flag",
                                              "alpha",      "beta",   "z_c"};

/* the --fields bits (out_mask) hold every field of the inverse sweep */
typedef char out_mask_fits[OUT_scene_resolved < 64 ? 1 : -1];

int out_shape_has(out_shape sh, int ax) {
  const int *a;
  for (a = out_shape_axes[sh]; *a >= 0; a++)
    if (*a == ax) return 1;
  return 0;
}

size_t out_columns(out_shape shape, size_t n) {
  switch (shape) {
  case OUT_CTL:
  case OUT_CTK:
  case OUT_CL: return 3;
  case OUT_CTEL: return 3 * n;
  case OUT_CF: return RPS3_DESIGN_NFLAG;
  case OUT_CP: return n;
  default: return 1;
  }
}

size_t out_type_size(out_type type) {
  return type == OUT_F64   ? sizeof(double)
         : type == OUT_I32 ? sizeof(int32_t)
         : type == OUT_I64 ? sizeof(int64_t)
                           : sizeof(char *);
}

const void *out_fill(int i) {
  static const double fnan = (double)NAN;
  static const int32_t fneg = -1, fnotrun = OUT_STATUS_NOT_COMPUTED;
  static const int64_t fneg64 = -1;
  const out_field_info *fi = &out_field_table[i];
  return fi->type == OUT_F64             ? (const void *)&fnan
         : fi->flags == OUT_FLAGS_STATUS ? (const void *)&fnotrun
         : fi->type == OUT_I32           ? (const void *)&fneg
         : fi->type == OUT_I64           ? (const void *)&fneg64
                                         : NULL;
}

void out_fill_n(void *dst, size_t n, int i) {
  size_t esz = out_type_size(out_field_table[i].type), k;
  const void *v = out_fill(i);
  /* memcpy: dst may be unaligned (a packed chunk); of a constant size, a
     store */
  for (k = 0; esz == 8 && k < n; k++) memcpy((char *)dst + k * 8, v, 8);
  for (k = 0; esz == 4 && k < n; k++) memcpy((char *)dst + k * 4, v, 4);
}

/* 1 when field i is in the inverse sweep's file (a member of out_block) */
static int inv(int i) { return (out_field_table[i].files & OUT_INV) != 0; }

/* elements of field i per slot */
static size_t slot_elems(const out_block *b, int i) {
  out_shape sh = out_field_table[i].shape;
  return out_shape_has(sh, OUT_AX_TIME)
             ? b->points * out_columns(sh, b->neffect)
             : out_columns(sh, b->points);
}

int out_block_alloc(out_block *b, int files, size_t cases, size_t points,
                    int effects) {
  int i, e;
  memset(b, 0, sizeof *b);
  b->cases = cases;
  b->points = points;
  for (e = 0; e < RPS3_NEFFECT; e++)
    if (effects & (1 << e)) b->effect[b->neffect++] = e;
  /* the per-sample buffers with OUT_SLACK bytes more (out_pack) */
  for (i = 0; i < OUT_NFIELD; i++) {
    size_t n =
        cases * slot_elems(b, i) * out_type_size(out_field_table[i].type);
    if ((out_field_table[i].files & files) &&
        !(b->buf[i] = calloc(1, n + OUT_SLACK)))
      goto fail;
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
  for (i = 0; i < OUT_NFIELD; i++) free(b->buf[i]);
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
    if (out_field_table[i].shape != OUT_C && b->buf[i])
      out_fill_n(
          (char *)b->buf[i] + lo * out_type_size(out_field_table[i].type),
          hi - lo, i);
  }
  for (j = slot * b->points + k; j < (slot + 1) * b->points; j++)
    b->t[j] = (double)NAN;
}

void out_schema_print(int files) {
  static const char *const types[] = {"float64", "int32", "int64", "string"};
  static const char *const when[] = {"always", "with a trajectory",
                                     "design.per_pose"};
  int i, design = (files & OUT_DESIGN) != 0;
  printf("| %s | dimensions | type | units |%s description |\n",
         design ? "design variable" : "dataset", design ? " written |" : "");
  printf("|---|---|---|---|%s---|\n", design ? "---|" : "");
  for (i = 0; i < OUT_NFIELD; i++) {
    const out_field_info *fi = &out_field_table[i];
    const int *a;
    if (!(fi->files & files)) continue;
    printf("| `%s` | ", fi->name);
    for (a = out_shape_axes[fi->shape]; *a >= 0; a++)
      printf("%s%s", a == out_shape_axes[fi->shape] ? "" : ", ",
             out_axis_name[*a]);
    printf(" | %s | %s |", types[fi->type], fi->units);
    if (design)
      printf(" %s |", when[fi->files == OUT_TASK   ? 1
                           : fi->files == OUT_POSE ? 2
                                                   : 0]);
    printf(" %s |\n", fi->doc);
  }
}

out_mask out_fields_all(void) {
  out_mask m = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (inv(i)) m |= (out_mask)1 << i;
  return m;
}

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
    if (per_point(i) && OUT_HAS(mask, i) && n < sz)
      n += (size_t)snprintf(buf + n, sz - n, "%s%s", n ? "," : "",
                            out_field_table[i].name);
  return buf;
}

const char *out_fields_attr(int files, out_mask mask, char *buf, size_t sz) {
  if (files & OUT_IDENT) {
    snprintf(buf, sz, "identification");
    return buf;
  }
  if (!(files & OUT_DES)) return out_fields_text(mask, buf, sz);
  snprintf(buf, sz, "design%s%s", files & OUT_TASK ? " task" : "",
           files & OUT_POSE ? " per_pose" : "");
  return buf;
}
