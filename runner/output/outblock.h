/*
 * outblock.h - the schema of a sweep's file and its tiles in memory:
 * RPS3_OUTPUT_FIELDS, the one table of what a file holds per case and per
 * sample, drives the tile buffers (outblock.c), dataset creation, the
 * writes and the units/description attributes (output.c); the chunks of a
 * tile packed off the writing thread (outpack.c); the selection of fields
 * (--fields).  No HDF5 calls.
 */
#ifndef RPS3_RUNNER_OUTBLOCK_H
#define RPS3_RUNNER_OUTBLOCK_H

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
#define RPS3_OUTPUT_FIELDS(X)                                                 \
  X(force, OUT_CTL, OUT_F64, "N", "actuating force along the link",           \
    "total actuating force F_i along link i, eq. (34); positive extends "     \
    "the link")                                                               \
  X(force_by_effect, OUT_CTEL, OUT_F64, "N",                                  \
    "actuating force by physical effect",                                     \
    "share of each selected effect in the actuating force; the shares "       \
    "sum to force")                                                           \
  X(length, OUT_CTL, OUT_F64, "m", "link length",                             \
    "link length l_i = R L_i, eqs. (5)-(7)")                                  \
  X(length_rate, OUT_CTL, OUT_F64, "m/s", "link extension rate",              \
    "link extension rate dl_i/dt (NaN when no effect needs rates)")           \
  X(length_accel, OUT_CTL, OUT_F64, "m/s^2", "link extension acceleration",   \
    "link extension acceleration d2l_i/dt2 (NaN when no effect needs "        \
    "it)")                                                                    \
  X(theta, OUT_CTL, OUT_F64, "rad", "link angle to the base plane",           \
    "angle theta_i between link i and the base plane, eq. (39) or "           \
    "(8)-(10)")                                                               \
  X(alpha, OUT_CT, OUT_F64, "rad", "platform precession angle",               \
    "precession angle alpha of the platform (Z-Y-Z Euler angles, eq. "        \
    "(2))")                                                                   \
  X(beta, OUT_CT, OUT_F64, "rad", "platform nutation angle",                  \
    "nutation angle beta of the platform")                                    \
  X(z_c, OUT_CT, OUT_F64, "m", "platform centre height",                      \
    "height z_c of the platform centre")                                      \
  X(x_c, OUT_CT, OUT_F64, "m", "platform centre x",                           \
    "platform centre x_c, eq. (3) times R")                                   \
  X(y_c, OUT_CT, OUT_F64, "m", "platform centre y",                           \
    "platform centre y_c, eq. (4) times R")                                   \
  X(lambda, OUT_CTK, OUT_F64, "N/m", "constraint Lagrange multiplier",        \
    "Lagrange multipliers lambda_k of the constraints (8)-(10) written "      \
    "in metres (f_k = norm(b_i - b_j)^2 - 3 r^2), eq. (34); NaN under "       \
    "newton_euler, which does not compute them")                              \
  X(energy_residual, OUT_CT, OUT_F64, "W", "energy-rate residual",            \
    "actuator power + friction power - dT/dt - dP/dt; zero up to "            \
    "rounding when the forces are right (NaN when solver.outputs leaves "     \
    "out certify)")                                                           \
  X(energy_scale, OUT_CT, OUT_F64, "W", "energy-rate scale",                  \
    "sum of the magnitudes of the terms of energy_residual, its scale")       \
  X(condition, OUT_CT, OUT_F64, "1",                                          \
    "condition number of the constraint Jacobian",                            \
    "1-norm condition number of the constraint Jacobian df/dtheta")           \
  X(transmission, OUT_CT, OUT_F64, "1", "force transmission",                 \
    "force transmission: largest actuator force per unit platform load "      \
    "(force, moment / R); warn above 100, refused above 1e8")                 \
  X(solve_niter, OUT_CT, OUT_I32, "1", "theta solve iterations",              \
    "iterations of the multiroot theta solve (0 for closed_form; -1 "         \
    "missing)")                                                               \
  X(solve_resid, OUT_CT, OUT_F64, "1", "theta solve residual",                \
    "max_k abs(f_k) after the theta solve, lengths in units of R")            \
  X(warn, OUT_CT, OUT_I32, "1", "warning bits",                               \
    "warning bits: 1 ill-conditioned lambda system, 2 alpha undefined, "      \
    "4 assembly mode changed, 8 transmission above trans_warn (-1 "           \
    "missing)")                                                               \
  X(status, OUT_C, OUT_I32, "1", "status of the case",                        \
    "0 = ok, else the rps3_status code of the first failing sample; "         \
    "-1000 = not computed (a case of another shard, or of a killed "          \
    "part)")                                                                  \
  X(failed_at, OUT_C, OUT_I32, "1", "time index of the first failing sample", \
    "time index of the first failing sample, -1 if none")                     \
  X(message, OUT_C, OUT_STR, "1", "failure message",                          \
    "why the case failed, empty if it did not")                               \
  X(scene_resolved, OUT_C, OUT_STR, "1", "resolved scene of the case",        \
    "the case's full scene as YAML (no sweep): rerun it alone with "          \
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
int out_fields_parse(const char *list, out_mask *mask, char *err, size_t errsz);

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
  size_t cases;             /* case slots */
  size_t points;            /* samples per slot */
  int neffect;              /* effects in force_by_effect */
  int effect[RPS3_NEFFECT]; /* their effect indices, in file order */
#define OUT_BLOCK_MEMBER(name, shape, type, ...) void *name;
  RPS3_OUTPUT_FIELDS(OUT_BLOCK_MEMBER)
#undef OUT_BLOCK_MEMBER
  double *t;        /* time of each sample [cases][points] */
  scene_text *yaml; /* per slot: scene_resolved's storage */
  char (*msg)[320]; /* per slot: message's storage */
  out_mask fields;  /* the fields the file gets (--fields) */
  /* scratch of the batch path (compute.c): OUT_BATCH points, structure of
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
  size_t ncase, nt; /* extents along case and time */
  size_t tc, q;     /* chunk extents along case and time */
  int neffect;
  int gzip;        /* deflate level, 0 for none */
  out_mask fields; /* the fields written */
  int case_time;   /* 1: case_time is written */
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
int out_pack(const out_layout *L, out_block *b, size_t c0, size_t nc, size_t k0,
             size_t nk);

/* columns of a shape per (case, sample) */
size_t out_columns(out_shape shape, int neffect);

/* Allocate a block; returns 0, or -1 (out of memory, nothing leaks). */
int out_block_alloc(out_block *b, size_t cases, size_t points, int effects);

/* Free a block's buffers; a zeroed block is accepted. */
void out_block_free(out_block *b);

/* Fill slot s from sample k on with the missing values (NaN, -1). */
void out_block_blank(out_block *b, size_t slot, size_t k);

/* the buffer of field i of b */
void *out_block_field(const out_block *b, int i);

/* print the schema (markdown) on stdout: name, dimensions, units, doc */
void out_schema_print(void);

#endif /* RPS3_RUNNER_OUTBLOCK_H */
