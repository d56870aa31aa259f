/*
 * design_output.h - the HDF5 file of a design study (scene/design.h): one
 * row per design (the `case` dimension, the swept keys its coordinates, as
 * a sweep's file), the summaries of rps3_design_eval over the pose grid,
 * the task's requirements (rps3_design_task_eval) when the scene has a
 * trajectory, and optionally the indices of every pose ([case, z_c, beta,
 * alpha]).  The conventions of the sweep's files (output.h): CF-1.10,
 * `units` and `long_name` on every variable, dimension scales, Fletcher-32
 * on every chunk, the scene verbatim and scene_resolved per design, a
 * `status` whose fill is OUT_STATUS_NOT_COMPUTED, the root attributes that
 * `merge` and `--resume` read: a part of a sharded design study merges and
 * joins as a sweep's part does (every chunk row is one work unit).
 *
 * DESIGN_OUT_FIELDS is the one table of the file's variables: it drives
 * the tile buffers, the datasets, the writes and `rps3-run --design-schema`
 * (docs/runner.md).
 */
#ifndef RPS3_RUNNER_DESIGN_OUTPUT_H
#define RPS3_RUNNER_DESIGN_OUTPUT_H

#include <stddef.h>
#include <stdint.h>

#include "output.h"

/* shapes: [case], [case, link], [case, flag], [case, z_c, beta, alpha] */
enum { DS_C, DS_CL, DS_CF, DS_CP };
/* element types */
enum { DT_F64, DT_I32, DT_I64, DT_STR };
/* which files have a variable: always, with a trajectory (the task), with
   design.per_pose */
enum { DW_ALL, DW_TASK, DW_POSE };

/*
 * DESIGN_OUT_FIELDS X(ID, NAME, SHAPE, TYPE, WHEN, UNITS, LONG_NAME, DOC)
 */
#define DESIGN_OUT_FIELDS(X)                                                   \
  X(DO_status, "status", DS_C, DT_I32, DW_ALL, "1", "status of the design",    \
    "0 = evaluated (an empty workspace included: nreach = 0), else the "       \
    "rps3_status that stopped it; -1000 = not computed")                       \
  X(DO_message, "message", DS_C, DT_STR, DW_ALL, "1", "message",               \
    "why the design failed, empty if it did not")                              \
  X(DO_nreach, "nreach", DS_C, DT_I64, DW_ALL, "1", "reachable poses",         \
    "poses of the grid in the workspace (no flag set); 0: an empty "           \
    "workspace")                                                               \
  X(DO_reach_fraction, "reach_fraction", DS_C, DT_F64, DW_ALL, "1",            \
    "reachable fraction", "nreach over the poses of the grid")                 \
  X(DO_volume, "volume", DS_C, DT_F64, DW_ALL, "m rad^2", "workspace volume",  \
    "nreach times the volume of a grid cell in (alpha, beta, z_c)")            \
  X(DO_gti, "gti", DS_C, DT_F64, DW_ALL, "1", "global transmission index",     \
    "mean local transmission index LTI over the reachable poses")              \
  X(DO_good_fraction, "good_fraction", DS_C, DT_F64, DW_ALL, "1",              \
    "good-transmission fraction",                                              \
    "reachable poses with LTI >= design.good_lti, over nreach")                \
  X(DO_lti_min, "lti_min", DS_C, DT_F64, DW_ALL, "1", "least LTI",             \
    "least local transmission index over the reachable poses")                 \
  X(DO_cond_h_max, "cond_h_max", DS_C, DT_F64, DW_ALL, "1",                    \
    "largest homogeneous condition number",                                    \
    "largest homogeneous condition number over the reachable poses")           \
  X(DO_trans_max, "trans_max", DS_C, DT_F64, DW_ALL, "1",                      \
    "largest force transmission",                                              \
    "largest force transmission (actuator force per unit platform load) "      \
    "over the reachable poses")                                                \
  X(DO_xc_max, "xc_max", DS_C, DT_F64, DW_ALL, "m", "largest parasitic x_c",   \
    "largest abs(x_c), eq. (3), over the reachable poses")                     \
  X(DO_yc_max, "yc_max", DS_C, DT_F64, DW_ALL, "m", "largest parasitic y_c",   \
    "largest abs(y_c), eq. (4), over the reachable poses")                     \
  X(DO_spin_max, "spin_max", DS_C, DT_F64, DW_ALL, "rad",                      \
    "largest parasitic spin",                                                  \
    "largest abs(spin), the yaw of the platform about the vertical, over the " \
    "reachable poses")                                                         \
  X(DO_l_lo, "l_lo", DS_C, DT_F64, DW_ALL, "m", "shortest link used",          \
    "shortest link length over the reachable poses")                           \
  X(DO_l_hi, "l_hi", DS_C, DT_F64, DW_ALL, "m", "longest link used",           \
    "longest link length over the reachable poses")                            \
  X(DO_flags_any, "flags_any", DS_C, DT_I32, DW_ALL, "1",                      \
    "reasons for unreachable poses",                                           \
    "OR of the reachability flags of every pose of the grid")                  \
  X(DO_nflag, "nflag", DS_CF, DT_I64, DW_ALL, "1",                             \
    "unreachable poses by reason", "poses of the grid with each flag set")     \
  X(DO_link_mass, "link_mass", DS_C, DT_F64, DW_ALL, "kg",                     \
    "link mass of the design",                                                 \
    "m of the design's model: actuator body plus rod (rps3_design_model)")     \
  X(DO_link_d, "link_d", DS_C, DT_F64, DW_ALL, "m", "link centroid",           \
    "d of the design's model: pin joint to the link's centroid")               \
  X(DO_link_Ic, "link_Ic", DS_C, DT_F64, DW_ALL, "kg m^2",                     \
    "link inertia of the design",                                              \
    "link_Ic of the design's model, about the centroid and the pin axis")      \
  X(DO_task_status, "task_status", DS_C, DT_I32, DW_TASK, "1",                 \
    "status of the task",                                                      \
    "0 = the design runs the whole trajectory; RPS3_EREACH = a sample is "     \
    "outside its workspace (task_fail_time); -1000 = not computed")            \
  X(DO_task_message, "task_message", DS_C, DT_STR, DW_TASK, "1",               \
    "task message", "where and why the task left the workspace, else empty")   \
  X(DO_task_fail_time, "task_fail_time", DS_C, DT_F64, DW_TASK, "s",           \
    "time the task left the workspace",                                        \
    "time of the first sample outside the workspace, NaN if none")             \
  X(DO_task_fail_flags, "task_fail_flags", DS_C, DT_I32, DW_TASK, "1",         \
    "why the task left the workspace",                                         \
    "reachability flags of that sample (0: none, or rps3_inverse failed)")     \
  X(DO_task_lti_min, "task_lti_min", DS_C, DT_F64, DW_TASK, "1",               \
    "least LTI along the task",                                                \
    "least local transmission index over the samples before a failure")        \
  X(DO_task_F_peak, "task_F_peak", DS_CL, DT_F64, DW_TASK, "N",                \
    "peak actuator force", "max over the samples of abs(F_i)")                 \
  X(DO_task_F_rms, "task_F_rms", DS_CL, DT_F64, DW_TASK, "N",                  \
    "RMS actuator force", "sqrt(mean over the samples of F_i^2)")              \
  X(DO_task_P_peak, "task_P_peak", DS_CL, DT_F64, DW_TASK, "W",                \
    "peak actuator power", "max over the samples of abs(F_i dl_i/dt)")         \
  X(DO_task_v_peak, "task_v_peak", DS_CL, DT_F64, DW_TASK, "m/s",              \
    "peak link rate", "max over the samples of abs(dl_i/dt)")                  \
  X(DO_task_l_lo, "task_l_lo", DS_CL, DT_F64, DW_TASK, "m",                    \
    "shortest link along the task", "min over the samples of l_i")             \
  X(DO_task_l_hi, "task_l_hi", DS_CL, DT_F64, DW_TASK, "m",                    \
    "longest link along the task", "max over the samples of l_i")              \
  X(DO_pose_flags, "pose_flags", DS_CP, DT_I32, DW_POSE, "1",                  \
    "reachability flags of the pose", "0 when reachable, else the reasons")    \
  X(DO_lti, "lti", DS_CP, DT_F64, DW_POSE, "1", "local transmission index",    \
    "min(OTI, CTI) at the pose; NaN where it does not assemble")               \
  X(DO_oti, "oti", DS_CP, DT_F64, DW_POSE, "1", "output transmission index",   \
    "least cosine of the actuators' pressure angles")                          \
  X(DO_cti, "cti", DS_CP, DT_F64, DW_POSE, "1",                                \
    "constraint transmission index",                                           \
    "least cosine of the constraint wrenches' pressure angles")                \
  X(DO_cond_h, "cond_h", DS_CP, DT_F64, DW_POSE, "1",                          \
    "homogeneous condition number",                                            \
    "2-norm condition number of the Jacobian with moments over "               \
    "design.length")                                                           \
  X(DO_transmission, "transmission", DS_CP, DT_F64, DW_POSE, "1",              \
    "force transmission", "actuator force per unit platform load")             \
  X(DO_x_c, "x_c", DS_CP, DT_F64, DW_POSE, "m", "parasitic x_c",               \
    "platform centre x_c, eq. (3) times R")                                    \
  X(DO_y_c, "y_c", DS_CP, DT_F64, DW_POSE, "m", "parasitic y_c",               \
    "platform centre y_c, eq. (4) times R")                                    \
  X(DO_spin, "spin", DS_CP, DT_F64, DW_POSE, "rad", "parasitic spin",          \
    "yaw of the platform about the vertical")                                  \
  X(DO_clearance, "clearance", DS_CP, DT_F64, DW_POSE, "m", "link clearance",  \
    "least distance between two link axes minus twice the link radius")        \
  X(DO_scene_resolved, "scene_resolved", DS_C, DT_STR, DW_ALL, "1",            \
    "resolved scene",                                                          \
    "the design's full scene as YAML (no sweep): rerun it alone with "         \
    "rps3-run")

#define DESIGN_OUT_ID(ID, ...) ID,
enum { DESIGN_OUT_FIELDS(DESIGN_OUT_ID) DESIGN_NFIELD };
#undef DESIGN_OUT_ID

/* one row of DESIGN_OUT_FIELDS */
typedef struct {
  const char *name;
  int shape, type, when;
  const char *units, *long_name, *doc;
} design_field_info;

extern const design_field_info design_field_table[DESIGN_NFIELD];

/* a tile: the rows of up to `cap` designs, every variable of the file */
typedef struct {
  size_t cap;               /* designs */
  size_t npose;             /* poses of the grid */
  int task;                 /* the task's variables are written */
  int per_pose;             /* the per-pose variables are written */
  void *buf[DESIGN_NFIELD]; /* cap x (1, 3, RPS3_DESIGN_NFLAG or npose)
                               elements (char * for strings, owned) */
} design_tile;

/* 1 when the file of a tile like t holds variable i */
int design_field_written(const design_tile *t, int i);

/* elements per design of variable i */
size_t design_field_inner(const design_tile *t, int i);

/* bytes per design of the variables a tile like t writes (strings
   excepted: about 64 bytes each are counted) */
size_t design_bytes_per_design(const design_tile *t);

/* the root attribute `fields` of such a file: "design", "task" when it
   has the task's variables, "per_pose" when the per-pose ones */
const char *design_fields_text(const design_tile *t);

/* Allocate a tile; 0 or -1 (out of memory; the tile then frees). */
int design_tile_alloc(design_tile *t, size_t cap, size_t npose, int task,
                      int per_pose);

/* Reset design slot j: NaN, -1, OUT_STATUS_NOT_COMPUTED, empty strings. */
void design_tile_clear(design_tile *t, size_t j);

/* Free a tile (a zeroed one is accepted). */
void design_tile_free(design_tile *t);

typedef struct design_file design_file;

/*
 * Create the file at `path` for the designs of s, in chunks of `unit`
 * designs (a work unit): the scales (case, link, flag, alpha, beta, z_c),
 * the swept keys, the scene and every variable of t's shape.  Returns
 * NULL with a message in err.
 */
design_file *design_out_create(const char *path, const scene *s,
                               const design_tile *t, size_t unit,
                               const out_meta *meta, char *err, size_t errsz);

/* Write slots [0, nc) of t as designs c0 .. c0 + nc - 1; 0 or -1 with err
   set. */
int design_out_write(design_file *f, const design_tile *t, size_t c0, size_t nc,
                     char *err, size_t errsz);

/* Flush and close; 0 or -1 with err set.  f is freed; NULL accepted. */
int design_out_close(design_file *f, char *err, size_t errsz);

/* Print the variable table (markdown) on stdout. */
void design_schema_print(void);

#endif /* RPS3_RUNNER_DESIGN_OUTPUT_H */
