/*
 * outpack.c - out_pack (outblock.h): HDF5's filters run in the one thread
 * that calls HDF5, so each worker packs its own tiles instead, into the
 * bytes of HDF5's deflate filter (zlib's compress2 at the level) and
 * fletcher32 filter (the checksum of the result, little-endian, after it).
 */
#include "outblock.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

/*
 * Fletcher-32 of HDF5's fletcher32 filter: sum1 = the sum of the big-endian
 * 16-bit words (an odd last byte as a word's high byte), sum2 = the sum of
 * sum1 after each word; sum2 high, sum1 low.  HDF5's folds keep each sum
 * modulo 65535 and positive, so the result is 0 when every byte is zero,
 * else the residue of the exact sum modulo 65535 in [1, 65535]: computed
 * here per byte lane of FL_LANES bytes (a[k] its bytes, c[k] a[k] after
 * each round, 32-bit lanes the compiler vectorises; a high byte counts 256
 * times, word j of round r of m weighs FL_LANES / 2 (m - r) - j in sum2).
 * FL_ROUNDS keeps c[k] below 2^32: 255 m (m + 1) / 2 < 2^32, m = 4096.
 */
#define FL_LANES 16
#define FL_ROUNDS 4096
static uint32_t fletcher32(const unsigned char *p, size_t nbytes) {
  uint64_t s1 = 0, s2 = 0; /* the sums modulo 65535 */
  size_t done = 0;
  int any = 0;
  while (nbytes - done >= FL_LANES) {
    uint32_t a[FL_LANES], c[FL_LANES];
    uint64_t d1 = 0, d2 = 0;
    size_t m = (nbytes - done) / FL_LANES, r;
    int k;
    if (m > FL_ROUNDS) m = FL_ROUNDS;
    memset(a, 0, sizeof a);
    memset(c, 0, sizeof c);
    for (r = 0; r < m; r++, p += FL_LANES)
      for (k = 0; k < FL_LANES; k++) {
        a[k] += p[k];
        c[k] += a[k];
      }
    for (k = 0; k < FL_LANES; k++) {
      uint64_t weight = k % 2 ? 1 : 256;
      d1 += weight * a[k];
      d2 +=
          weight * ((uint64_t)(FL_LANES / 2) * c[k] - (uint64_t)(k / 2) * a[k]);
    }
    any |= d1 != 0;
    /* sum2 gains sum1 once per word of the block, and the block's own */
    s2 = (s2 + (m * FL_LANES / 2) % 65535 * s1 + d2 % 65535) % 65535;
    s1 = (s1 + d1 % 65535) % 65535;
    done += m * FL_LANES;
  }
  /* the last words, and an odd last byte */
  for (; done < nbytes; done += 2, p += 2) {
    uint32_t w = (uint32_t)p[0] << 8 | (done + 1 < nbytes ? p[1] : 0);
    any |= w != 0;
    s1 = (s1 + w) % 65535;
    s2 = (s2 + s1) % 65535;
  }
  if (!any) return 0;
  return (uint32_t)(s2 ? s2 : 65535) << 16 | (uint32_t)(s1 ? s1 : 65535);
}

/* *buf holds at least need bytes (grown by doubling); 0 or -1 */
static int reserve(unsigned char **buf, size_t *cap, size_t need) {
  unsigned char *p;
  size_t n = *cap ? *cap : 65536;
  if (need <= *cap) return 0;
  while (n < need) n *= 2;
  p = realloc(*buf, n);
  if (!p) return -1;
  *buf = p;
  *cap = n;
  return 0;
}

/* the chunk (c0, kc) of a [cases][points][cols] buffer into dst: rows
   [0, nc) from the tile, samples up to the tile's end; the rest fill.
   dst may be the chunk's own place in src (rows contiguous there): then
   only the fill is written */
static void gather(unsigned char *dst, const unsigned char *src,
                   const out_layout *L, const out_block *b, size_t esz,
                   size_t cols, int field, size_t nc, size_t kk, size_t ns) {
  size_t r, row = L->q * cols * esz;
  for (r = 0; r < L->tc; r++) {
    unsigned char *d = dst + r * row;
    const unsigned char *from = src + (r * b->points + kk) * cols * esz;
    size_t have = r < nc ? ns : 0;
    if (have && d != from) memcpy(d, from, have * cols * esz);
    /* case_time's fill, NaN, is any float64 field's */
    if (have < L->q)
      out_fill_n(d + have * cols * esz, (L->q - have) * cols,
                 field < OUT_NFIELD ? field : OUT_force);
  }
}

/* pack the chunks of one field (OUT_NFIELD: case_time) of the tile */
static int pack_field(const out_layout *L, out_block *b, int field, size_t c0,
                      size_t nc, size_t k0, size_t nk) {
  const out_type type =
      field < OUT_NFIELD ? out_field_table[field].type : OUT_F64;
  const size_t cols =
      field < OUT_NFIELD ? out_columns(out_field_table[field].shape, b->neffect)
                         : 1;
  const size_t esz = type == OUT_F64 ? sizeof(double) : sizeof(int32_t);
  const size_t raw = L->tc * L->q * cols * esz;
  unsigned char *src = field < OUT_NFIELD ? b->buf[field] : (void *)b->t;
  /* the buffer's bytes; its rows are contiguous in a chunk when a chunk
     row is a whole slot, or when there is one row */
  const size_t total = b->cases * b->points * cols * esz;
  const int rows_contiguous = L->tc == 1 || b->points == L->q;
  size_t kc;
  for (kc = k0; kc < k0 + nk; kc += L->q) {
    size_t ns = k0 + nk - kc < L->q ? k0 + nk - kc : L->q, stored = raw;
    size_t start = (kc - k0) * cols * esz;
    uLongf zlen = compressBound((uLong)raw);
    unsigned char *out;
    uint32_t sum;
    int i, direct;
    if (b->npk == b->pk_max) {
      size_t n = b->pk_max ? 2 * b->pk_max : 64;
      out_chunk *p = realloc(b->pk, n * sizeof *p);
      if (!p) return -1;
      b->pk = p;
      b->pk_max = n;
    }
    /* a chunk that ends where the buffer ends is stored from the buffer
       itself (its fill set in place: nothing reads it after this), its
       checksum in the buffer's slack: no copy */
    direct = !L->gzip && rows_contiguous && start + raw == total;
    if (direct)
      out = src + start;
    else if (reserve(&b->pk_buf, &b->pk_cap, b->pk_len + zlen + 4))
      return -1;
    else
      out = b->pk_buf + b->pk_len;
    if (!direct && L->gzip) {
      /* the deflate filter: compress2 at the level, zlib format */
      if (reserve(&b->pk_tmp, &b->pk_tmp_cap, raw)) return -1;
      gather(b->pk_tmp, src, L, b, esz, cols, field, nc, kc - k0, ns);
      if (compress2(out, &zlen, b->pk_tmp, (uLong)raw, L->gzip) != Z_OK)
        return -1;
      stored = zlen;
    } else
      gather(out, src, L, b, esz, cols, field, nc, kc - k0, ns);
    /* the fletcher32 filter: the checksum after the bytes, little-endian */
    sum = fletcher32(out, stored);
    for (i = 0; i < 4; i++)
      out[stored + (size_t)i] = (unsigned char)(sum >> (8 * i));
    b->pk[b->npk].field = field;
    b->pk[b->npk].c0 = c0;
    b->pk[b->npk].k0 = kc;
    b->pk[b->npk].direct = direct;
    b->pk[b->npk].off = direct ? start : b->pk_len;
    b->pk[b->npk].size = stored + 4;
    b->npk++;
    if (!direct) b->pk_len += stored + 4;
  }
  return 0;
}

int out_pack(const out_layout *L, out_block *b, size_t c0, size_t nc, size_t k0,
             size_t nk) {
  int i;
  b->packed = 0;
  b->npk = 0;
  b->pk_len = 0;
  for (i = 0; i < OUT_NFIELD; i++)
    if (out_field_table[i].shape != OUT_C && OUT_HAS(L->fields, i) &&
        pack_field(L, b, i, c0, nc, k0, nk))
      return -1;
  if (L->case_time && pack_field(L, b, OUT_NFIELD, c0, nc, k0, nk)) return -1;
  b->packed = 1;
  return 0;
}
