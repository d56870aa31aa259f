/*
 * tmpout.h - the temporary file of a run or a merge, and the signals that
 * may end it.  The file is written as OUT.h5.tmp.HOST.PID.jobJOB.rankR in
 * the directory of OUT.h5 (HOST the short host name, PID the writing
 * process, JOB the Slurm job, ARRAY_TASK for an array task, or "none", R
 * the MPI rank or 0), made durable and renamed to OUT.h5 (or to the part's
 * name) when complete, and removed on failure or when a signal ends the
 * process.  SIGKILL cannot be caught: what it leaves, tmpout_clean()
 * removes (`rps3-run --clean OUT.h5`, and every run of OUT.h5 for the dead
 * processes of its own host).
 *
 * sig_init() decides once, at start, what each signal does:
 *   - a signal ignored at start stays ignored (nohup's SIGHUP, a shell's
 *     SIGINT for background jobs): the run goes on;
 *   - SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGALRM, SIGUSR1, SIGUSR2,
 *     SIGVTALRM, SIGPROF, SIGXCPU: the temporary file is removed and the
 *     process dies of that signal (shell status 128 + N);
 *   - SIGPIPE (stdout or stderr into a pipe whose reader is gone): while
 *     a temporary file exists, it is removed and the process exits 3;
 *     once the output is complete, the signal is ignored (the exit code
 *     is the run's); before, the process dies of SIGPIPE as filters do;
 *   - SIGXFSZ (ulimit -f): ignored, so that the write fails with EFBIG and
 *     the run ends as any failed write does (exit 3, temporary removed).
 *
 * One temporary file per process: process-wide state of the runner only
 * (the library has none).
 */
#ifndef RPS3_RUNNER_TMPOUT_H
#define RPS3_RUNNER_TMPOUT_H

/* Install the policy above (once per process, before any thread). */
void sig_init(void);

/* Name the temporary file of out_path for this process and MPI `rank`: 0,
   or -1 with a message on stderr (the name is too long). */
int tmpout_name(const char *out_path, int rank);

/*
 * Remove the temporary files of out_path whose process is gone: written
 * on this host by a process that no longer exists.  With `force`, those of
 * other hosts and of unknown owners too (when no run of out_path is
 * going).  Each removal is said on stderr; with `quiet`, nothing else.
 * Returns the number of temporary files kept, or -1 when the directory
 * cannot be read.
 */
int tmpout_clean(const char *out_path, int force, int quiet);

/* The program named in the messages ("rps3-run" unless set); name is
   kept, not copied. */
void tmpout_prog(const char *name);

/* The temporary file's name. */
const char *tmpout_path(void);

/* From now on the temporary file exists: a signal removes it. */
void tmpout_arm(void);

/*
 * Make the temporary file durable and rename it to out_path: fsync the
 * file, rename (and forget the temporary name with it), fsync the
 * directory, so that a power loss cannot leave an OUT that looks complete
 * and is not.  0, or -1 with a message on stderr (the temporary file is
 * then still there: tmpout_discard removes it).
 */
int tmpout_commit(const char *out_path);

/* Remove the temporary file, if armed, and forget it. */
void tmpout_discard(void);

#endif /* RPS3_RUNNER_TMPOUT_H */
