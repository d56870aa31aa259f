/*
 * output.h - the HDF5 file of an inverse sweep, a simulation or a design
 * study, the one writer of the schema (outblock.h), in tiles (a run of
 * whole cases, or a window of one long case): one hyperslab write per
 * field, memory bounded by the tile whatever the sweep.
 */
#ifndef RPS3_RUNNER_OUTPUT_H
#define RPS3_RUNNER_OUTPUT_H

#include "out_h5.h"
#include "outblock.h"

/* what the file says about the run */
typedef struct {
  const char *command_line;
  int gzip;           /* deflate level 1-9, 0 for none */
  const char *shard;  /* "K/N" of a part file (merge.h), NULL if whole */
  out_mask fields;    /* the fields written (--fields) */
  const char *inputs; /* the files the scene read and their SHA-256
                         (inputs.h): root attribute input_files */
} out_meta;

/* an open file (output.c's own) */
typedef struct out_file {
  int files;       /* the rows of the schema it holds (out_spec) */
  const char *row; /* what a case is: "case", "design" */
  hid_t file;
  hid_t ds[OUT_NFIELD]; /* -1 for a field the file does not have */
  hid_t case_time;      /* [case, time] when the grid differs, else -1 */
  hid_t str;            /* variable-length UTF-8 string type */
  hid_t dxpl;           /* the tiles' transfer properties */
  out_layout layout;    /* for out_pack */
} out_file;

/* what a file holds and how it is chunked (out_open) */
typedef struct {
  int files;            /* OUT_INV, OUT_SIM or the OUT_DESIGN bits of the
                           design's fields: the rows of the schema */
  const char *title;    /* root attribute title */
  const char *content;  /* root attribute content, NULL for none */
  const char *time_doc; /* description of the common time axis */
  size_t nt;            /* samples along time: the most of any case */
  int grid_common;      /* 1: every case has the time grid of time() */
  double (*time)(const void *ctx, size_t k); /* time of sample k [s] */
  const void *time_ctx;
  size_t tile_cases;   /* case extent of a per-sample chunk */
  size_t case_chunk;   /* case extent of a per-case chunk */
  size_t chunk_points; /* time extent of a chunk */
  int case_cache;      /* 1: the per-case fields are written a case at a
                          time: they get a chunk cache */
  int neffect;         /* the effects of force_by_effect ... */
  const int *effect;   /* ... their indices, in file order */
} out_spec;

/* Create the file at `path` (truncating it) for the cases of s and the
   fields of sp->files (of an inverse sweep's, those of meta->fields): the
   root attributes, the scene text, the scales, the swept keys, each
   field's dataset with its attributes, and case_time when the grid
   differs between cases.  Returns NULL with a message in err. */
out_file *out_open(const char *path, const scene *s, const out_spec *sp,
                   const out_meta *meta, char *err, size_t errsz);

/* out_open for an inverse sweep (files OUT_INV) or a simulation (OUT_SIM):
   its time axis from `axis` (the sweep's first scene_case, the simulation's
   nt times) when the grid is common to all cases, else NULL (case_time
   holds the times).  An inverse sweep's chunks are [b->cases,
   chunk_points, ...]; a simulation's [1, chunk_points, (3)] (b NULL). */
out_file *out_create(const char *path, const scene *s, int files, size_t nt,
                     const void *axis, size_t chunk_points, const out_block *b,
                     const out_meta *meta, char *err, size_t errsz);

/* a filled block to write: slots [0, nc) hold cases c0 .., samples
   [k0, k0 + nk) (none when nk is 0); with the per-case fields (status,
   message, ...) when with_case; and what it adds to the run's counts */
typedef struct {
  size_t c0, nc, k0, nk;
  int with_case;
  size_t blank_below; /* > 0: first the (blank) block over the windows
                         [0, blank_below) of case c0: a late failure */
  size_t points;      /* samples computed */
} out_tile;

/* Write tile t of b; when b->packed, the per-sample fields as the chunks
   out_pack made of it.  Returns 0 or -1 with err set. */
int out_write(out_file *f, const out_block *b, const out_tile *t, char *err,
              size_t errsz);

/* Flush and close the file; returns 0 or -1 with err set.  f is freed
   either way; NULL is accepted. */
int out_close(out_file *f, char *err, size_t errsz);

#endif /* RPS3_RUNNER_OUTPUT_H */
