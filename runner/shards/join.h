/*
 * join.h - join the part files of a sharded run by HDF5 virtual datasets.
 *
 * A part (rps3-run --shard K/N, merge.h) has the full layout and owns the
 * chunk rows r with r % N == K of every chunked (per-case) dataset.  The
 * joined file holds no sample: each chunked dataset of part 0 becomes a
 * virtual dataset of the same type and shape whose chunk rows map to the
 * same rows of the part that computed them (two mappings per part: its
 * whole rows as one strided hyperslab, and the last, shorter row when it
 * is the part's).  Everything else (the scene, the axes, the dimension
 * scales, every attribute) is copied from part 0.  Reading it reads the
 * parts, which must stay where they are (a part's name is stored relative
 * to the directory of the joined file when it lies below it, so the
 * directory may move as a whole).
 *
 * The file is written with the HDF5 1.10 file format (libver bounds
 * V110..V110), so that HDF5 1.10 readers open it whatever library wrote it.
 */
#ifndef RPS3_RUNNER_JOIN_H
#define RPS3_RUNNER_JOIN_H

#include <stddef.h>

/*
 * Create the file `dst` (truncated if it exists) joining the n parts
 * part[k] (part[k] is shard k of n) by virtual datasets, each checked with
 * merge_part_check against part 0's scene, with the same record of input
 * files (inputs.h) and the same shapes and chunks as part 0.  The names of the
 * parts are stored relative to the directory of dst when below it (dst is
 * renamed within it).  The root attributes are part 0's without `shard`, with
 * `command_line` and `created_utc` of this join; *nfailed is the number of
 * cases whose status is not 0.  Returns 0, or -1 with err set (dst is then
 * incomplete: the caller removes it).
 */
int join_vds(const char *dst, const char *const *part, size_t n,
             const char *command_line, size_t *nfailed, char *err,
             size_t errsz);

#endif /* RPS3_RUNNER_JOIN_H */
