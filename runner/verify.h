/*
 * verify.h - that part files can be trusted before they are merged: every
 * stored chunk decodes (the runner writes a Fletcher-32 checksum with each
 * chunk, so damaged bytes are found whether compressed or not), and every
 * part was written by the same versions of rps3, GSL, HDF5 and libyaml,
 * with the same fields (--fields).
 */
#ifndef RPS3_RUNNER_VERIFY_H
#define RPS3_RUNNER_VERIFY_H

#include <stddef.h>

/*
 * Read every dataset of the file at path, a block of rows at a time (one
 * chunk row for chunked datasets; memory stays at a few chunks), so that
 * HDF5 checks each chunk's checksum and decompresses it.  Returns 0, or -1
 * with err naming the dataset and the first case of the damaged block.
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

#endif /* RPS3_RUNNER_VERIFY_H */
