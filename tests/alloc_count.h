/*
 * alloc_count.h - a malloc interposer for the tests that prove the
 * library allocates nothing after init: it counts every malloc, calloc,
 * realloc, posix_memalign and free of the process (GSL's included, since
 * the executable's definitions take precedence over glibc's for every
 * shared object) while a window is open (count_start .. count_stop).
 * Include it in one test program, outside the sanitizer build (ASan
 * brings its own allocator, which must not be interposed).
 */
#ifndef RPS3_TESTS_ALLOC_COUNT_H
#define RPS3_TESTS_ALLOC_COUNT_H

#include <errno.h>
#include <stdlib.h>

/* glibc's allocator under its internal names */
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t size);
extern void *__libc_memalign(size_t align, size_t size);
extern void __libc_free(void *p);

/* counters of this test program (single-threaded), not of the library */
static int counting;       /* 1 while a counted window is open */
static long n_alloc;       /* allocations seen in counted windows */
static long n_free;        /* frees of non-NULL pointers seen in them */

void *malloc(size_t size) {
  if (counting) n_alloc++;
  return __libc_malloc(size);
}

void *calloc(size_t n, size_t size) {
  if (counting) n_alloc++;
  return __libc_calloc(n, size);
}

void *realloc(void *p, size_t size) {
  if (counting) n_alloc++;
  return __libc_realloc(p, size);
}

int posix_memalign(void **out, size_t align, size_t size) {
  void *p;
  if (counting) n_alloc++;
  if (align < sizeof(void *) || (align & (align - 1)) != 0) return EINVAL;
  p = __libc_memalign(align, size);
  if (p == NULL) return ENOMEM;
  *out = p;
  return 0;
}

void free(void *p) {
  if (counting && p != NULL) n_free++;
  __libc_free(p);
}

static void count_start(void) {
  n_alloc = n_free = 0;
  counting = 1;
}

static void count_stop(void) { counting = 0; }

#endif /* RPS3_TESTS_ALLOC_COUNT_H */
