/*
 * data.c - the per-thread workspace: the only allocation of the library.
 */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

int rps3_data_alloc(const rps3_model *m, rps3_data **out) {
  rps3_data *d;
  int status;
  if (out == NULL) return RPS3_EINVAL;
  *out = NULL;
  if (m == NULL || !m->valid) return RPS3_EINVAL;
  d = (rps3_data *)calloc(1, sizeof(*d));
  if (d == NULL) return RPS3_ENOMEM;
  status = rps3_solver_alloc(m, &d->solver);
  if (status != RPS3_OK) {
    free(d);
    return status;
  }
  *out = d;
  return RPS3_OK;
}

void rps3_data_free(rps3_data *d) {
  if (d == NULL) return;
  rps3_solver_free(d->solver);
  free(d);
}

void rps3_data_reset(rps3_data *d) {
  struct rps3_solver_state *s;
  if (d == NULL) return;
  s = d->solver;
  memset(d, 0, sizeof(*d));
  d->solver = s;
}
