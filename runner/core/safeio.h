/*
 * safeio.h - what every program of the runner does about its process and
 * its output file before, while and after it writes: standard streams,
 * HDF5's exit, the output path, free space, stale temporaries, fsync, and
 * strict parsing of numbers on the command line.
 */
#ifndef RPS3_RUNNER_SAFEIO_H
#define RPS3_RUNNER_SAFEIO_H

#include <stddef.h>
#include <sys/types.h>

/*
 * Call first in main(): reopen each of fds 0-2 that is closed on /dev/null
 * (else the first file opened would get fd 2, and progress lines would be
 * written into it), and keep HDF5 from registering its atexit cleanup
 * (proc_exit decides).
 */
void proc_init(void);

/*
 * Return `code` from main() through this.  HDF5's library cleanup runs only
 * when no write failed (code != 3): after a failed H5Fclose (a full disk,
 * EFBIG) HDF5 1.10 keeps the half-closed file's id, and its cleanup then
 * dereferences the freed file (SIGSEGV at exit).  Nothing is lost by
 * skipping it: the temporary file is removed already.
 */
int proc_exit(int code);

/*
 * Check that `out` may be written as `out` by rename: refuses "" and names
 * ending in '/', an existing directory, symbolic link, character or block
 * device, FIFO or socket, any of the `ninput` input files in[] (the same
 * file under any name), and a directory that does not exist or is not
 * writable.  Returns 0, or -1 with err set (the caller exits 2).
 */
int out_path_check(const char *out, const char *const *in, size_t ninput,
                   char *err, size_t errsz);

/*
 * Print to stderr, prefixed by prog, every OUT.tmp.PID (and
 * OUT.tmp.PID.partR) next to `out` whose process PID does not exist: the
 * temporaries of killed runs (SIGKILL, power loss).  Returns their number.
 */
size_t stale_report(const char *prog, const char *out);

/* What a file of mode m is, in words ("a directory", "a FIFO", ...), for
   a refusal of what is not a regular file. */
const char *file_kind(mode_t m);

/*
 * Read the regular file at path, of at most max bytes, into *text (malloc'd,
 * NUL-terminated) and *len.  What is not a regular file (a FIFO, /dev/zero,
 * a directory) and a larger file are refused before they are read; a FIFO
 * is not waited for.  Returns 0, or -1 with why set to what follows the
 * file's name: "cannot open: CAUSE", "is a FIFO: KIND_RULE", "is N bytes:
 * SIZE_RULE", "changed while it was read", "out of memory" or "cannot
 * read: CAUSE".
 */
int file_read_all(const char *path, size_t max, const char *kind_rule,
                  const char *size_rule, char **text, size_t *len, char *why,
                  size_t whysz);

/* Bytes available to this user on the file system of out's directory;
   -1 when unknown. */
double disk_free(const char *out);

/* The directory part of path ("." when none) into dir: 0, or -1 when it
   does not fit. */
int path_dir(const char *path, char *dir, size_t sz);

/*
 * Strict numbers for options: the whole of `a` is a decimal integer in
 * [lo, hi] (no sign for unsigned, no spaces, no suffix, no overflow).
 * Returns 0 or -1.
 */
int parse_ulong(const char *a, unsigned long lo, unsigned long hi,
                unsigned long *v);

#endif /* RPS3_RUNNER_SAFEIO_H */
