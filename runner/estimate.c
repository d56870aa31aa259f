/*
 * estimate.c - see estimate.h.
 */
#include "estimate.h"

#include <stdint.h>
#include <stdio.h>

#include "output.h"

/* HDF5's global heap: a variable-length string is a 16-byte reference in
   the dataset and an object of 16 bytes of header plus its text, rounded up
   to 8 bytes, in the heap */
#define VLEN_REF 16.0
#define VLEN_OBJ 16.0
/* per chunk and chunked dataset: its B-tree entry (measured: 40-60 bytes) */
#define CHUNK_INDEX 64.0
/* superblock, object headers, attributes, dimension scales: measured at
   30-60 kB for the configs */
#define FIXED 131072.0

/* rows of the per-case chunks: ncase rounded up to whole chunks */
static size_t round_rows(size_t ncase, size_t tc)
{
  return (ncase + tc - 1) / tc * tc;
}

double est_file_bytes(const scene *s, const sweep_plan *p)
{
  double neff = 0;
  /* the chunks the plan allocates (sweep.h): per sample field, `stored`
     samples in chunks of tile_cases x chunk_points; per case, whole rows */
  const double tc = (double)p->tile_cases, nt = (double)p->nt;
  const double stored = (double)p->stored;
  const double chunks = stored / (tc * (double)p->chunk_points);
  const double rows = (double)round_rows(s->ncase, p->tile_cases);
  double per_sample = 0, per_case = 0, nds = 0, yaml = 600, total;
  scene_text t = {0};
  size_t a;
  int e;

  for (e = 0; e < RPS3_NEFFECT; e++)
    if (p->first.model.opt.effects & (1 << e))
      neff += 1;

#define EST_FIELD(name, shape, type, ...)                                     \
  {                                                                           \
    double cols = shape == OUT_CTEL                     ? 3 * neff            \
                  : shape == OUT_CTL || shape == OUT_CTK ? 3                  \
                                                         : 1;                 \
    double size = type == OUT_F64   ? 8                                       \
                  : type == OUT_I32 ? 4                                       \
                                    : VLEN_REF;                               \
    if (shape == OUT_C)                                                       \
      per_case += size;                                                       \
    else                                                                      \
      per_sample += cols * size;                                              \
    nds += 1;                                                                 \
  }
  RPS3_OUTPUT_FIELDS(EST_FIELD)
#undef EST_FIELD
  if (!p->grid_common) {
    per_sample += 8; /* case_time */
    nds += 1;
  }
  /* the heap objects: scene_resolved (the first case's YAML as the
     typical one) and an empty message per case */
  if (scene_case_yaml(&p->first, &t) == 0)
    yaml = (double)t.len;
  scene_text_free(&t);
  per_case += 2 * VLEN_OBJ + 8.0 * (double)(size_t)((yaml + 7) / 8);
  /* the case scale and the swept keys */
  per_case += 8;
  for (a = 0; a < s->naxis; a++)
    per_case += 8;
  total = stored * per_sample + rows * per_case + 8 * nt +
          chunks * nds * CHUNK_INDEX + (double)s->text_len + FIXED;
  return total;
}

const char *est_human(double bytes, char *buf, size_t sz)
{
  static const char *const unit[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) {
    bytes /= 1000;
    u++;
  }
  snprintf(buf, sz, u ? "%.3g %s" : "%.0f %s", bytes, unit[u]);
  return buf;
}
