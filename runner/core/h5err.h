/*
 * h5err.h - the cause of an HDF5 failure in one line.
 *
 * HDF5's error stack goes from the API call (the outermost, "unable to
 * create file") down to the function that met the system's error ("unable
 * to lock file, errno = 11"); only the two together say what happened.
 */
#ifndef RPS3_RUNNER_H5ERR_H
#define RPS3_RUNNER_H5ERR_H

#include <stddef.h>

/*
 * Replace HDF5's printing of errors by their capture: when an HDF5 call
 * fails, its error stack is walked at once (a later call, such as the
 * H5Sclose of the cleanup, clears the stack) and kept for h5_cause.  Call
 * once, from the thread that calls HDF5.
 */
void h5_errors_capture(void);

/*
 * buf = "OUTER: CAUSE" for the last failed HDF5 call, where
 * OUTER is the outermost description and CAUSE the innermost, named in
 * words for what a user can act on (another process holds the file's lock,
 * no space left on the device, read-only file system, no such file or
 * directory, file too large for ulimit -f, ...), with a missing filter
 * between them when the stack names one; "" when no call failed since the
 * last h5_cause.  A failure still on the stack (printing off, as while a
 * table is read) comes before the capture.  Both are then cleared.
 */
void h5_cause(char *buf, size_t sz);

#endif /* RPS3_RUNNER_H5ERR_H */
