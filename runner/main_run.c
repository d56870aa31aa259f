/*
 * main_run.c - rps3-run: run a scene (and its sweep) into an HDF5 file.
 *
 *   rps3-run SCENE.yaml -o OUT.h5 [--quiet] [--gzip LEVEL] [--check]
 *
 * Exit codes: 0 every case ok; 1 the file is complete but some cases failed
 * (see status/message/failed_at); 2 bad command line or scene, nothing
 * written; 3 the file could not be written (or an internal error), no
 * OUT.h5; killed by SIGINT/SIGTERM/SIGHUP: the temporary file is removed and
 * the process dies of that signal (shell status 128 + signal).
 */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>
#include <hdf5.h>

#include "output.h"
#include "progress.h"
#include "scene.h"
#include "sweep.h"

enum { EXIT_OK = 0, EXIT_FAILED_CASES = 1, EXIT_USAGE = 2, EXIT_IO = 3 };

/* the temporary file, for the signal handler: process-wide state of this
   program only (the library has none) */
static char tmp_path[4096];
static volatile sig_atomic_t have_tmp;

/* remove the temporary file, then die of the same signal */
static void on_signal(int sig)
{
  if (have_tmp)
    unlink(tmp_path);
  signal(sig, SIG_DFL);
  raise(sig);
}

static const int signals[] = {SIGINT, SIGTERM, SIGHUP};
#define NSIGNAL (sizeof signals / sizeof signals[0])

static void signals_install(void)
{
  struct sigaction sa;
  size_t i;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (i = 0; i < NSIGNAL; i++)
    sigaction(signals[i], &sa, NULL);
}

static void signals_block(int how)
{
  sigset_t set;
  size_t i;
  sigemptyset(&set);
  for (i = 0; i < NSIGNAL; i++)
    sigaddset(&set, signals[i]);
  sigprocmask(how, &set, NULL);
}

static void usage(FILE *out)
{
  fprintf(out,
          "usage: rps3-run SCENE.yaml -o OUT.h5 [--quiet] [--gzip LEVEL] "
          "[--check]\n"
          "       rps3-run --keys | --schema | --version | --help\n"
          "\n"
          "Runs the inverse dynamics of the Lee & Shah 3-RPS manipulator "
          "along the\n"
          "scene's trajectory, for every case of its sweep, into OUT.h5.\n"
          "  -o OUT.h5      output file (written as OUT.h5.tmp.PID, renamed "
          "when complete)\n"
          "  -q, --quiet    no progress on stderr\n"
          "  --gzip LEVEL   deflate the datasets (1-9; default 0, none)\n"
          "  --check        validate the scene and every case, write "
          "nothing\n"
          "  --keys         print the scene keys (markdown)\n"
          "  --schema       print the datasets of OUT.h5 (markdown)\n"
          "exit: 0 ok, 1 some cases failed, 2 bad scene or usage, 3 cannot "
          "write\n");
}

/* the command line, each argument quoted for a POSIX shell when needed */
static char *command_line(int argc, char **argv)
{
  size_t len = 1, i;
  char *s, *p;
  for (i = 0; i < (size_t)argc; i++)
    len += 4 * strlen(argv[i]) + 3;
  s = malloc(len);
  if (!s)
    return NULL;
  p = s;
  for (i = 0; i < (size_t)argc; i++) {
    const char *a = argv[i];
    int plain = a[0] != '\0' &&
                strspn(a, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                          "0123456789-_./=:,+@%") == strlen(a);
    if (i)
      *p++ = ' ';
    if (plain) {
      strcpy(p, a);
      p += strlen(a);
      continue;
    }
    *p++ = '\'';
    for (; *a; a++) {
      if (*a == '\'') {
        memcpy(p, "'\\''", 4);
        p += 4;
      } else
        *p++ = *a;
    }
    *p++ = '\'';
  }
  *p = '\0';
  return s;
}

int main(int argc, char **argv)
{
  const char *scene_path = NULL, *out_path = NULL;
  int quiet = 0, check = 0, gzip = 0, i, code;
  char err[512];
  scene s;
  scene_error serr;
  sweep_plan plan;
  sweep_stats st;
  out_block block;
  out_meta meta;
  out_file *f;
  progress pr;
  char *cmd;

  /* process-wide policy: GSL returns its errors, HDF5 prints none */
  gsl_set_error_handler_off();
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  if (strcmp(rps3_version(), RPS3_VERSION_STRING) != 0) {
    fprintf(stderr, "rps3-run: library %s does not match header %s\n",
            rps3_version(), RPS3_VERSION_STRING);
    return EXIT_IO;
  }

  for (i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      usage(stdout);
      return EXIT_OK;
    } else if (strcmp(a, "--version") == 0) {
      printf("rps3-run %s\n", rps3_version());
      return EXIT_OK;
    } else if (strcmp(a, "--keys") == 0) {
      scene_keys_print();
      return EXIT_OK;
    } else if (strcmp(a, "--schema") == 0) {
      out_schema_print();
      return EXIT_OK;
    } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (strcmp(a, "--check") == 0) {
      check = 1;
    } else if (strcmp(a, "-o") == 0 || strcmp(a, "--gzip") == 0) {
      char *end;
      if (i + 1 >= argc) {
        fprintf(stderr, "rps3-run: %s needs a value\n", a);
        return EXIT_USAGE;
      }
      if (a[1] == 'o') {
        out_path = argv[++i];
        continue;
      }
      gzip = (int)strtol(argv[++i], &end, 10);
      if (*end != '\0' || end == argv[i] || gzip < 0 || gzip > 9) {
        fprintf(stderr, "rps3-run: --gzip needs a level 0-9, got '%s'\n",
                argv[i]);
        return EXIT_USAGE;
      }
    } else if (a[0] == '-' && a[1] != '\0') {
      fprintf(stderr, "rps3-run: unknown option '%s'\n", a);
      usage(stderr);
      return EXIT_USAGE;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      fprintf(stderr, "rps3-run: one scene at a time ('%s' and '%s')\n",
              scene_path, a);
      return EXIT_USAGE;
    }
  }
  if (!scene_path || (!out_path && !check)) {
    usage(stderr);
    return EXIT_USAGE;
  }

  /* the scene and every case are checked before anything is written */
  if (scene_load(&s, scene_path, &serr)) {
    scene_error_print(scene_path, &serr);
    return EXIT_USAGE;
  }
  if (sweep_plan_make(&s, &plan, &serr)) {
    scene_error_print(scene_path, &serr);
    scene_free(&s);
    return EXIT_USAGE;
  }
  if (check) {
    printf("%s: %zu case%s, %zu samples (%zu per case at most)%s\n",
           scene_path, s.ncase, s.ncase == 1 ? "" : "s", plan.npoint,
           plan.nt, plan.grid_common ? "" : ", time grid differs by case");
    scene_free(&s);
    return EXIT_OK;
  }

  cmd = command_line(argc, argv);
  if (!cmd ||
      out_block_alloc(&block, plan.tile_cases, plan.tile_points,
                      plan.first.model.opt.effects)) {
    fprintf(stderr, "rps3-run: out of memory\n");
    free(cmd);
    scene_free(&s);
    return EXIT_IO;
  }
  meta.command_line = cmd;
  meta.gzip = gzip;

  /* write under a temporary name in the same directory, rename at the end */
  if ((size_t)snprintf(tmp_path, sizeof tmp_path, "%s.tmp.%ld", out_path,
                       (long)getpid()) >= sizeof tmp_path) {
    fprintf(stderr, "rps3-run: %s: path too long\n", out_path);
    code = EXIT_USAGE;
    goto done;
  }
  signals_install();
  have_tmp = 1;
  f = out_create(tmp_path, &s, &plan.first, plan.nt, plan.grid_common,
                 &block, &meta, err, sizeof err);
  if (!f) {
    fprintf(stderr, "rps3-run: %s: %s\n", out_path, err);
    code = EXIT_IO;
    goto done;
  }
  progress_start(&pr, s.ncase, quiet);
  if (sweep_run(&s, &plan, f, &block, &pr, &st, err, sizeof err)) {
    fprintf(stderr, "rps3-run: %s: %s\n", out_path, err);
    out_close(f, NULL, 0);
    code = EXIT_IO;
    goto done;
  }
  if (out_close(f, err, sizeof err)) {
    fprintf(stderr, "rps3-run: %s: %s\n", out_path, err);
    code = EXIT_IO;
    goto done;
  }
  /* the rename and forgetting the temporary name happen together */
  signals_block(SIG_BLOCK);
  if (rename(tmp_path, out_path) != 0) {
    fprintf(stderr, "rps3-run: cannot rename %s to %s: %s\n", tmp_path,
            out_path, strerror(errno));
    signals_block(SIG_UNBLOCK);
    code = EXIT_IO;
    goto done;
  }
  have_tmp = 0;
  signals_block(SIG_UNBLOCK);
  progress_finish(&pr, st.cases_done, st.points_done, st.nfailed);
  code = st.nfailed ? EXIT_FAILED_CASES : EXIT_OK;

done:
  if (have_tmp) {
    unlink(tmp_path);
    have_tmp = 0;
  }
  out_block_free(&block);
  free(cmd);
  scene_free(&s);
  return code;
}
