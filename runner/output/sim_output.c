/*
 * sim_output.c - see output.h: a simulation's file, the OUT_SIM rows
 * of the schema written by output.c a window of one case at a time.
 */
#include "output.h"

#include <stdlib.h>
#include <string.h>

/* 1 when field i is the simulation's */
static int sim_field(int i) {
  return (out_field_table[i].files & OUT_SIM) != 0;
}

int sim_window_alloc(sim_window *w, size_t points) {
  int i;
  memset(w, 0, sizeof *w);
  w->points = points;
  for (i = 0; i < OUT_NFIELD; i++) {
    if (out_field_table[i].shape == OUT_C || !sim_field(i)) continue;
    w->buf[i] = malloc(points * out_columns(out_field_table[i].shape, 0) *
                       sizeof(double));
    if (!w->buf[i]) {
      sim_window_free(w);
      return -1;
    }
  }
  return 0;
}

void sim_window_free(sim_window *w) {
  int i;
  for (i = 0; i < OUT_NFIELD; i++) free(w->buf[i]);
  memset(w, 0, sizeof *w);
}

int sim_file_window(out_file *f, const sim_window *w, size_t c, size_t k0,
                    size_t nk, const double *times, char *err, size_t errsz) {
  void *buf[OUT_NFIELD];
  int i;
  for (i = 0; i < OUT_NFIELD; i++) buf[i] = w->buf[i];
  return out_write_window(f, buf, w->points, c, k0, nk, times, err, errsz);
}

int sim_file_case(out_file *f, const sim_case_values *v, size_t c, char *err,
                  size_t errsz) {
  const char *msg = v->message;
  const void *val[OUT_NFIELD];
  memset(val, 0, sizeof val);
  val[OUT_tracking_error_max] = &v->tracking_error_max;
  val[OUT_failed_time] = &v->failed_time;
  val[OUT_sim_status] = &v->status;
  val[OUT_sim_failed_at] = &v->failed_at;
  val[OUT_nsteps] = &v->nsteps;
  val[OUT_nevals] = &v->nevals;
  val[OUT_nticks] = &v->nticks;
  val[OUT_nsat] = &v->nsat;
  val[OUT_message] = &msg;
  val[OUT_scene_resolved] = &v->scene_resolved;
  return out_write_case(f, val, c, 1, err, errsz);
}

double sim_file_bytes(size_t ncase, size_t npoint) {
  double per_point = 0, per_case = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (!sim_field(i))
      continue;
    else if (out_field_table[i].shape == OUT_C)
      per_case += out_field_table[i].type == OUT_STR ? 512.0 : 8.0;
    else
      per_point += 8.0 * (double)out_columns(out_field_table[i].shape, 0);
  /* the scene, the scales and HDF5's metadata: a bound */
  return per_point * (double)npoint + per_case * (double)ncase + 65536.0;
}
