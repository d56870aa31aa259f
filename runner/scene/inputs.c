/*
 * inputs.c - see inputs.h.  The digest is OpenSSL's SHA-256 (libcrypto,
 * FIPS 180-4) over the file's bytes, read again after the scene loaded it;
 * then the table is read once more and must give the rows the scene
 * holds, so that the digest is of the data the run uses.
 */
#include "inputs.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openssl/evp.h>

int inputs_sha256(const char *path, char hex[INPUTS_HEX], char *err,
                  size_t errsz) {
  enum { BUF = 1 << 16 };
  static const char digits[] = "0123456789abcdef";
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int nmd = 0, i;
  FILE *f = fopen(path, "rb");
  EVP_MD_CTX *ctx = NULL;
  unsigned char *buf = NULL;
  size_t got;
  int rc = -1;
  if (!f) {
    snprintf(err, errsz, "%s: cannot open: %s", path, strerror(errno));
    return -1;
  }
  buf = malloc(BUF);
  ctx = EVP_MD_CTX_new();
  if (!buf || !ctx || EVP_DigestInit_ex(ctx, EVP_sha256(), NULL) != 1) {
    snprintf(err, errsz, "%s: cannot compute its SHA-256 (out of memory)",
             path);
    goto done;
  }
  while ((got = fread(buf, 1, BUF, f)) > 0)
    if (EVP_DigestUpdate(ctx, buf, got) != 1) break;
  if (ferror(f) || !feof(f)) {
    snprintf(err, errsz, "%s: cannot read: %s", path, strerror(errno));
    goto done;
  }
  if (EVP_DigestFinal_ex(ctx, md, &nmd) != 1 || nmd != 32) {
    snprintf(err, errsz, "%s: cannot compute its SHA-256", path);
    goto done;
  }
  for (i = 0; i < nmd; i++) {
    hex[2 * i] = digits[md[i] >> 4];
    hex[2 * i + 1] = digits[md[i] & 15];
  }
  hex[2 * nmd] = '\0';
  rc = 0;
done:
  EVP_MD_CTX_free(ctx);
  free(buf);
  fclose(f);
  return rc;
}

/* n rows of m doubles equal bit for bit (both absent counts as equal) */
static int same_doubles(const void *a, const void *b, size_t n, size_t m) {
  if (!a || !b) return !a && !b;
  return memcmp(a, b, n * m * sizeof(double)) == 0;
}

/*
 * 1 when the table `file` reads now (after its digest) as the rows t was
 * read with.  The scene read it before the digest; a file rewritten in
 * between would leave a digest of data the run did not use.  Read once
 * more, the rows differ unless the file is the one the scene read (or was
 * changed and changed back, which is the same data).
 */
static int same_rows(const table_data *t, const scene *s, const char *file,
                     int what) {
  table_data now;
  char msg[256];
  int same;
  if (table_read(&now, s->file, file, what, msg, sizeof msg)) return 0;
  same = now.n == t->n && now.rates_given == t->rates_given &&
         same_doubles(now.time, t->time, t->n, 1) &&
         same_doubles(now.value, t->value, t->n, 3) &&
         same_doubles(now.rate, t->rate, t->n, 3) &&
         same_doubles(now.acc, t->acc, t->n, 3);
  table_free(&now);
  return same;
}

char *inputs_record(const scene *s, char *err, size_t errsz) {
  char *rec = NULL, hex[INPUTS_HEX];
  size_t len = 0;
  int k, rc = 0;
  FILE *m = open_memstream(&rec, &len);
  if (!m) {
    snprintf(err, errsz, "out of memory");
    return NULL;
  }
  for (k = 0; k < SCENE_NKEY && rc == 0; k++) {
    const scene_key_info *ki = scene_key_get(k);
    const table_data *t = &s->table[SCENE_TABLE_OF(k)];
    if (ki->type != KEY_FILE || !t->abs || !s->given[k]) continue;
    rc = inputs_sha256(t->abs, hex, err, errsz);
    if (rc == 0 && !same_rows(t, s, t->abs, SCENE_TABLE_OF(k))) {
      snprintf(err, errsz,
               "%s: %s changed while this run read it (its rows now are not "
               "those read): run again once it is written",
               ki->path, t->abs);
      rc = -1;
    }
    if (rc == 0) fprintf(m, "%s sha256:%s %s\n", ki->path, hex, t->abs);
  }
  if (fclose(m) != 0 && rc == 0) {
    snprintf(err, errsz, "out of memory");
    rc = -1;
  }
  if (rc == 0) return rec;
  free(rec);
  return NULL;
}

/* one line of a record: its key, digest and path, and the next line */
typedef struct {
  const char *key, *dig, *path;
  size_t nkey, ndig, npath;
} rec_line;

/* parse the line at *p (advanced past it); 0 at the end of the record */
static int next_line(const char **p, rec_line *l) {
  const char *s = *p, *e, *sp;
  if (!*s) return 0;
  e = strchr(s, '\n');
  if (!e) e = s + strlen(s);
  *p = *e ? e + 1 : e;
  memset(l, 0, sizeof *l);
  l->key = s;
  sp = memchr(s, ' ', (size_t)(e - s));
  l->nkey = sp ? (size_t)(sp - s) : (size_t)(e - s);
  if (!sp) return 1;
  l->dig = sp + 1;
  sp = memchr(l->dig, ' ', (size_t)(e - l->dig));
  l->ndig = sp ? (size_t)(sp - l->dig) : (size_t)(e - l->dig);
  if (sp) {
    l->path = sp + 1;
    l->npath = (size_t)(e - l->path);
  }
  return 1;
}

/* the line of rec whose key is key[0..nkey), 1 if found */
static int find_key(const char *rec, const char *key, size_t nkey,
                    rec_line *out) {
  const char *p = rec;
  while (next_line(&p, out))
    if (out->nkey == nkey && memcmp(out->key, key, nkey) == 0) return 1;
  return 0;
}

static void put(char *dst, size_t sz, const char *s, size_t n) {
  if (sz == 0) return;
  if (n >= sz) n = sz - 1;
  memcpy(dst, s, n);
  dst[n] = '\0';
}

/* the first key of `from` whose digest differs in `to` (1), else 0 */
static int first_difference(const char *from, const char *to, rec_line *lf,
                            rec_line *lt, int *in_to) {
  const char *p = from;
  while (next_line(&p, lf)) {
    *in_to = find_key(to, lf->key, lf->nkey, lt);
    if (!*in_to || lt->ndig != lf->ndig ||
        memcmp(lt->dig, lf->dig, lf->ndig) != 0)
      return 1;
  }
  return 0;
}

int inputs_differ(const char *a, const char *b, char *key, size_t keysz,
                  char *path, size_t pathsz, char *da, char *db, size_t dsz) {
  static const char none[] = "none", unrec[] = "not recorded";
  rec_line la, lb, *l = &la;
  const char *x, *y, *p = a ? a : b;
  size_t nx, ny;
  int in;
  key[0] = path[0] = da[0] = db[0] = '\0';
  if (!a || !b) {
    /* a file written before records were kept: what it read is unknown,
       unless the scene (compared elsewhere) reads no file */
    if (!p || !next_line(&p, &la)) return 0;
    x = a ? la.dig : unrec;
    nx = a ? la.ndig : strlen(unrec);
    y = b ? la.dig : unrec;
    ny = b ? la.ndig : strlen(unrec);
  } else if (first_difference(a, b, &la, &lb, &in)) {
    x = la.dig;
    nx = la.ndig;
    y = in ? lb.dig : none;
    ny = in ? lb.ndig : 4;
  } else if (first_difference(b, a, &lb, &la, &in)) {
    /* a key that only b has */
    l = &lb;
    x = none;
    nx = 4;
    y = lb.dig;
    ny = lb.ndig;
  } else {
    return 0;
  }
  put(key, keysz, l->key, l->nkey);
  put(path, pathsz, l->path ? l->path : "", l->npath);
  put(da, dsz, x, nx);
  put(db, dsz, y, ny);
  return 1;
}

int inputs_find(const char *rec, const char *key, char *dig, size_t dsz,
                char *path, size_t pathsz) {
  rec_line l;
  if (!rec || !find_key(rec, key, strlen(key), &l)) return 0;
  put(dig, dsz, l.dig ? l.dig : "", l.ndig);
  put(path, pathsz, l.path ? l.path : "", l.npath);
  return 1;
}
