/*
 * verify.h - that part files can be trusted before they are merged, and
 * the HDF5 helpers of shards/.
 */
#ifndef RPS3_RUNNER_VERIFY_H
#define RPS3_RUNNER_VERIFY_H

#include <stddef.h>
#include <stdio.h>

#include <hdf5.h>

/*
 * Read every dataset of the file at path, a block of rows at a time (one
 * chunk row for chunked datasets; memory stays at a few chunks), so that
 * HDF5 checks each chunk's checksum and decompresses it: the runner writes
 * a Fletcher-32 checksum with each chunk, so damaged bytes are found
 * whether compressed or not.  Returns 0, or -1 with err naming the dataset
 * and the first case of the damaged block.
 */
int verify_file(const char *path, char *err, size_t errsz);

/*
 * The root attributes rps3_version, gsl_version, hdf5_version,
 * yaml_version and fields (the per-sample fields written, --fields) of the
 * n files path[i] agree.  Returns 0, or -1 with err naming both files, the
 * attribute and both values.
 */
int verify_same_versions(const char *const *path, size_t n, char *err,
                         size_t errsz);

/* the root string attribute `name` of the file at path (malloc'd), or
   NULL when it has none or cannot be read */
char *verify_root_attr(const char *path, const char *name);

/*
 * The record of input files (inputs.h) of the file at path against `rec`
 * (NULL: not recorded), whose origin `rec_is` names ("p0.h5 read", "the
 * file now has").  Returns 0 when every file has the same digest in both;
 * else -1 with err naming the file's key and path and both digests.
 */
int verify_inputs_as(const char *path, const char *rec, const char *rec_is,
                     char *err, size_t errsz);

/*
 * The records of input files of the n parts path[i] agree: every part was
 * computed from the same content of every file its scene reads.  When not,
 * say on `out` (prefixed `who`) which file differs and which parts read
 * which content, set bad[i] for the parts that read another content than
 * the file has now (every part when the file matches none), and return
 * -1 (the file cannot be read now: no part is marked).  Returns 0 when
 * they agree.
 */
int verify_parts_inputs(const char *const *path, size_t n, int *bad,
                        const char *who, FILE *out);

/* Close the n HDF5 ids given, of any kind, those that are open (>= 0). */
void shard_h5_close(int n, ...);

/*
 * The block [off, off + count) of dataset ds read in memory type `type`
 * into *buf, grown to *cap bytes as needed.  Returns its memory space (the
 * caller reclaims variable-length strings with it, then closes it), or -1.
 */
hid_t verify_read_block(hid_t ds, hid_t type, int rank, const hsize_t *off,
                        const hsize_t *count, void **buf, size_t *cap);

#endif /* RPS3_RUNNER_VERIFY_H */
