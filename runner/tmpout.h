/*
 * tmpout.h - the temporary file of a run or a merge: written as
 * OUT.h5.tmp.PID (OUT.h5.tmp.PID.partR for MPI rank R > 0, named after rank
 * 0's PID) in the directory of OUT.h5, made durable and renamed to OUT.h5
 * when complete, and removed on failure or when a signal ends the process
 * (signals.h says which, and what the process does then).
 *
 * One temporary file per process: process-wide state of the runner only
 * (the library has none).
 */
#ifndef RPS3_RUNNER_TMPOUT_H
#define RPS3_RUNNER_TMPOUT_H

/* Name the temporary file of out_path for `pid` and `rank`: 0, or -1 with
   a message on stderr (the name is too long). */
int tmpout_name(const char *out_path, long pid, int rank);

/* The temporary file's name. */
const char *tmpout_path(void);

/* From now on the temporary file exists: a signal removes it. */
void tmpout_arm(void);

/* fsync the temporary file, rename it to out_path (the rename and
   forgetting the temporary name happen together), fsync the directory.
   0, or -1 with a message on stderr. */
int tmpout_commit(const char *out_path);

/* Remove the temporary file, if armed. */
void tmpout_discard(void);

#endif /* RPS3_RUNNER_TMPOUT_H */
