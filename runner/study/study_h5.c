/*
 * study_h5.c - the files of rps3-study, with the runner's conventions and
 * its helpers (output.h): units and description on every dataset,
 * dimension scales on every axis, Fletcher-32 on every chunk, and the root
 * attributes rps3_version, created_utc, command_line, gsl_version,
 * hdf5_version and title; CF's long_name on every dataset (long_names
 * below) and the root Conventions, history and git_revision (out_h5.h).
 */
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_version.h>
#include <hdf5_hl.h>

#include "output/output.h"
#include "study.h"

/* the CF long_name of every dataset of the study files, by name: a
   dataset missing here is refused (study_h5_write), so that none is
   written without one */
static const struct {
  const char *name, *long_name;
} long_names[] = {
    /* workspace */
    {"rho", "platform radius over base radius"},
    {"alpha", "platform precession angle"},
    {"beta", "platform nutation angle"},
    {"z_c", "platform centre height"},
    {"link", "link number"},
    {"status", "status"},
    {"condition", "condition number of the constraint Jacobian"},
    {"transmission", "force transmission"},
    {"force", "static actuating force along the link"},
    {"max_force", "largest static actuating force magnitude"},
    {"mode", "assembly mode"},
    /* accuracy */
    {"trajectory", "trajectory name"},
    {"config", "configuration index"},
    {"study", "knob the configuration turns"},
    {"label", "configuration label"},
    {"theta_route", "theta route"},
    {"solver", "theta solver"},
    {"derivative", "rate computation"},
    {"method", "formulation of the dynamics"},
    {"tolerance", "theta solve tolerance"},
    {"fd_step", "finite-difference step"},
    {"dt_fraction", "sample interval over trajectory duration"},
    {"effects", "selected effects bits"},
    {"warm_start", "theta solve warm start"},
    {"ns_per_point", "median time per sample"},
    {"ns_per_point_q1", "first quartile of time per sample"},
    {"ns_per_point_q3", "third quartile of time per sample"},
    {"ns_per_second", "time per simulated second of trajectory"},
    {"force_error", "relative actuating force error"},
    {"theta_error", "link angle error"},
    {"peak_force_error", "relative peak force error"},
    {"energy_residual", "relative energy residual"},
    {"mean_iterations", "mean theta solve iterations"},
    {"failed_samples", "failed samples"},
    {"reference_floor_force", "relative rounding floor of the reference force"},
    {"reference_floor_theta", "rounding floor of the reference theta"},
    {"reference_force_max", "largest reference force magnitude"},
    {"reference_peak_force", "peak reference force magnitude"}};

static const char *long_name_of(const char *name) {
  size_t i;
  for (i = 0; i < sizeof long_names / sizeof long_names[0]; i++)
    if (strcmp(long_names[i].name, name) == 0) return long_names[i].long_name;
  return NULL;
}

/* the compression of the maps (rank >= 3), as the runner's default */
#define STUDY_GZIP 4

int study_h5_open(study_h5 *o, const char *path, const char *cmdline,
                  const char *title) {
  char now[32], h5v[32];
  unsigned maj, min, rel;
  const char *const kv[][2] = {{"rps3_version", rps3_version()},
                               {"created_utc", now},
                               {"command_line", cmdline},
                               {"gsl_version", gsl_version},
                               {"hdf5_version", h5v},
                               {"title", title}};
  o->str = -1;
  o->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (o->file < 0) return -1;
  o->str = H5Tcopy(H5T_C_S1);
  if (o->str < 0 || H5Tset_size(o->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(o->str, H5T_CSET_UTF8) < 0)
    return -1;
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return out_h5_attrs(o->file, o->str, kv, 6) < 0 ||
                 out_cf_root(o->file, o->str, now, cmdline) < 0
             ? -1
             : 0;
}

int study_h5_close(study_h5 *o) {
  int rc = 0;
  if (o->str >= 0 && H5Tclose(o->str) < 0) rc = -1;
  if (o->file >= 0 && H5Fclose(o->file) < 0) rc = -1;
  return rc;
}

/* attach the named scales to ds's dimensions (NULL: ds is that scale) */
static int attach_scales(const study_h5 *o, hid_t ds, const char *name,
                         int rank, const char *const *scales) {
  int k, bad;
  if (!scales) return H5DSset_scale(ds, name) < 0 ? -1 : 0;
  for (k = 0; k < rank; k++) {
    hid_t sc = H5Dopen2(o->file, scales[k], H5P_DEFAULT);
    if (sc < 0) return -1;
    bad = H5DSattach_scale(ds, sc, (unsigned)k) < 0;
    H5Dclose(sc);
    if (bad) return -1;
  }
  return 0;
}

int study_h5_write(study_h5 *o, const char *name, hid_t type, int rank,
                   const hsize_t *dims, const void *data, const char *units,
                   const char *doc, const char *const *scales) {
  hsize_t chunk[8];
  hid_t ds;
  const char *long_name = long_name_of(name);
  int k, rc = -1;
  if (rank > 8 || !long_name) return -1;
  /* the maps: one chunk per leading index, deflated */
  chunk[0] = 1;
  for (k = 1; k < rank; k++) chunk[k] = dims[k];
  ds = out_h5_dataset(o->file, o->str, name, type, rank, dims,
                      rank >= 3 ? chunk : NULL, STUDY_GZIP, NULL, units, doc);
  if (ds < 0) return -1;
  if (out_cf_long_name(ds, o->str, long_name) == 0 &&
      H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0 &&
      attach_scales(o, ds, name, rank, scales) == 0)
    rc = 0;
  H5Dclose(ds);
  return rc;
}
