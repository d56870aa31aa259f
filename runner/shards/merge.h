/*
 * merge.h - join the part files of a sharded run into one file:
 * `rps3-run merge` (merge_main, parts.c).
 *
 * `rps3-run --shard K/N` computes the jobs j with j % N == K (sweep.h) into
 * a file of the full layout, written by out_create like any run: the cases
 * of the other shards are there but unwritten (unallocated chunks, read as
 * the fill values NaN, -1 and "").  A job is one chunk row of every per-case
 * dataset, so a part owns whole chunks, and merging (--copy) is copying
 * chunks: the chunk rows r with r % N == K of every chunked dataset, as
 * stored (no decompression), strings by value.  The result equals, dataset
 * for dataset, the file of a run without shards.
 *
 * Joining (join.c, the default) writes no sample: each chunked dataset of
 * part 0 becomes a virtual dataset of the same type and shape whose chunk
 * rows map to the same rows of the part that computed them (two mappings
 * per part: its whole rows as one strided hyperslab, and the last, shorter
 * row when it is the part's).  Everything else (the scene, the axes, the
 * dimension scales, every attribute) is copied from part 0.  Reading it
 * reads the parts, which must stay where they are (a part's name is stored
 * relative to the directory of the joined file when it lies below it, so
 * the directory may move as a whole).  The file is written with the HDF5
 * 1.10 file format (libver bounds V110..V110), so that HDF5 1.10 readers
 * open it whatever library wrote it.
 */
#ifndef RPS3_RUNNER_MERGE_H
#define RPS3_RUNNER_MERGE_H

#include <stddef.h>
#include <stdio.h>

#include <hdf5.h>

/* the root attribute that marks a part file: "K/N" */
#define MERGE_SHARD_ATTR "shard"

/* Read the shard K/N of the part file at `path` into *k, *n.  Returns 0, or
   -1 with err set (no such file, not an rps3-run file, not a part). */
int merge_shard_of(const char *path, size_t *k, size_t *n, char *err,
                   size_t errsz);

/* Check the part file at `path`: shard k of n, the scene text text0 byte
   for byte when not NULL, and every case of the part has its status (none
   left at the fill value: all its jobs were written).  Returns 0, or -1
   with err set saying what is wrong. */
int merge_part_check(const char *path, size_t k, size_t n, const char *text0,
                     char *err, size_t errsz);

/*
 * The n parts part[k] (shard k of n) into the file `dst`, each checked
 * with merge_part_check against part 0's scene, with the same record of
 * input files (inputs.h) and the same shapes and chunks as part 0.  The
 * root attributes are part 0's without `shard`, with `command_line` and
 * `created_utc` of this merge; *nfailed is the number of cases whose
 * status is not 0.  Returns 0, or -1 with err set (dst is then incomplete:
 * the caller removes it).  merge_parts copies the cases of parts 1 .. n-1
 * into dst, part 0 itself or a copy of it (merge_each_part); join_vds
 * creates dst (truncated if it exists) of virtual datasets over the parts,
 * whose names are stored relative to the directory of dst when below it
 * (dst is renamed within it).
 */
int merge_parts(const char *dst, const char *const *part, size_t n,
                const char *command_line, size_t *nfailed, char *err,
                size_t errsz);
int join_vds(const char *dst, const char *const *part, size_t n,
             const char *command_line, size_t *nfailed, char *err,
             size_t errsz);

/*
 * rps3-run merge OUT.h5 PART.h5 ... [--copy] [--quiet] (argv[1] is
 * "merge"): the parts of shards 0..N-1, in any order.  By default OUT.h5
 * is a file of virtual datasets over the parts (join_vds); with --copy it
 * is a copy of part 0 into which the other parts' chunks are copied
 * (merge_parts).  Either is written under a temporary name and renamed
 * when complete.  A missing or incomplete part is named, with the command
 * that makes it again (parts_report).  Returns the exit code.
 */
int merge_main(int argc, char **argv);

/* the chunked datasets of a file by name: the per-case variables */
#define MERGE_MAX_CHUNKED 64
typedef struct {
  char name[MERGE_MAX_CHUNKED][256];
  int n;
} merge_chunked;

/* dataset `name` (list index j) of the open part file `part` (at path),
   shard k of n, with its shape and chunks */
typedef struct {
  hid_t part;
  const char *path, *name;
  size_t k, n;
  int j, rank;
  hsize_t dims[H5S_MAX_RANK], chunk[H5S_MAX_RANK];
} merge_rows;

/* what a merge (copy the chunk rows) or a join (map them) does with a
   part's dataset: 0, or -1 with err set */
typedef int (*merge_rows_fn)(void *ctx, const merge_rows *r, char *err,
                             size_t errsz);

/*
 * The one loop over the parts of a merge and of a join.  The open file
 * `ref` (at ref_path) is part 0 or a copy of it; its chunked datasets go
 * into *list.  Every part[k], k0 <= k < n, is checked first: shard k of n
 * of ref's scene, complete (merge_part_check), with ref's record of input
 * files (inputs.h; rec_is names it in messages).  Then for each part and
 * each chunked dataset, of the same shape and chunks in both: fn(ctx, ...).
 * Returns 0, or -1 with err set.
 */
int merge_each_part(hid_t ref, const char *ref_path, const char *rec_is,
                    const char *const *part, size_t k0, size_t n,
                    merge_chunked *list, merge_rows_fn fn, void *ctx, char *err,
                    size_t errsz);

/* Of the cases of the chunk rows r % n == k of an open rps3-run file (k 0,
   n 1: all), those whose status is not 0 (*nfailed) and of those the ones
   never written (*nunset: OUT_STATUS_NOT_COMPUTED, the fill value), the
   first of them in *first_unset when not NULL.  Returns 0 or -1. */
int merge_count_failed(hid_t file, size_t k, size_t n, size_t *nfailed,
                       size_t *nunset, size_t *first_unset);

/* Copy the file `from` byte for byte to `to` (created or truncated).
   Returns 0 or -1 with err set. */
int merge_copy_file(const char *from, const char *to, char *err, size_t errsz);

/*
 * The part files given to `rps3-run merge` (parts.c): in shard order, and
 * what to do about the missing or incomplete ones.
 *
 * A part records the command that made it (root attribute command_line),
 * so the command that makes a missing shard again is that command with
 * another --shard and -o: the output name of part K has K in it where the
 * given part has its own number (parts/grid.3.h5 -> parts/grid.5.h5), else
 * PART_K.h5 stands in for it.  Run it from the directory the parts were
 * made in (the paths are the ones that command was given).
 *
 * parts_by_shard: the npart part files part[i] by shard: *byk gets a malloc'd
 * array of *n names, byk[k] the part of shard k or NULL when none is given.
 * Returns 0, or -1 with err set (a file that cannot be read or is not a part,
 * two parts of the same shard, parts of different shard counts).
 */
int parts_by_shard(const char *const *part, size_t npart, const char ***byk,
                   size_t *n, char *err, size_t errsz);

/*
 * Tell `out` which of the n shards are missing (byk[k] NULL) or, when
 * bad[k] is set, incomplete: their indices as one comma-separated list (as
 * `sbatch --array=` takes it) and the command that makes each again.
 * Returns the number of such shards.
 */
size_t parts_report(FILE *out, const char *const *byk, const int *bad,
                    size_t n);

/*
 * rps3-run --resume: 1 when the file at `path` is already shard k of n of
 * the scene whose text is text0, complete (merge_part_check), with the
 * per-sample fields `fields` (the root attribute, out_fields_text),
 * computed from the same content of every file the scene reads (`inputs`,
 * the record of inputs.h), with *nfailed the failed cases of this shard;
 * 0 when it must be computed (absent, or not that: said on stderr).
 */
int parts_resume(const char *path, size_t k, size_t n, const char *text0,
                 const char *fields, const char *inputs, size_t *nfailed);

#endif /* RPS3_RUNNER_MERGE_H */
