/*
 * parts.h - the part files given to `rps3-run merge`: in shard order, and
 * what to do about the missing or incomplete ones.
 *
 * A part records the command that made it (root attribute command_line),
 * so the command that makes a missing shard again is that command with
 * another --shard and -o: the output name of part K has K in it where the
 * given part has its own number (parts/grid.3.h5 -> parts/grid.5.h5), else
 * PART_K.h5 stands in for it.  Run it from the directory the parts were
 * made in (the paths are the ones that command was given).
 */
#ifndef RPS3_RUNNER_PARTS_H
#define RPS3_RUNNER_PARTS_H

#include <stddef.h>
#include <stdio.h>

/*
 * The npart part files part[i] by shard: *byk gets a malloc'd array of *n
 * names, byk[k] the part of shard k or NULL when none is given.  Returns
 * 0, or -1 with err set (a file that cannot be read or is not a part, two
 * parts of the same shard, parts of different shard counts).
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

#endif /* RPS3_RUNNER_PARTS_H */
