/*
 * test_nomem.c - rps3_data_alloc (and rps3_design_ws_alloc) under
 * allocation failure: the k-th
 * allocation fails, for every k, and each time the call returns
 * RPS3_ENOMEM with everything it had built freed.  A malloc interposer
 * (glibc's __libc_* entry points) sees GSL's allocations too.  The
 * sanitizer build has its own allocator, so there the test is skipped.
 */
#include <stdlib.h>

#include "testutil.h"

#ifndef RPS3_SANITIZE
extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void __libc_free(void *);

/* test-only counters: armed around the call under test */
static int armed, fail_at, n_alloc, n_live;

/* allocations before and at the entry of the GSL solver constructor */
#define OWN_ALLOCS 6

static int should_fail(void) {
  if (!armed) return 0;
  n_alloc++;
  return n_alloc == fail_at;
}

void *malloc(size_t n) {
  void *p;
  if (should_fail()) return NULL;
  p = __libc_malloc(n);
  if (armed && p) n_live++;
  return p;
}
void *calloc(size_t k, size_t n) {
  void *p;
  if (should_fail()) return NULL;
  p = __libc_calloc(k, n);
  if (armed && p) n_live++;
  return p;
}
void *realloc(void *q, size_t n) {
  if (should_fail()) return NULL;
  return __libc_realloc(q, n);
}
void free(void *p) {
  if (armed && p) n_live--;
  __libc_free(p);
}

static void every_failure_is_enomem(void **state) {
  int s;
  (void)state;
  for (s = 0; s < RPS3_NSOLVER; s++) {
    rps3_model m;
    rps3_data *d = NULL;
    int k, status, total;
    rps3_model_default(&m);
    m.opt.solver = (rps3_solver)s;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    /* count the allocations of a successful call */
    armed = 1, fail_at = -1, n_alloc = 0, n_live = 0;
    status = rps3_data_alloc(&m, &d);
    armed = 0;
    assert_int_equal(status, RPS3_OK);
    total = n_alloc;
    assert_true(total > OWN_ALLOCS);
    rps3_data_free(d);
    for (k = 1; k <= OWN_ALLOCS; k++) {
      armed = 1, fail_at = k, n_alloc = 0, n_live = 0;
      status = rps3_data_alloc(&m, &d);
      armed = 0;
      if (status != RPS3_ENOMEM)
        fail_msg("%s: allocation %d of %d failed, got status %d",
                 rps3_solver_name(s), k, total, status);
      assert_null(d);
      if (n_live != 0)
        fail_msg("%s: allocation %d failed: %d blocks leaked",
                 rps3_solver_name(s), k, n_live);
    }
  }
}

/* rps3_design_ws_alloc: its own two blocks and the data's, the first
   OWN_ALLOCS + 2 allocations each failed in turn */
static void design_ws_failure_is_enomem(void **state) {
  rps3_design_ws *w = NULL;
  int k, status, total;
  (void)state;
  armed = 1, fail_at = -1, n_alloc = 0, n_live = 0;
  status = rps3_design_ws_alloc(&w);
  armed = 0;
  assert_int_equal(status, RPS3_OK);
  total = n_alloc;
  rps3_design_ws_free(w);
  assert_true(total > OWN_ALLOCS + 2);
  for (k = 1; k <= OWN_ALLOCS + 2; k++) {
    armed = 1, fail_at = k, n_alloc = 0, n_live = 0;
    status = rps3_design_ws_alloc(&w);
    armed = 0;
    if (status != RPS3_ENOMEM)
      fail_msg("design workspace: allocation %d of %d failed, got status %d",
               k, total, status);
    assert_null(w);
    if (n_live != 0)
      fail_msg("design workspace: allocation %d failed: %d blocks leaked", k,
               n_live);
  }
}
#else
static void every_failure_is_enomem(void **state) {
  (void)state;
  skip();
}
static void design_ws_failure_is_enomem(void **state) {
  (void)state;
  skip();
}
#endif

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(every_failure_is_enomem),
      cmocka_unit_test(design_ws_failure_is_enomem),
  };
  gsl_set_error_handler_off();
  return cmocka_run_group_tests(tests, NULL, NULL);
}
