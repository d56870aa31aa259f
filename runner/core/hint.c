/* hint.c - "did you mean": the closest names by edit distance (hint.h). */
#include "hint.h"

#include <stdio.h>
#include <string.h>

/* optimal string alignment distance between a and b: insertions,
   deletions, substitutions and transpositions of two adjacent characters
   each count 1 */
static int hint_distance(const char *a, const char *b) {
  /* three rows of the dynamic programme: the transposition reads two back */
  int d[3][HINT_MAX_LEN + 2];
  size_t la = strlen(a), lb = strlen(b), i, j;
  if (la > HINT_MAX_LEN || lb > HINT_MAX_LEN) return HINT_MAX_LEN + 1;
  for (j = 0; j <= lb; j++) d[0][j] = (int)j;
  for (i = 1; i <= la; i++) {
    int *row = d[i % 3], *up = d[(i - 1) % 3], *up2 = d[(i + 1) % 3];
    row[0] = (int)i;
    for (j = 1; j <= lb; j++) {
      int cost = a[i - 1] != b[j - 1];
      int best = up[j] + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      if (up[j - 1] + cost < best) best = up[j - 1] + cost;
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
          up2[j - 2] + 1 < best)
        best = up2[j - 2] + 1;
      row[j] = best;
    }
  }
  return d[la % 3][lb];
}

const char *hint_last_part(const char *s) {
  const char *p = strrchr(s, '.');
  return p ? p + 1 : s;
}

/* the distance that counts for a hint */
static int hint_cost(const char *word, const char *cand) {
  int d = hint_distance(word, cand);
  if (d > 1 && strchr(cand, '.') &&
      strcmp(hint_last_part(word), hint_last_part(cand)) == 0)
    d = 1;
  return d;
}

void hint_text(char *buf, size_t sz, const char *word, const char *const *cand,
               size_t n) {
  size_t len = strlen(hint_last_part(word)), i, best_i = n, tie_i = n;
  /* how far a typo goes, by the length of the name's last part (the part
     a user types): one edit in a short name, up to three in a long one */
  int limit = len <= 4 ? 1 : len <= 9 ? 2 : 3, best = limit + 1;
  buf[0] = '\0';
  for (i = 0; i < n; i++) {
    int d;
    if (cand[i] == NULL || strcmp(cand[i], word) == 0) continue;
    d = hint_cost(word, cand[i]);
    if (d > limit) continue;
    if (d < best) {
      best = d;
      best_i = i;
      tie_i = n;
    } else if (d == best && tie_i == n && strcmp(cand[i], cand[best_i]) != 0) {
      tie_i = i;
    }
  }
  if (best_i == n) return;
  if (tie_i < n)
    snprintf(buf, sz, " (did you mean %s or %s?)", cand[best_i], cand[tie_i]);
  else
    snprintf(buf, sz, " (did you mean %s?)", cand[best_i]);
}
