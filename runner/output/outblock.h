/*
 * outblock.h - the schema of every runner file (RPS3_OUTPUT_FIELDS: what
 * the inverse sweep's, the simulation's and the design study's files hold)
 * and a tile of it in memory, the out_block every job fills.  No HDF5.
 */
#ifndef RPS3_RUNNER_OUTBLOCK_H
#define RPS3_RUNNER_OUTBLOCK_H

#include <stddef.h>
#include <stdint.h>

#include "scene/scene.h"

/* the axes of the files */
typedef enum {
  OUT_AX_CASE,
  OUT_AX_TIME, /* or sample, when the time grid differs between cases */
  OUT_AX_LINK,
  OUT_AX_CON,   /* constraint */
  OUT_AX_EFF,   /* physical effect */
  OUT_AX_FLAG,  /* reachability flag */
  OUT_AX_ALPHA, /* the pose grid of a design study */
  OUT_AX_BETA,
  OUT_AX_Z_C,
  OUT_NAXIS
} out_axis;

/* shapes, their axes in out_shape_axes */
typedef enum {
  OUT_C,    /* [case] */
  OUT_CT,   /* [case, time] */
  OUT_CTL,  /* [case, time, link] */
  OUT_CTK,  /* [case, time, constraint] */
  OUT_CTEL, /* [case, time, effect, link] */
  OUT_CL,   /* [case, link] */
  OUT_CF,   /* [case, flag] */
  OUT_CP    /* [case, z_c, beta, alpha] */
} out_shape;
extern const int out_shape_axes[][5]; /* ending at -1 */
extern const char *const out_axis_name[OUT_NAXIS];

/* 1 when a field of shape sh has axis ax */
int out_shape_has(out_shape sh, int ax);

/* element types: double (NaN for missing), int32 and int64 (-1 for
   missing), string */
typedef enum { OUT_F64, OUT_I32, OUT_I64, OUT_STR } out_type;

/* the files a field is in */
#define OUT_INV 1   /* the inverse sweep's */
#define OUT_SIM 2   /* the simulation's */
#define OUT_BOTH 3  /* both */
#define OUT_DES 4   /* every design study's */
#define OUT_TASK 8  /* a design study's with a trajectory (the task) */
#define OUT_POSE 16 /* a design study's with design.per_pose */
#define OUT_DESIGN (OUT_DES | OUT_TASK | OUT_POSE)
#define OUT_IDENT                                     \
  32 /* an identification's: no schema field, its own \
        datasets (exec/ident_run.h) */

/* the CF flag attributes of a field (out_h5.h) */
typedef enum {
  OUT_FLAGS_NONE,
  OUT_FLAGS_STATUS, /* flag_values: every rps3_status, not computed */
  OUT_FLAGS_WARN,   /* flag_masks of the warning bits */
  OUT_FLAGS_REACH   /* flag_masks of the reachability flags */
} out_flags;

/* the fill value of a status: a case not computed (by this shard, or not
   yet); distinct from every rps3_status, RPS3_EINVAL = -1 included */
#define OUT_STATUS_NOT_COMPUTED (-1000)

/*
 * The one table of what a runner file holds per case (per design) and per
 * sample: X(id, name, files, shape, type, flags, units (UDUNITS),
 * long_name (CF), description).  id names the field in the code (OUT_id),
 * name the dataset (a name in several kinds of file with another meaning
 * has a row of each).  The inverse sweep's fields come before the 64th
 * row (out_mask).
 */
#define RPS3_OUTPUT_FIELDS(X)                                                  \
  X(force, force, OUT_INV, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "N",              \
    "actuating force along the link",                                          \
    "total actuating force F_i along link i, eq. (34); positive extends "      \
    "the link")                                                                \
  X(force_by_effect, force_by_effect, OUT_INV, OUT_CTEL, OUT_F64,              \
    OUT_FLAGS_NONE, "N", "actuating force by physical effect",                 \
    "share of each selected effect in the actuating force; the shares "        \
    "sum to force")                                                            \
  X(length, length, OUT_INV, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "m",            \
    "link length", "link length l_i = R L_i, eqs. (5)-(7)")                    \
  X(length_rate, length_rate, OUT_INV, OUT_CTL, OUT_F64, OUT_FLAGS_NONE,       \
    "m/s", "link extension rate",                                              \
    "link extension rate dl_i/dt (NaN when no effect needs rates)")            \
  X(length_accel, length_accel, OUT_INV, OUT_CTL, OUT_F64, OUT_FLAGS_NONE,     \
    "m/s^2", "link extension acceleration",                                    \
    "link extension acceleration d2l_i/dt2 (NaN when no effect needs "         \
    "it)")                                                                     \
  X(theta, theta, OUT_INV, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "rad",            \
    "link angle to the base plane",                                            \
    "angle theta_i between link i and the base plane, eq. (39) or "            \
    "(8)-(10)")                                                                \
  X(alpha, alpha, OUT_INV, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "rad",             \
    "platform precession angle",                                               \
    "precession angle alpha of the platform (Z-Y-Z Euler angles, eq. "         \
    "(2))")                                                                    \
  X(sim_length, length, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "m",        \
    "link length", "link length l_i of the simulated plant")                   \
  X(sim_length_rate, length_rate, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE,   \
    "m/s", "link extension rate", "link rate dl_i/dt of the plant")            \
  X(length_ref, length_ref, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "m",    \
    "reference link length",                                                   \
    "reference link length l_d,i: the trajectory's pose through the "          \
    "closed form (after the trajectory: its final pose)")                      \
  X(length_rate_ref, length_rate_ref, OUT_SIM, OUT_CTL, OUT_F64,               \
    OUT_FLAGS_NONE, "m/s", "reference link extension rate",                    \
    "reference link rate dl_d,i/dt (0 after the trajectory)")                  \
  X(tracking_error, tracking_error, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, \
    "m", "link length tracking error",                                         \
    "l_d,i - l_i, the controller's e from the true lengths")                   \
  X(force_cmd, force_cmd, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "N",      \
    "commanded actuating force",                                               \
    "force commanded by the controller at the last tick before t "             \
    "(held over the control period ending at t); NaN at t = 0")                \
  X(sim_force, force, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "N",          \
    "applied actuating force",                                                 \
    "force applied to the link: force_cmd after saturation at fmax")           \
  X(sim_theta, theta, OUT_SIM, OUT_CTL, OUT_F64, OUT_FLAGS_NONE, "rad",        \
    "link angle to the base plane", "angle theta_i of link i to the base")     \
  X(sim_alpha, alpha, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "rad",         \
    "platform precession angle", "precession angle alpha of the platform")     \
  X(beta, beta, OUT_BOTH, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "rad",              \
    "platform nutation angle", "nutation angle beta of the platform")          \
  X(z_c, z_c, OUT_BOTH, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",                  \
    "platform centre height", "height z_c of the platform centre")             \
  X(x_c, x_c, OUT_BOTH, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",                  \
    "platform centre x", "platform centre x_c, eq. (3) times R")               \
  X(y_c, y_c, OUT_BOTH, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",                  \
    "platform centre y", "platform centre y_c, eq. (4) times R")               \
  X(lambda, lambda, OUT_INV, OUT_CTK, OUT_F64, OUT_FLAGS_NONE, "N/m",          \
    "constraint Lagrange multiplier",                                          \
    "Lagrange multipliers lambda_k of the constraints (8)-(10) written "       \
    "in metres (f_k = norm(b_i - b_j)^2 - 3 r^2), eq. (34); NaN under "        \
    "newton_euler, which does not compute them")                               \
  X(energy_residual, energy_residual, OUT_INV, OUT_CT, OUT_F64,                \
    OUT_FLAGS_NONE, "W", "energy-rate residual",                               \
    "actuator power + friction power - dT/dt - dP/dt; zero up to "             \
    "rounding when the forces are right (NaN when solver.outputs leaves "      \
    "out certify)")                                                            \
  X(energy_scale, energy_scale, OUT_INV, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "W", \
    "energy-rate scale",                                                       \
    "sum of the magnitudes of the terms of energy_residual, its scale")        \
  X(condition, condition, OUT_INV, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "1",       \
    "condition number of the constraint Jacobian",                             \
    "1-norm condition number of the constraint Jacobian df/dtheta")            \
  X(transmission, transmission, OUT_INV, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "1", \
    "force transmission",                                                      \
    "force transmission: largest actuator force per unit platform load "       \
    "(force, moment / R); warn above 100, refused above 1e8")                  \
  X(solve_niter, solve_niter, OUT_INV, OUT_CT, OUT_I32, OUT_FLAGS_NONE, "1",   \
    "theta solve iterations",                                                  \
    "iterations of the multiroot theta solve (0 for closed_form; -1 "          \
    "missing)")                                                                \
  X(solve_resid, solve_resid, OUT_INV, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "1",   \
    "theta solve residual",                                                    \
    "max_k abs(f_k) after the theta solve, lengths in units of R")             \
  X(warn, warn, OUT_INV, OUT_CT, OUT_I32, OUT_FLAGS_WARN, "1", "warning bits", \
    "warning bits: 1 ill-conditioned lambda system, 2 alpha undefined, "       \
    "4 assembly mode changed, 8 transmission above trans_warn (-1 "            \
    "missing)")                                                                \
  X(status, status, OUT_INV, OUT_C, OUT_I32, OUT_FLAGS_STATUS, "1",            \
    "status of the case",                                                      \
    "0 = ok, else the rps3_status code of the first failing sample; "          \
    "-1000 = not computed (a case of another shard, or of a killed "           \
    "part)")                                                                   \
  X(failed_at, failed_at, OUT_INV, OUT_C, OUT_I32, OUT_FLAGS_NONE, "1",        \
    "time index of the first failing sample",                                  \
    "time index of the first failing sample, -1 if none")                      \
  X(alpha_ref, alpha_ref, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "rad",     \
    "reference platform precession angle", "reference alpha (the trajectory)") \
  X(beta_ref, beta_ref, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "rad",       \
    "reference platform nutation angle", "reference beta")                     \
  X(z_c_ref, z_c_ref, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",           \
    "reference platform centre height", "reference z_c")                       \
  X(x_c_ref, x_c_ref, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",           \
    "reference platform centre x", "reference x_c")                            \
  X(y_c_ref, y_c_ref, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE, "m",           \
    "reference platform centre y", "reference y_c")                            \
  X(kinetic_energy, kinetic_energy, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE,  \
    "J", "kinetic energy", "kinetic energy T of the plant")                    \
  X(potential_energy, potential_energy, OUT_SIM, OUT_CT, OUT_F64,              \
    OUT_FLAGS_NONE, "J", "potential energy",                                   \
    "potential energy P of the plant (zero on the base plane)")                \
  X(work_actuators, work_actuators, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE,  \
    "J", "work of the actuators",                                              \
    "work of the applied forces since t = 0, integral of F . dl/dt")           \
  X(work_friction, work_friction, OUT_SIM, OUT_CT, OUT_F64, OUT_FLAGS_NONE,    \
    "J", "work of the pin friction",                                           \
    "work of the pin friction since t = 0 (<= 0)")                             \
  X(sim_energy_residual, energy_residual, OUT_SIM, OUT_CT, OUT_F64,            \
    OUT_FLAGS_NONE, "J", "energy balance residual",                            \
    "T + P - (T + P)(0) - work_actuators - work_friction: the "                \
    "integration error")                                                       \
  X(tracking_error_max, tracking_error_max, OUT_SIM, OUT_C, OUT_F64,           \
    OUT_FLAGS_NONE, "m", "largest link length tracking error",                 \
    "largest abs(tracking_error) over the samples reached and the "            \
    "links")                                                                   \
  X(sim_status, status, OUT_SIM, OUT_C, OUT_I32, OUT_FLAGS_STATUS, "1",        \
    "simulation status",                                                       \
    "0 = ok, else the rps3_status that stopped the simulation; -1000 "         \
    "= not computed")                                                          \
  X(sim_failed_at, failed_at, OUT_SIM, OUT_C, OUT_I32, OUT_FLAGS_NONE, "1",    \
    "first sample not reached",                                                \
    "first time index not reached (NaN from there on), -1 if none")            \
  X(failed_time, failed_time, OUT_SIM, OUT_C, OUT_F64, OUT_FLAGS_NONE, "s",    \
    "time of the failure", "simulated time of the failure, NaN if none")       \
  X(nsteps, nsteps, OUT_SIM, OUT_C, OUT_I64, OUT_FLAGS_NONE, "1",              \
    "integrator steps", "integrator steps")                                    \
  X(nevals, nevals, OUT_SIM, OUT_C, OUT_I64, OUT_FLAGS_NONE, "1",              \
    "forward dynamics evaluations", "forward dynamics evaluations")            \
  X(nticks, nticks, OUT_SIM, OUT_C, OUT_I64, OUT_FLAGS_NONE, "1",              \
    "controller ticks", "controller calls at the control rate")                \
  X(nsat, nsat, OUT_SIM, OUT_C, OUT_I64, OUT_FLAGS_NONE, "1",                  \
    "saturated ticks", "ticks with a saturated actuator")                      \
  X(message, message, OUT_BOTH, OUT_C, OUT_STR, OUT_FLAGS_NONE, "1",           \
    "failure message", "why the case failed, empty if it did not")             \
  X(scene_resolved, scene_resolved, OUT_BOTH, OUT_C, OUT_STR, OUT_FLAGS_NONE,  \
    "1", "resolved scene of the case",                                         \
    "the case's full scene as YAML (no sweep): rerun it alone with "           \
    "rps3-run")                                                                \
  X(des_status, status, OUT_DES, OUT_C, OUT_I32, OUT_FLAGS_STATUS, "1",        \
    "status of the design",                                                    \
    "0 = evaluated (an empty workspace included: nreach = 0), else the "       \
    "rps3_status that stopped it; -1000 = not computed")                       \
  X(des_message, message, OUT_DES, OUT_C, OUT_STR, OUT_FLAGS_NONE, "1",        \
    "message", "why the design failed, empty if it did not")                   \
  X(nreach, nreach, OUT_DES, OUT_C, OUT_I64, OUT_FLAGS_NONE, "1",              \
    "reachable poses",                                                         \
    "poses of the grid in the workspace (no flag set); 0: an empty workspace") \
  X(reach_fraction, reach_fraction, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE,   \
    "1", "reachable fraction", "nreach over the poses of the grid")            \
  X(volume, volume, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m rad^2",        \
    "workspace volume",                                                        \
    "nreach times the volume of a grid cell in (alpha, beta, z_c)")            \
  X(gti, gti, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "1",                    \
    "global transmission index",                                               \
    "mean local transmission index LTI over the reachable poses")              \
  X(good_fraction, good_fraction, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE,     \
    "1", "good-transmission fraction",                                         \
    "reachable poses with LTI >= design.good_lti, over nreach")                \
  X(lti_min, lti_min, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "1",            \
    "least LTI", "least local transmission index over the reachable poses")    \
  X(cond_h_max, cond_h_max, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "1",      \
    "largest homogeneous condition number",                                    \
    "largest homogeneous condition number over the reachable poses")           \
  X(trans_max, trans_max, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "1",        \
    "largest force transmission",                                              \
    "largest force transmission (actuator force per unit platform load) over " \
    "the reachable poses")                                                     \
  X(xc_max, xc_max, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m",              \
    "largest parasitic x_c",                                                   \
    "largest abs(x_c), eq. (3), over the reachable poses")                     \
  X(yc_max, yc_max, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m",              \
    "largest parasitic y_c",                                                   \
    "largest abs(y_c), eq. (4), over the reachable poses")                     \
  X(spin_max, spin_max, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "rad",        \
    "largest parasitic spin",                                                  \
    "largest abs(spin), the yaw of the platform about the vertical, over the " \
    "reachable poses")                                                         \
  X(l_lo, l_lo, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m",                  \
    "shortest link used", "shortest link length over the reachable poses")     \
  X(l_hi, l_hi, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m",                  \
    "longest link used", "longest link length over the reachable poses")       \
  X(flags_any, flags_any, OUT_DES, OUT_C, OUT_I32, OUT_FLAGS_REACH, "1",       \
    "reasons for unreachable poses",                                           \
    "OR of the reachability flags of every pose of the grid")                  \
  X(nflag, nflag, OUT_DES, OUT_CF, OUT_I64, OUT_FLAGS_NONE, "1",               \
    "unreachable poses by reason", "poses of the grid with each flag set")     \
  X(link_mass, link_mass, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "kg",       \
    "link mass of the design",                                                 \
    "m of the design's model: actuator body plus rod (rps3_design_model)")     \
  X(link_d, link_d, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "m",              \
    "link centroid",                                                           \
    "d of the design's model: pin joint to the link's centroid")               \
  X(link_Ic, link_Ic, OUT_DES, OUT_C, OUT_F64, OUT_FLAGS_NONE, "kg m^2",       \
    "link inertia of the design",                                              \
    "link_Ic of the design's model, about the centroid and the pin axis")      \
  X(task_status, task_status, OUT_TASK, OUT_C, OUT_I32, OUT_FLAGS_STATUS, "1", \
    "status of the task",                                                      \
    "0 = the design runs the whole trajectory; RPS3_EREACH = a sample is "     \
    "outside its workspace (task_fail_time); -1000 = not computed")            \
  X(task_message, task_message, OUT_TASK, OUT_C, OUT_STR, OUT_FLAGS_NONE, "1", \
    "task message", "where and why the task left the workspace, else empty")   \
  X(task_fail_time, task_fail_time, OUT_TASK, OUT_C, OUT_F64, OUT_FLAGS_NONE,  \
    "s", "time the task left the workspace",                                   \
    "time of the first sample outside the workspace, NaN if none")             \
  X(task_fail_flags, task_fail_flags, OUT_TASK, OUT_C, OUT_I32,                \
    OUT_FLAGS_REACH, "1", "why the task left the workspace",                   \
    "reachability flags of that sample (0: none, or rps3_inverse failed)")     \
  X(task_lti_min, task_lti_min, OUT_TASK, OUT_C, OUT_F64, OUT_FLAGS_NONE, "1", \
    "least LTI along the task",                                                \
    "least local transmission index over the samples before a failure")        \
  X(task_F_peak, task_F_peak, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE, "N",  \
    "peak actuator force", "max over the samples of abs(F_i)")                 \
  X(task_F_rms, task_F_rms, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE, "N",    \
    "RMS actuator force", "sqrt(mean over the samples of F_i^2)")              \
  X(task_P_peak, task_P_peak, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE, "W",  \
    "peak actuator power", "max over the samples of abs(F_i dl_i/dt)")         \
  X(task_v_peak, task_v_peak, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE,       \
    "m/s", "peak link rate", "max over the samples of abs(dl_i/dt)")           \
  X(task_l_lo, task_l_lo, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE, "m",      \
    "shortest link along the task", "min over the samples of l_i")             \
  X(task_l_hi, task_l_hi, OUT_TASK, OUT_CL, OUT_F64, OUT_FLAGS_NONE, "m",      \
    "longest link along the task", "max over the samples of l_i")              \
  X(pose_flags, pose_flags, OUT_POSE, OUT_CP, OUT_I32, OUT_FLAGS_REACH, "1",   \
    "reachability flags of the pose", "0 when reachable, else the reasons")    \
  X(lti, lti, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "1",                  \
    "local transmission index",                                                \
    "min(OTI, CTI) at the pose; NaN where it does not assemble")               \
  X(oti, oti, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "1",                  \
    "output transmission index",                                               \
    "least cosine of the actuators' pressure angles")                          \
  X(cti, cti, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "1",                  \
    "constraint transmission index",                                           \
    "least cosine of the constraint wrenches' pressure angles")                \
  X(cond_h, cond_h, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "1",            \
    "homogeneous condition number",                                            \
    "2-norm condition number of the Jacobian with moments over design.length") \
  X(des_transmission, transmission, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, \
    "1", "force transmission", "actuator force per unit platform load")        \
  X(des_x_c, x_c, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "m",              \
    "parasitic x_c", "platform centre x_c, eq. (3) times R")                   \
  X(des_y_c, y_c, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "m",              \
    "parasitic y_c", "platform centre y_c, eq. (4) times R")                   \
  X(spin, spin, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "rad",              \
    "parasitic spin", "yaw of the platform about the vertical")                \
  X(clearance, clearance, OUT_POSE, OUT_CP, OUT_F64, OUT_FLAGS_NONE, "m",      \
    "link clearance",                                                          \
    "least distance between two link axes minus twice the link radius")        \
  X(des_scene_resolved, scene_resolved, OUT_DES, OUT_C, OUT_STR,               \
    OUT_FLAGS_NONE, "1", "resolved scene",                                     \
    "the design's full scene as YAML (no sweep): rerun it alone with "         \
    "rps3-run")

#define OUT_FIELD_ID(id, ...) OUT_##id,
typedef enum { RPS3_OUTPUT_FIELDS(OUT_FIELD_ID) OUT_NFIELD } out_field;
#undef OUT_FIELD_ID

/* a row of the schema, and the table (outblock.c) */
typedef struct {
  const char *name;
  int files; /* the OUT_INV, OUT_SIM, ... bits */
  out_shape shape;
  out_type type;
  out_flags flags;
  const char *units;     /* UDUNITS-2 spelling */
  const char *long_name; /* CF long_name */
  const char *doc;
} out_field_info;
extern const out_field_info out_field_table[OUT_NFIELD];

/* a set of the inverse sweep's fields: bit i for field i (i < 64) */
typedef uint64_t out_mask;

/* 1 when field i is in mask (0 from the 64th field on) */
#define OUT_HAS(mask, i) ((i) < 64 && ((mask) >> ((i)&63) & 1))

/* every field of the inverse sweep's file */
out_mask out_fields_all(void);

/* --fields: a comma-separated list of per-sample fields ("force,length")
   into *mask, with every per-case field (what a reader needs).  Returns 0,
   or -1 with err naming the unknown name and listing the valid ones. */
int out_fields_parse(const char *list, out_mask *mask, char *err, size_t errsz);

/* the per-sample fields of mask, comma-separated, in schema order, into
   buf: the root attribute `fields` */
const char *out_fields_text(out_mask mask, char *buf, size_t sz);

/* the root attribute `fields` of a file of the kinds `files`: an inverse
   sweep's, out_fields_text; a design study's, "design" and "task" and
   "per_pose" when it has those fields; into buf */
const char *out_fields_attr(int files, out_mask mask, char *buf, size_t sz);

/*
 * The buffers of one tile: up to `cases` cases of up to `points` samples.
 * buf[i], field i's buffer (NULL when the block's files lack the field),
 * is [cases][points][columns] (C order, the layout of the hyperslab),
 * strings one pointer per case.  A field without a time axis is
 * [cases][columns]; of a design study's per-pose fields the columns are
 * the poses, `points`.
 */
typedef struct {
  size_t cases;             /* case slots */
  size_t points;            /* samples per slot */
  int neffect;              /* effects in force_by_effect */
  int effect[RPS3_NEFFECT]; /* their effect indices, in file order */
  void *buf[OUT_NFIELD];
  double *t;        /* time of each sample [cases][points] */
  scene_text *yaml; /* per slot: scene_resolved's storage */
  char (*msg)[320]; /* per slot: message's storage */
  out_mask fields;  /* the fields the file gets (--fields) */
  /* scratch of the batch path (exec/sweep.c): OUT_BATCH points, structure of
     arrays, OUT_BATCH_DOUBLES and OUT_BATCH_INTS values a point */
  double *bx;
  int *bi;
  /* the tile's per-sample chunks as the file stores them (out_pack), or
     packed 0: out_write then hands the buffers to HDF5's filters */
  int packed;
  unsigned char *pk_buf; /* the stored chunks back to back */
  size_t pk_len, pk_cap;
  struct out_chunk *pk; /* [npk]: where each chunk goes */
  size_t npk, pk_max;
  unsigned char *pk_tmp; /* one chunk before deflate */
  size_t pk_tmp_cap;
} out_block;

/* the buffer of field OUT_id of block b, as its element type */
#define OUT_D(b, id) ((double *)(b)->buf[OUT_##id])
#define OUT_I(b, id) ((int32_t *)(b)->buf[OUT_##id])
#define OUT_L(b, id) ((int64_t *)(b)->buf[OUT_##id])
#define OUT_S(b, id) ((char **)(b)->buf[OUT_##id])

/* points per call of rps3_inverse_batch in the runner, and the scratch
   they need (exec/sweep.c): time, pose and its rates, lengths, theta, F,
   lambda, F_effect of every effect, link rates and accelerations, centre;
   status, warn, niter */
#define OUT_BATCH 256
#define OUT_BATCH_DOUBLES (1 + 9 + 12 + 3 * RPS3_NEFFECT + 9)
#define OUT_BATCH_INTS 3

/* a packed chunk: pk_buf[off, off + size) is chunk (c0, k0) of field
   (OUT_NFIELD: case_time), filters applied; or, when direct, the bytes
   [off, off + size) of the field's own buffer (a whole uncompressed chunk
   at the buffer's end, its checksum in the buffer's OUT_SLACK bytes) */
typedef struct out_chunk {
  int field;
  int direct;
  size_t c0, k0;
  size_t off, size;
} out_chunk;

/* bytes past the end of each per-sample buffer of a block (and of t): the
   Fletcher-32 checksum of a chunk stored from the buffer itself */
#define OUT_SLACK 8

/* what out_pack needs of a file: plain numbers, read by any thread */
typedef struct {
  size_t tc, q;    /* chunk extents along case and time */
  int gzip;        /* deflate level, 0 for none */
  out_mask fields; /* the fields written */
  int case_time;   /* 1: case_time is written */
} out_layout;

/*
 * Pack the per-sample fields (and case_time) of a tile -- slots [0, nc) of
 * b, cases c0 .., samples [k0, k0 + nk), on chunk boundaries -- into whole
 * chunks as HDF5 stores them: deflate at L->gzip, then the Fletcher-32
 * checksum, the chunk past the tile filled.  No HDF5 call, so worker
 * threads pack while the writing thread writes (H5Dwrite_chunk).  Returns
 * 0, or -1 (out of memory, or zlib failed).
 */
int out_pack(const out_layout *L, out_block *b, size_t c0, size_t nc, size_t k0,
             size_t nk);

/* values of a shape per (case, sample), or per case when it has no time
   axis; n: the effects of CTEL, the poses of CP */
size_t out_columns(out_shape shape, size_t n);

/* bytes of an element of a type (a string: its pointer) */
size_t out_type_size(out_type type);

/* the fill value of field i: NaN, -1, OUT_STATUS_NOT_COMPUTED of a
   status; NULL for a string (HDF5's, empty) */
const void *out_fill(int i);

/* n fill values of field i (not a string) at dst */
void out_fill_n(void *dst, size_t n, int i);

/* Allocate a block for the fields of the files `files` (OUT_INV, ...);
   returns 0, or -1 (out of memory, nothing leaks). */
int out_block_alloc(out_block *b, int files, size_t cases, size_t points,
                    int effects);

/* Free a block's buffers; a zeroed block is accepted. */
void out_block_free(out_block *b);

/* Fill slot s from sample k on with the missing values (NaN, -1). */
void out_block_blank(out_block *b, size_t slot, size_t k);

/* print the schema of the files `files` as markdown on stdout: name,
   dimensions, type, units, (of a design study, in which files,)
   description */
void out_schema_print(int files);

#endif /* RPS3_RUNNER_OUTBLOCK_H */
