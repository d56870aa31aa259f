/*
 * parts.c - the part files by shard, and what to do about missing ones
 * (merge.h).
 */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hdf5.h>

#include "merge.h"
#include "output/out_h5.h"
#include "verify.h"

int parts_by_shard(const char *const *part, size_t npart, const char ***byk,
                   size_t *n, char *err, size_t errsz) {
  const char **by = NULL;
  size_t i, k, nn, n0 = 0;
  *byk = NULL;
  for (i = 0; i < npart; i++) {
    if (merge_shard_of(part[i], &k, &nn, err, errsz)) goto fail;
    if (i == 0) {
      n0 = nn;
      by = calloc(nn, sizeof *by);
      if (!by) {
        snprintf(err, errsz, "out of memory");
        return -1;
      }
    }
    if (nn != n0) {
      snprintf(err, errsz, "%s is shard %zu/%zu, %s is of %zu", part[i], k, nn,
               part[0], n0);
      goto fail;
    }
    if (by[k]) {
      snprintf(err, errsz, "%s and %s are both shard %zu/%zu", by[k], part[i],
               k, nn);
      goto fail;
    }
    by[k] = part[i];
  }
  *byk = by;
  *n = n0;
  return 0;
fail:
  free(by);
  return -1;
}

/* the end of the shell word at s (plain or single-quoted pieces, as
   main_run.c's command_line writes them) */
static const char *word_end(const char *s) {
  while (*s && *s != ' ') {
    if (*s == '\'') {
      const char *q = strchr(s + 1, '\'');
      s = q ? q + 1 : s + strlen(s);
    } else
      s++;
  }
  return s;
}

/* the output name of shard k on t: `was` (of shard k0) with its one number
   k0 replaced by k; PART_k.h5 when there is no such single number or the
   name is quoted */
static void put_part_name(FILE *t, const char *was, size_t len, size_t k0,
                          size_t k) {
  const char *p, *hit = NULL, *base = was;
  size_t nhit = 0, hitlen = 0;
  for (p = was; p < was + len; p++)
    if (*p == '/') base = p + 1;
  for (p = base; p < was + len;) {
    if (isdigit((unsigned char)*p)) {
      const char *q = p;
      while (q < was + len && isdigit((unsigned char)*q)) q++;
      if (strtoul(p, NULL, 10) == k0 && (size_t)(q - p) < 20) {
        hit = p;
        hitlen = (size_t)(q - p);
        nhit++;
      }
      p = q;
    } else
      p++;
  }
  if (nhit != 1 || memchr(was, '\'', len))
    fprintf(t, "PART_%zu.h5", k);
  else
    fprintf(t, "%.*s%zu%.*s", (int)(hit - was), was, k,
            (int)(len - (size_t)(hit - was) - hitlen), hit + hitlen);
}

/* the command that makes shard k again, from the command_line of a part
   `model` (malloc'd; NULL when out of memory or when `model` has none) */
static char *rerun_command(const char *model, size_t k, size_t n) {
  const char *p = model, *e, *sh;
  size_t k0 = (size_t)-1, len = 0;
  char *out = NULL;
  FILE *t;
  if (!model || !(t = open_memstream(&out, &len))) return NULL;
  /* the model's own shard number, for its output name */
  if ((sh = strstr(model, " --shard ")) != NULL) k0 = strtoul(sh + 9, NULL, 10);
  while (*p) {
    e = word_end(p);
    fwrite(p, 1, (size_t)(e - p), t);
    if ((e - p == 2 && strncmp(p, "-o", 2) == 0) ||
        (e - p == 7 && strncmp(p, "--shard", 7) == 0)) {
      int is_o = p[1] == 'o';
      for (p = e; *p == ' '; p++) fputc(' ', t);
      e = word_end(p);
      if (is_o)
        put_part_name(t, p, (size_t)(e - p), k0, k);
      else
        fprintf(t, "%zu/%zu", k, n);
    }
    for (p = e; *p == ' '; p++) fputc(' ', t);
  }
  if (fclose(t) != 0) {
    free(out);
    return NULL;
  }
  return out;
}

size_t parts_report(FILE *out, const char *const *byk, const int *bad,
                    size_t n) {
  size_t k, nmiss = 0;
  const char *model = NULL;
  char *cmd = NULL;
  for (k = 0; k < n; k++) {
    if (byk[k] && !(bad && bad[k]) && !model) model = byk[k];
    nmiss += !byk[k] || (bad && bad[k]);
  }
  if (nmiss == 0) return 0;
  if (!model) /* every part bad: the first given one still has the command */
    for (k = 0; k < n && !model; k++) model = byk[k];
  fprintf(out, "rps3-run merge: %zu of %zu shard%s to run again: ", nmiss, n,
          n == 1 ? "" : "s");
  for (k = 0, nmiss = 0; k < n; k++)
    if (!byk[k] || (bad && bad[k]))
      fprintf(out, "%s%zu", nmiss++ ? "," : "", k);
  fprintf(out, "\n");
  if (model) cmd = verify_root_attr(model, "command_line");
  if (!cmd) {
    fprintf(out, "  (rps3-run SCENE -o PART --shard K/%zu for each)\n", n);
    return nmiss;
  }
  fprintf(out, "  from the directory the parts were made in:\n");
  for (k = 0; k < n; k++)
    if (!byk[k] || (bad && bad[k])) {
      char *c = rerun_command(cmd, k, n);
      fprintf(out, "  %s\n", c ? c : "(out of memory)");
      free(c);
    }
  free(cmd);
  return nmiss;
}

/* the stderr line of a --resume that computes the part again: 0 */
static int run_again(const char *why, size_t k, size_t n) {
  fprintf(stderr, "rps3-run: --resume: %s: running shard %zu/%zu again\n", why,
          k, n);
  return 0;
}

int parts_resume(const char *path, size_t k, size_t n, const char *text0,
                 const char *fields, const char *inputs, size_t *nfailed) {
  char err[1024], *have;
  hid_t f;
  int rc = -1;
  size_t unset = 0;
  if (access(path, F_OK) != 0) return 0;
  if (merge_part_check(path, k, n, text0, err, sizeof err))
    return run_again(err, k, n);
  /* a part of other fields would not merge with this run's parts */
  have = verify_root_attr(path, "fields");
  if (!have || strcmp(have, fields) != 0) {
    snprintf(err, sizeof err, "%s has the fields %s, this run writes %s", path,
             have ? have : "(none)", fields);
    free(have);
    return run_again(err, k, n);
  }
  free(have);
  /* the same scene text over other data (a table measured again) is
     another run: its cases would not be this run's */
  if (verify_inputs_as(path, inputs, "the file now has", err, sizeof err))
    return run_again(err, k, n);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f >= 0) {
    rc = merge_count_failed(f, k, n, nfailed, &unset, NULL);
    H5Fclose(f);
  }
  snprintf(err, sizeof err, "%s: cannot read status", path);
  /* the cases of this shard only: the other shards' read as the fill
     value (not computed), no failure of this one */
  return rc < 0 ? run_again(err, k, n) : 1;
}
