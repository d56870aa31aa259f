/*
 * sim_output.h - the HDF5 file of a simulated scene (simulate.h): its
 * schema and a writer of windows of one case at a time.
 *
 * The conventions of output.h: dimension scales case, time and link, the
 * swept keys as [case] coordinates, units and description on every
 * dataset, Fletcher-32 on every chunk, NaN (-1) for missing values,
 * status -1000 for a case not computed, the scene verbatim and each
 * case's resolved scene.  The datasets differ: SIM_OUTPUT_FIELDS.
 */
#ifndef RPS3_RUNNER_SIM_OUTPUT_H
#define RPS3_RUNNER_SIM_OUTPUT_H

#include <stddef.h>
#include <stdint.h>

#include "scene/scene.h"

/* shapes: [case], [case, time], [case, time, link] */
typedef enum { SIM_C, SIM_CT, SIM_CTL } sim_shape;
/* element types: double (NaN missing), int32 / int64 (-1), string */
typedef enum { SIM_F64, SIM_I32, SIM_I64, SIM_STR } sim_type;

/* X(name, shape, type, units (UDUNITS), long_name (CF), description) */
#define SIM_OUTPUT_FIELDS(X)                                                   \
  X(length, SIM_CTL, SIM_F64, "m", "link length",                              \
    "link length l_i of the simulated plant")                                  \
  X(length_rate, SIM_CTL, SIM_F64, "m/s", "link extension rate",               \
    "link rate dl_i/dt of the plant")                                          \
  X(length_ref, SIM_CTL, SIM_F64, "m", "reference link length",                \
    "reference link length l_d,i: the trajectory's pose through the "          \
    "closed form (after the trajectory: its final pose)")                      \
  X(length_rate_ref, SIM_CTL, SIM_F64, "m/s", "reference link extension rate", \
    "reference link rate dl_d,i/dt (0 after the trajectory)")                  \
  X(tracking_error, SIM_CTL, SIM_F64, "m", "link length tracking error",       \
    "l_d,i - l_i, the controller's e from the true lengths")                   \
  X(force_cmd, SIM_CTL, SIM_F64, "N", "commanded actuating force",             \
    "force commanded by the controller at the last tick before t "             \
    "(held over the control period ending at t); NaN at t = 0")                \
  X(force, SIM_CTL, SIM_F64, "N", "applied actuating force",                   \
    "force applied to the link: force_cmd after saturation at fmax")           \
  X(theta, SIM_CTL, SIM_F64, "rad", "link angle to the base plane",            \
    "angle theta_i of link i to the base")                                     \
  X(alpha, SIM_CT, SIM_F64, "rad", "platform precession angle",                \
    "precession angle alpha of the platform")                                  \
  X(beta, SIM_CT, SIM_F64, "rad", "platform nutation angle",                   \
    "nutation angle beta of the platform")                                     \
  X(z_c, SIM_CT, SIM_F64, "m", "platform centre height",                       \
    "height z_c of the platform centre")                                       \
  X(x_c, SIM_CT, SIM_F64, "m", "platform centre x",                            \
    "platform centre x_c, eq. (3) times R")                                    \
  X(y_c, SIM_CT, SIM_F64, "m", "platform centre y",                            \
    "platform centre y_c, eq. (4) times R")                                    \
  X(alpha_ref, SIM_CT, SIM_F64, "rad", "reference platform precession angle",  \
    "reference alpha (the trajectory)")                                        \
  X(beta_ref, SIM_CT, SIM_F64, "rad", "reference platform nutation angle",     \
    "reference beta")                                                          \
  X(z_c_ref, SIM_CT, SIM_F64, "m", "reference platform centre height",         \
    "reference z_c")                                                           \
  X(x_c_ref, SIM_CT, SIM_F64, "m", "reference platform centre x",              \
    "reference x_c")                                                           \
  X(y_c_ref, SIM_CT, SIM_F64, "m", "reference platform centre y",              \
    "reference y_c")                                                           \
  X(kinetic_energy, SIM_CT, SIM_F64, "J", "kinetic energy",                    \
    "kinetic energy T of the plant")                                           \
  X(potential_energy, SIM_CT, SIM_F64, "J", "potential energy",                \
    "potential energy P of the plant (zero on the base plane)")                \
  X(work_actuators, SIM_CT, SIM_F64, "J", "work of the actuators",             \
    "work of the applied forces since t = 0, integral of F . dl/dt")           \
  X(work_friction, SIM_CT, SIM_F64, "J", "work of the pin friction",           \
    "work of the pin friction since t = 0 (<= 0)")                             \
  X(energy_residual, SIM_CT, SIM_F64, "J", "energy balance residual",          \
    "T + P - (T + P)(0) - work_actuators - work_friction: the "                \
    "integration error")                                                       \
  X(tracking_error_max, SIM_C, SIM_F64, "m",                                   \
    "largest link length tracking error",                                      \
    "largest abs(tracking_error) over the samples reached and the "            \
    "links")                                                                   \
  X(status, SIM_C, SIM_I32, "1", "simulation status",                          \
    "0 = ok, else the rps3_status that stopped the simulation; -1000 "         \
    "= not computed")                                                          \
  X(failed_at, SIM_C, SIM_I32, "1", "first sample not reached",                \
    "first time index not reached (NaN from there on), -1 if none")            \
  X(failed_time, SIM_C, SIM_F64, "s", "time of the failure",                   \
    "simulated time of the failure, NaN if none")                              \
  X(nsteps, SIM_C, SIM_I64, "1", "integrator steps", "integrator steps")       \
  X(nevals, SIM_C, SIM_I64, "1", "forward dynamics evaluations",               \
    "forward dynamics evaluations")                                            \
  X(nticks, SIM_C, SIM_I64, "1", "controller ticks",                           \
    "controller calls at the control rate")                                    \
  X(nsat, SIM_C, SIM_I64, "1", "saturated ticks",                              \
    "ticks with a saturated actuator")                                         \
  X(message, SIM_C, SIM_STR, "1", "failure message",                           \
    "why the case failed, empty if it did not")                                \
  X(scene_resolved, SIM_C, SIM_STR, "1", "resolved scene of the case",         \
    "the case's full scene as YAML (no sweep): rerun it alone with "           \
    "rps3-run")

#define SIM_FIELD_ID(name, ...) SIM_##name,
typedef enum { SIM_OUTPUT_FIELDS(SIM_FIELD_ID) SIM_NFIELD } sim_field;
#undef SIM_FIELD_ID

/*
 * The buffer of one window of one case: for each field of shape CT or CTL
 * `points` samples of 1 or 3 doubles, row k of field i at
 * buf[i] + k * columns (NULL for the per-case fields).
 */
typedef struct {
  size_t points; /* samples per window */
  double *buf[SIM_NFIELD];
} sim_window;

/* the per-case values of a case */
typedef struct {
  double tracking_error_max, failed_time;
  int32_t status, failed_at;
  int64_t nsteps, nevals, nticks, nsat;
  char message[640];
  const char *scene_resolved;
} sim_case_values;

/* Allocate the window buffers for `points` samples: 0, or -1. */
int sim_window_alloc(sim_window *w, size_t points);
void sim_window_free(sim_window *w);

typedef struct sim_file sim_file;

/*
 * Create the file at path for the cases of s; nt the most samples of any
 * case; times the common time axis (nt values) or NULL when the grid
 * differs by case (then `time` is a sample index and case_time holds the
 * times).  Chunks are [1, points, (3)], Fletcher-32, deflate at gzip.
 * Returns NULL with a message in err.
 */
sim_file *sim_file_create(const char *path, const scene *s, size_t nt,
                          const double *times, size_t points, int gzip,
                          const char *command_line, char *err, size_t errsz);

/* Write samples [k0, k0 + nk) of case c from the window (and, with `times`
   when the grid differs, its times).  0 or -1 with err set. */
int sim_file_window(sim_file *f, const sim_window *w, size_t c, size_t k0,
                    size_t nk, const double *times, char *err, size_t errsz);

/* Write the per-case values of case c.  0 or -1 with err set. */
int sim_file_case(sim_file *f, const sim_case_values *v, size_t c, char *err,
                  size_t errsz);

/* Close (f freed either way; NULL accepted): 0 or -1 with err set. */
int sim_file_close(sim_file *f, char *err, size_t errsz);

/* Bytes of a file of ncase cases and npoint samples in all, uncompressed
   (the per-case strings estimated): an estimate for the disk check. */
double sim_file_bytes(size_t ncase, size_t npoint);

/* the schema (markdown) on stdout */
void sim_schema_print(void);

#endif /* RPS3_RUNNER_SIM_OUTPUT_H */
