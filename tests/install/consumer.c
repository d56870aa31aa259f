/*
 * consumer.c - a program outside the tree, built by tests/test_install.py
 * against the installed library (pkg-config and CMake): forces of the
 * paper's helix at a few samples, printed to 17 digits, so that the test
 * can compare them with the same program built in the tree.
 */
#include <stdio.h>
#include <string.h>

#include <rps3.h>

int main(void) {
  rps3_model m;
  rps3_data *d = NULL;
  rps3_traj tr;
  rps3_check chk;
  int k, status;
  /* the header this program was compiled with and the library it runs
     with must be the same version */
  if (strcmp(rps3_version(), RPS3_VERSION_STRING) != 0) {
    fprintf(stderr, "header %s, library %s\n", RPS3_VERSION_STRING,
            rps3_version());
    return 1;
  }
  rps3_model_default(&m);
  if (rps3_model_init(&m, &chk) != RPS3_OK) {
    fprintf(stderr, "model: %s\n", chk.msg);
    return 1;
  }
  if (rps3_data_alloc(&m, &d) != RPS3_OK) return 1;
  rps3_traj_default(&tr);
  printf("version %s\n", rps3_version());
  for (k = 0; k <= 4; k++) {
    double t = 0.2385 * k;
    status = rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose);
    if (status == RPS3_OK) status = rps3_inverse(&m, d);
    if (status != RPS3_OK) {
      fprintf(stderr, "t = %g: %s\n", t, d->err.msg);
      rps3_data_free(d);
      return 1;
    }
    printf("%.17g %.17g %.17g %.17g\n", t, d->F[0], d->F[1], d->F[2]);
  }
  rps3_data_free(d);
  return 0;
}
