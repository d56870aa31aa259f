/*
 * outpack.c - a tile's chunks as the file stores them, made off the
 * writing thread (see out_pack in output.h).  HDF5's filter pipeline runs
 * in the one thread that calls HDF5 (Debian's HDF5 is not thread-safe), so
 * with -j N deflate and the checksums would be serial; here each worker
 * packs its own tiles, and the writer only writes bytes (H5Dwrite_chunk).
 * The bytes are those HDF5's own filters make: zlib's compress2 at the
 * level (the deflate filter) followed by the Fletcher-32 checksum of the
 * result, stored little-endian after it (the fletcher32 filter).
 */
#include "output.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

/* Fletcher-32 of HDF5's fletcher32 filter: sums of big-endian 16-bit words
   (an odd last byte as the high byte of a word), folded every 360 words so
   that they never overflow, then to 16 bits each; sum2 high, sum1 low */
static uint32_t fletcher32(const unsigned char *p, size_t nbytes)
{
  uint32_t sum1 = 0, sum2 = 0;
  size_t words = nbytes / 2;
  while (words) {
    size_t n = words > 360 ? 360 : words;
    words -= n;
    for (; n; n--, p += 2) {
      sum1 += (uint32_t)p[0] << 8 | p[1];
      sum2 += sum1;
    }
    sum1 = (sum1 & 0xffff) + (sum1 >> 16);
    sum2 = (sum2 & 0xffff) + (sum2 >> 16);
  }
  if (nbytes % 2) {
    sum1 += (uint32_t)p[0] << 8;
    sum2 += sum1;
    sum1 = (sum1 & 0xffff) + (sum1 >> 16);
    sum2 = (sum2 & 0xffff) + (sum2 >> 16);
  }
  sum1 = (sum1 & 0xffff) + (sum1 >> 16);
  sum2 = (sum2 & 0xffff) + (sum2 >> 16);
  return sum2 << 16 | sum1;
}

/* *buf holds at least need bytes (grown by doubling); 0 or -1 */
static int reserve(unsigned char **buf, size_t *cap, size_t need)
{
  unsigned char *p;
  size_t n = *cap ? *cap : 65536;
  if (need <= *cap)
    return 0;
  while (n < need)
    n *= 2;
  p = realloc(*buf, n);
  if (!p)
    return -1;
  *buf = p;
  *cap = n;
  return 0;
}

/* n elements of the fill value (NaN, or -1 for int32) at dst */
static void fill(unsigned char *dst, size_t n, out_type type)
{
  size_t i;
  if (type == OUT_F64) {
    const double nan = (double)NAN;
    for (i = 0; i < n; i++)
      memcpy(dst + i * sizeof nan, &nan, sizeof nan);
  } else {
    const int32_t neg = -1;
    for (i = 0; i < n; i++)
      memcpy(dst + i * sizeof neg, &neg, sizeof neg);
  }
}

/* the chunk (c0, kc) of a [cases][points][cols] buffer into dst: rows
   [0, nc) from the tile, samples up to the tile's end; the rest fill */
static void gather(unsigned char *dst, const unsigned char *src,
                   const out_layout *L, const out_block *b, size_t esz,
                   size_t cols, out_type type, size_t nc, size_t kk,
                   size_t ns)
{
  size_t r, row = L->q * cols * esz;
  for (r = 0; r < L->tc; r++) {
    unsigned char *d = dst + r * row;
    size_t have = r < nc ? ns : 0;
    if (have)
      memcpy(d, src + (r * b->points + kk) * cols * esz, have * cols * esz);
    if (have < L->q)
      fill(d + have * cols * esz, (L->q - have) * cols, type);
  }
}

/* pack the chunks of one field (OUT_NFIELD: case_time) of the tile */
static int pack_field(const out_layout *L, out_block *b, int field,
                      size_t c0, size_t nc, size_t k0, size_t nk)
{
  const out_type type = field < OUT_NFIELD ? out_field_table[field].type
                                           : OUT_F64;
  const size_t cols = field < OUT_NFIELD
                          ? out_columns(out_field_table[field].shape,
                                        b->neffect)
                          : 1;
  const size_t esz = type == OUT_F64 ? sizeof(double) : sizeof(int32_t);
  const size_t raw = L->tc * L->q * cols * esz;
  const unsigned char *src = field < OUT_NFIELD ? out_block_field(b, field)
                                                : (const void *)b->t;
  size_t kc;
  for (kc = k0; kc < k0 + nk; kc += L->q) {
    size_t ns = k0 + nk - kc < L->q ? k0 + nk - kc : L->q, stored = raw;
    uLongf zlen = compressBound((uLong)raw);
    unsigned char *out;
    uint32_t sum;
    int i;
    if (b->npk == b->pk_max) {
      size_t n = b->pk_max ? 2 * b->pk_max : 64;
      out_chunk *p = realloc(b->pk, n * sizeof *p);
      if (!p)
        return -1;
      b->pk = p;
      b->pk_max = n;
    }
    if (reserve(&b->pk_buf, &b->pk_cap, b->pk_len + zlen + 4))
      return -1;
    out = b->pk_buf + b->pk_len;
    if (L->gzip) {
      /* the deflate filter: compress2 at the level, zlib format */
      if (reserve(&b->pk_tmp, &b->pk_tmp_cap, raw))
        return -1;
      gather(b->pk_tmp, src, L, b, esz, cols, type, nc, kc - k0, ns);
      if (compress2(out, &zlen, b->pk_tmp, (uLong)raw, L->gzip) != Z_OK)
        return -1;
      stored = zlen;
    } else
      gather(out, src, L, b, esz, cols, type, nc, kc - k0, ns);
    /* the fletcher32 filter: the checksum after the bytes, little-endian */
    sum = fletcher32(out, stored);
    for (i = 0; i < 4; i++)
      out[stored + (size_t)i] = (unsigned char)(sum >> (8 * i));
    b->pk[b->npk].field = field;
    b->pk[b->npk].c0 = c0;
    b->pk[b->npk].k0 = kc;
    b->pk[b->npk].off = b->pk_len;
    b->pk[b->npk].size = stored + 4;
    b->npk++;
    b->pk_len += stored + 4;
  }
  return 0;
}

int out_pack(const out_layout *L, out_block *b, size_t c0, size_t nc,
             size_t k0, size_t nk)
{
  int i;
  b->packed = 0;
  b->npk = 0;
  b->pk_len = 0;
  for (i = 0; i < OUT_NFIELD; i++)
    if (out_field_table[i].shape != OUT_C && (L->fields >> i & 1) &&
        pack_field(L, b, i, c0, nc, k0, nk))
      return -1;
  if (L->case_time && pack_field(L, b, OUT_NFIELD, c0, nc, k0, nk))
    return -1;
  b->packed = 1;
  return 0;
}
