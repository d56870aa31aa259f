/*
 * fuzz_scene.c - libFuzzer harness over the runner's scene parser.
 *
 *   make check-fuzz          a bounded run (20 s) from tests/fuzz/corpus
 *   build/fuzz_scene -max_total_time=3600 -jobs=4 build/fuzz-corpus \
 *       tests/fuzz/corpus configs tests/bad_scenes   the long run (docs/hard-cases.md)
 *
 * Each input is written to a file and read by scene_load(), the entry point
 * of rps3-run.  What must hold, besides no crash, leak or undefined
 * behaviour (ASan, UBSan, LeakSanitizer):
 *   - a rejected scene has a message: a non-empty what and path, and a
 *     position that is 0:0 or a real 1-based line:column;
 *   - an accepted scene has at least one case; its first and last cases
 *     either build, or are rejected with a message; a case that builds
 *     writes its YAML (scene_resolved) and that YAML is accepted again.
 * A failed property calls abort(), which libFuzzer reports as a crash with
 * the input that caused it.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* one scratch file per fuzzing process */
static char path_in[64], path_rt[64];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  int fd;
  (void)argc;
  (void)argv;
  gsl_set_error_handler_off();
  snprintf(path_in, sizeof path_in, "/tmp/rps3-fuzz-%ld.yaml", (long)getpid());
  snprintf(path_rt, sizeof path_rt, "/tmp/rps3-fuzz-%ld-rt.yaml",
           (long)getpid());
  fd = open(path_in, O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd < 0) abort();
  close(fd);
  return 0;
}

static void write_file(const char *path, const void *data, size_t size) {
  FILE *f = fopen(path, "wb");
  if (!f || (size && fwrite(data, 1, size, f) != size)) abort();
  if (fclose(f) != 0) abort();
}

static void check_error(const scene_error *e) {
  if (e->what[0] == '\0' || e->path[0] == '\0') abort();
  if (e->mark.line < 0 || e->mark.column < 0) abort();
  if ((e->mark.line == 0) != (e->mark.column == 0)) abort();
}

/* build case k; when it builds, its YAML must load again */
static void check_case(const scene *s, size_t k) {
  scene_case c;
  scene_error e;
  memset(&e, 0, sizeof e);
  if (scene_case_build(s, k, &c, &e) != 0) {
    check_error(&e);
    return;
  }
  {
    scene_text t = {NULL, 0, 0, 0};
    scene rt;
    scene_error e2;
    memset(&rt, 0, sizeof rt);
    memset(&e2, 0, sizeof e2);
    if (scene_case_yaml(&c, &t) != 0) {
      if (!t.oom) abort(); /* only running out of memory may stop it */
      scene_text_free(&t);
      return;
    }
    write_file(path_rt, t.s, t.len);
    if (scene_load(&rt, path_rt, &e2) != 0) abort();
    if (rt.ncase != 1) abort();
    scene_free(&rt);
    scene_text_free(&t);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  scene s;
  scene_error e;
  memset(&s, 0, sizeof s);
  memset(&e, 0, sizeof e);
  write_file(path_in, data, size);
  if (scene_load(&s, path_in, &e) != 0) {
    check_error(&e);
    scene_free(&s);
    return 0;
  }
  if (s.ncase < 1) abort();
  check_case(&s, 0);
  if (s.ncase > 1) check_case(&s, s.ncase - 1);
  scene_free(&s);
  return 0;
}
