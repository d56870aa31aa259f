/*
 * hint.h - help for a mistyped name: the closest names a user may have
 * meant ("did you mean"), by edit distance.
 */
#ifndef RPS3_RUNNER_HINT_H
#define RPS3_RUNNER_HINT_H

#include <stddef.h>

/* names longer than this count as far from all */
#define HINT_MAX_LEN 127

/*
 * " (did you mean X?)" or " (did you mean X or Y?)" into buf: the names of
 * cand[0..n-1] closest to word, when close enough to be a typo (distance
 * at most 1 when the last part of word has up to 4 characters, 2 up to 9,
 * else 3); a dotted name
 * whose last part equals word's last part counts as distance 1 (a key put
 * in the wrong section).  "" when none is close.
 */
void hint_text(char *buf, size_t sz, const char *word, const char *const *cand,
               size_t n);

/* the last part of a dotted name ("c" of "a.b.c") */
const char *hint_last_part(const char *s);

#endif /* RPS3_RUNNER_HINT_H */
