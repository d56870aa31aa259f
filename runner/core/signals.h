/*
 * signals.h - the temporary output file of a program and the signals that
 * may end it.
 *
 * A program writes OUT under a temporary name (tmp_set) and renames it when
 * complete (tmp_commit: fsync of the file, rename, fsync of the directory).
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
 * This is process-wide state of the programs only (the library has none).
 */
#ifndef RPS3_RUNNER_SIGNALS_H
#define RPS3_RUNNER_SIGNALS_H

#include <stddef.h>

/* Install the policy above (once per process, before any thread). */
void sig_init(void);

/* Block (SIG_BLOCK) or unblock (SIG_UNBLOCK) the handled signals on this
   thread. */
void sig_block(int how);

/* The temporary file the handlers remove: `path` is copied.  Returns 0, or
   -1 when it is too long. */
int tmp_set(const char *path);

/*
 * Make the temporary file durable and rename it to out: fsync the file,
 * rename, fsync the directory, so that a power loss cannot leave an OUT
 * that looks complete and is not.  Returns 0, or -1 with err set (the
 * temporary file is then still there: tmp_discard removes it).
 */
int tmp_commit(const char *out, char *err, size_t errsz);

/* Remove the temporary file, if any, and forget it. */
void tmp_discard(void);

#endif /* RPS3_RUNNER_SIGNALS_H */
