/*
 * output.h - the HDF5 file of a sweep: its schema and a streaming writer.
 *
 * RPS3_OUTPUT_FIELDS is the one table of what a file holds per case and per
 * sample.  It drives the tile buffers, dataset creation, the writes and the
 * units/description attributes.  The coordinates (case, time, link, effect,
 * constraint, the swept keys, case_time) are written by output.c itself.
 *
 * The file is written in tiles: a tile is a run of whole cases, or one
 * window of samples of a single long case.  A tile is one hyperslab write
 * per field, so memory is bounded by the tile size, whatever the sweep size.
 */
#ifndef RPS3_RUNNER_OUTPUT_H
#define RPS3_RUNNER_OUTPUT_H

#include <stddef.h>
#include <stdint.h>

#include <hdf5.h>

#include "scene/scene.h"

/* shapes: C [case], CT [case, time], CTL [case, time, link],
   CTK [case, time, constraint], CTEL [case, time, effect, link] */
typedef enum { OUT_C, OUT_CT, OUT_CTL, OUT_CTK, OUT_CTEL } out_shape;

/* element types: double (NaN for missing), int32 (-1 for missing), string */

/* the fill value of `status`: a case not computed (by this shard, or not
   yet); distinct from every rps3_status, RPS3_EINVAL = -1 included */
#define OUT_STATUS_NOT_COMPUTED (-1000)
typedef enum { OUT_F64, OUT_I32, OUT_STR } out_type;

/* X(name, shape, type, units (UDUNITS), long_name (CF), description) */
#define RPS3_OUTPUT_FIELDS(X)                                                  \
  X(force, OUT_CTL, OUT_F64, "N", "actuating force along the link",            \
    "total actuating force F_i along link i, eq. (34); positive extends "      \
    "the link")                                                                \
  X(force_by_effect, OUT_CTEL, OUT_F64, "N",                                   \
    "actuating force by physical effect",                                      \
    "share of each selected effect in the actuating force; the shares "        \
    "sum to force")                                                            \
  X(length, OUT_CTL, OUT_F64, "m", "link length",                              \
    "link length l_i = R L_i, eqs. (5)-(7)")                                   \
  X(length_rate, OUT_CTL, OUT_F64, "m/s", "link extension rate",               \
    "link extension rate dl_i/dt (NaN when no effect needs rates)")            \
  X(length_accel, OUT_CTL, OUT_F64, "m/s^2", "link extension acceleration",    \
    "link extension acceleration d2l_i/dt2 (NaN when no effect needs "         \
    "it)")                                                                     \
  X(theta, OUT_CTL, OUT_F64, "rad", "link angle to the base plane",            \
    "angle theta_i between link i and the base plane, eq. (39) or "            \
    "(8)-(10)")                                                                \
  X(alpha, OUT_CT, OUT_F64, "rad", "platform precession angle",                \
    "precession angle alpha of the platform (Z-Y-Z Euler angles, eq. "         \
    "(2))")                                                                    \
  X(beta, OUT_CT, OUT_F64, "rad", "platform nutation angle",                   \
    "nutation angle beta of the platform")                                     \
  X(z_c, OUT_CT, OUT_F64, "m", "platform centre height",                       \
    "height z_c of the platform centre")                                       \
  X(x_c, OUT_CT, OUT_F64, "m", "platform centre x",                            \
    "platform centre x_c, eq. (3) times R")                                    \
  X(y_c, OUT_CT, OUT_F64, "m", "platform centre y",                            \
    "platform centre y_c, eq. (4) times R")                                    \
  X(lambda, OUT_CTK, OUT_F64, "N/m", "constraint Lagrange multiplier",         \
    "Lagrange multipliers lambda_k of the constraints (8)-(10) written "       \
    "in metres (f_k = norm(b_i - b_j)^2 - 3 r^2), eq. (34); NaN under "        \
    "newton_euler, which does not compute them")                               \
  X(energy_residual, OUT_CT, OUT_F64, "W", "energy-rate residual",             \
    "actuator power + friction power - dT/dt - dP/dt; zero up to "             \
    "rounding when the forces are right (NaN when solver.certify is "          \
    "false)")                                                                  \
  X(energy_scale, OUT_CT, OUT_F64, "W", "energy-rate scale",                   \
    "sum of the magnitudes of the terms of energy_residual, its scale")        \
  X(condition, OUT_CT, OUT_F64, "1",                                           \
    "condition number of the constraint Jacobian",                             \
    "1-norm condition number of the constraint Jacobian df/dtheta")            \
  X(transmission, OUT_CT, OUT_F64, "1", "force transmission",                  \
    "force transmission: largest actuator force per unit platform load "       \
    "(force, moment / R); warn above 100, refused above 1e8")                  \
  X(solve_niter, OUT_CT, OUT_I32, "1", "theta solve iterations",               \
    "iterations of the multiroot theta solve (0 for closed_form; -1 "          \
    "missing)")                                                                \
  X(solve_resid, OUT_CT, OUT_F64, "1", "theta solve residual",                 \
    "max_k abs(f_k) after the theta solve, lengths in units of R")             \
  X(warn, OUT_CT, OUT_I32, "1", "warning bits",                                \
    "warning bits: 1 ill-conditioned lambda system, 2 alpha undefined, "       \
    "4 assembly mode changed, 8 transmission above trans_warn (-1 "            \
    "missing)")                                                                \
  X(status, OUT_C, OUT_I32, "1", "status of the case",                         \
    "0 = ok, else the rps3_status code of the first failing sample; "          \
    "-1000 = not computed (a case of another shard, or of a killed "           \
    "part)")                                                                   \
  X(failed_at, OUT_C, OUT_I32, "1", "time index of the first failing sample",  \
    "time index of the first failing sample, -1 if none")                      \
  X(message, OUT_C, OUT_STR, "1", "failure message",                           \
    "why the case failed, empty if it did not")                                \
  X(scene_resolved, OUT_C, OUT_STR, "1", "resolved scene of the case",         \
    "the case's full scene as YAML (no sweep): rerun it alone with "           \
    "rps3-run")

#define OUT_FIELD_ID(name, ...) OUT_##name,
typedef enum { RPS3_OUTPUT_FIELDS(OUT_FIELD_ID) OUT_NFIELD } out_field;
#undef OUT_FIELD_ID

/* a row of the schema, and the table (outblock.c) */
typedef struct {
  const char *name;
  out_shape shape;
  out_type type;
  const char *units;     /* UDUNITS-2 spelling */
  const char *long_name; /* CF long_name */
  const char *doc;
} out_field_info;
extern const out_field_info out_field_table[OUT_NFIELD];

/* a set of fields: bit i for field i (OUT_NFIELD < 32) */
typedef uint32_t out_mask;

/* every field */
out_mask out_fields_all(void);

/*
 * --fields: a comma-separated list of per-sample fields ("force,length")
 * into *mask, with every per-case field (status, failed_at, message,
 * scene_resolved: what a reader needs).  Returns 0, or -1 with err naming
 * the unknown name and listing the valid ones.
 */
int out_fields_parse(const char *list, out_mask *mask, char *err,
                     size_t errsz);

/* the per-sample fields of mask, comma-separated, in schema order, into
   buf: the root attribute `fields` */
const char *out_fields_text(out_mask mask, char *buf, size_t sz);

/*
 * The buffers of one tile: up to `cases` cases of up to `points` samples.
 * Each field's buffer is [cases][points][columns] (C order, the layout of
 * the hyperslab), strings are one pointer per case.  Samples of slot s,
 * time index k (counted from the tile's first sample) and column j are at
 * field[(s * points + k) * columns + j].
 */
typedef struct {
  size_t cases;           /* case slots */
  size_t points;          /* samples per slot */
  int neffect;            /* effects in force_by_effect */
  int effect[RPS3_NEFFECT]; /* their effect indices, in file order */
#define OUT_BLOCK_MEMBER(name, shape, type, ...) void *name;
  RPS3_OUTPUT_FIELDS(OUT_BLOCK_MEMBER)
#undef OUT_BLOCK_MEMBER
  double *t;              /* time of each sample [cases][points] */
  scene_text *yaml;       /* per slot: scene_resolved's storage */
  char (*msg)[320];       /* per slot: message's storage */
  out_mask fields;        /* the fields the file gets (--fields) */
  /* scratch of the batch path (compute.c): OUT_BATCH points, structure of
     arrays, OUT_BATCH_DOUBLES and OUT_BATCH_INTS values a point */
  double *bx;
  int *bi;
  /* the tile's per-sample chunks as the file stores them (out_pack), or
     packed 0: out_write then hands the buffers to HDF5's filters */
  int packed;
  unsigned char *pk_buf;  /* the stored chunks back to back */
  size_t pk_len, pk_cap;
  struct out_chunk *pk;   /* [npk]: where each chunk goes */
  size_t npk, pk_max;
  unsigned char *pk_tmp;  /* one chunk before deflate */
  size_t pk_tmp_cap;
} out_block;

/* points per call of rps3_inverse_batch in the runner, and the scratch
   they need: time, pose, rates, accelerations, lengths, theta, F, lambda,
   F_effect of every effect, link rates and accelerations, centre; status,
   warn, niter (the per-point values of one column go to the block
   itself) */
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
  size_t ncase, nt;       /* extents along case and time */
  size_t tc, q;           /* chunk extents along case and time */
  int neffect;
  int gzip;               /* deflate level, 0 for none */
  out_mask fields;        /* the fields written */
  int case_time;          /* 1: case_time is written */
} out_layout;

/*
 * Pack the per-sample fields (and case_time) of a tile -- slots [0, nc) of
 * b, cases c0 .., samples [k0, k0 + nk), k0 and c0 on chunk boundaries --
 * into whole chunks as HDF5 stores them with the file's filters: deflate at
 * L->gzip, then the Fletcher-32 checksum (padding past the tile with the
 * fill values).  Calls no HDF5 function, so worker threads pack while the
 * writing thread writes; out_write then writes the chunks as they are
 * (H5Dwrite_chunk).  Returns 0, or -1 (out of memory, or zlib failed).
 */
int out_pack(const out_layout *L, out_block *b, size_t c0, size_t nc,
             size_t k0, size_t nk);

/* columns of a shape per (case, sample) */
size_t out_columns(out_shape shape, int neffect);

/* Allocate a block; returns 0, or -1 (out of memory, nothing leaks). */
int out_block_alloc(out_block *b, size_t cases, size_t points,
                    int effects);

/* Free a block's buffers; a zeroed block is accepted. */
void out_block_free(out_block *b);

/* Fill slot s from sample k on with the missing values (NaN, -1). */
void out_block_blank(out_block *b, size_t slot, size_t k);

/* the buffer of field i of b */
void *out_block_field(const out_block *b, int i);

/* what the file says about the run */
typedef struct {
  const char *command_line;
  int gzip;               /* deflate level 1-9, 0 for none */
  const char *shard;      /* "K/N" of a part file (merge.h), NULL if whole */
  out_mask fields;        /* the fields written (--fields) */
  const char *inputs;     /* the files the scene read and their SHA-256
                             (inputs.h): root attribute input_files */
} out_meta;

typedef struct out_file out_file;

/*
 * Create the file at `path` (truncating it) for the cases of s: all
 * datasets, dimension scales, attributes, the scene text, the swept keys
 * and, when the grid is common to all cases (grid_common), the time axis
 * from `first`.  nt is the largest number of samples of any case; chunks
 * are [b->cases, chunk_points, ...] (a tile is a whole number of chunks).
 * Returns NULL with a message in err.
 */
out_file *out_create(const char *path, const scene *s,
                     const scene_case *first, size_t nt, int grid_common,
                     size_t chunk_points, const out_block *b,
                     const out_meta *meta, char *err, size_t errsz);

/* the layout of an open file's chunks, for out_pack */
void out_file_layout(const out_file *f, out_layout *L);

/*
 * Write a tile: slots [0, nc) of b hold cases c0 .. c0 + nc - 1, samples
 * [k0, k0 + nk).  Per-case fields (status, message, ...) are written only
 * when with_case is 1.  When b->packed, the per-sample fields are written
 * as the chunks out_pack made of this tile.  Returns 0 or -1 with err set.
 */
int out_write(out_file *f, const out_block *b, size_t c0, size_t nc,
              size_t k0, size_t nk, int with_case, char *err, size_t errsz);

/* Flush and close the file; returns 0 or -1 with err set.  f is freed
   either way; NULL is accepted. */
int out_close(out_file *f, char *err, size_t errsz);

/* print the schema (markdown) on stdout: name, dimensions, units, doc */
void out_schema_print(void);

/* ------------------------------------------- HDF5 helpers for merge.c */

/* err = the message (printf-style) and the innermost HDF5 error, which is
   then cleared */
void out_fail(char *err, size_t errsz, const char *fmt, ...);

/* Set (replace) the root attributes created_utc (now) and command_line of
   an open file.  Returns 0 or -1. */
int out_stamp(hid_t file, const char *command_line);

/* now = the time now, ISO 8601 in UTC ("2026-01-31T12:00:00Z") */
void out_utc_now(char now[32]);

/* ------------------------------- HDF5 helpers for sim_output.c */

/* a scalar string attribute (str: the file's UTF-8 string type); 0 or -1 */
int out_h5_attr(hid_t obj, hid_t str, const char *name, const char *value);

/* a dataset with units and description attributes, as the runner's own:
   chunk NULL for contiguous, else Fletcher-32 (and deflate at gzip) on
   every chunk, fill value fill (NULL: HDF5's), no chunk cache; or -1 */
hid_t out_h5_dataset(hid_t file, hid_t str, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const hsize_t *chunk,
                     int gzip, const void *fill, const char *units,
                     const char *doc);

/* a 1-D dimension scale of n values (data NULL: written later); or -1 */
hid_t out_h5_scale(hid_t file, hid_t str, const char *name, hid_t type,
                   size_t n, const void *data, const char *units,
                   const char *doc);

/* n elements into rows [c0, c0 + n) of a 1-D dataset; 0 or -1 */
int out_h5_rows(hid_t ds, hid_t type, size_t c0, size_t n, const void *data);

/* the case and time scales and the swept values are written in runs of
   this many values: memory does not grow with the sweep */
#define OUT_AXIS_RUN 65536

/* Write all of a small dataset: 0, or -1. */
int out_h5_write_all(hid_t ds, hid_t type, const void *data);

/* the values of sweep axis a of s, case by case, into a [case] dataset of
   the key's type; 0 or -1 */
int out_h5_axis(hid_t ds, hid_t str, const scene *s, size_t a);

/* "key1 key2 [case_time]": the coordinates attribute, the swept keys'
   variables and, when with_case_time (a per-sample variable of a file
   whose time grid differs between cases), case_time (malloc'd; NULL when
   out of memory) */
char *out_h5_coordinates(const scene *s, int with_case_time);

#endif /* RPS3_RUNNER_OUTPUT_H */
