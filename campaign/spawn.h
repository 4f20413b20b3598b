/*
 * spawn: start a program without copying the caller's page tables.
 *
 * fork() copies the runner's page tables and then takes copy-on-write
 * faults on every page either side writes while the child lives; on 400
 * no-op jobs that was two thirds of the runner's CPU time (docs/bench.md,
 * "Campaign dispatch").  spawn_start does what glibc's posix_spawn does --
 * clone(CLONE_VM | CLONE_VFORK) with a stack of its own, the caller
 * suspended until the child has called execve or _exit -- but with the one
 * set-up step posix_spawn cannot do, PR_SET_PDEATHSIG.
 *
 * The child shares the caller's memory, so it may only make system calls
 * on its own stack and write the one field meant for it (the failure):
 * no stdio, no malloc, no locks, no handler of the caller's may run in it.
 * Hence, in this order:
 *   - the caller blocks every signal around the clone, so nothing is
 *     delivered to the child before it has set every caught signal to
 *     SIG_DFL (what execve does anyway; a handler of the runner's running
 *     on the shared memory would corrupt it);
 *   - the child also sets SIGCHLD, SIGINT, SIGTERM, SIGHUP and SIGPIPE to
 *     SIG_DFL (the runner takes the first four with sigtimedwait, and a
 *     solver must not start with SIGPIPE ignored), leaves the signals the
 *     runner ignores ignored (as fork + exec did), and starts with an empty
 *     signal mask;
 *   - it leads a process group of its own (a timeout or a cancel reaches
 *     every process of the job, the terminal's Ctrl-C only the runner),
 *     dies with the caller (PR_SET_PDEATHSIG; it exits at once when the
 *     caller is already gone);
 *   - fds[0..2] become its 0, 1, 2 -- or, where paths[k] is set, the
 *     child opens that file as k (0 for reading; 1 and 2 created or
 *     truncated), so that creating a job's stdout and stderr is not the
 *     caller's work -- and every other descriptor is close-on-exec,
 *     whether the runner opened it so or inherited it
 *     (close_range(CLOSE_RANGE_CLOEXEC)): a job never holds the runner's
 *     database, pipes or a make jobserver open;
 *   - it changes to cwd and calls execve(prog, argv, envp): a program path
 *     and an argument vector, never a shell.
 * A failing step stores its errno and name in the request and exits 127;
 * the caller reads them once spawn_start returns (the child has ended its
 * use of the memory by then) and says why in the job's stderr file.
 */
#ifndef CASCADE_CAMPAIGN_SPAWN_H
#define CASCADE_CAMPAIGN_SPAWN_H

#include <stddef.h>
#include <sys/types.h>

#include "util/err.h"

/* The child's stack: mapped once, reused by every spawn (the caller is
 * suspended while a child uses it, so one is enough). */
struct spawn_stack {
    void *base;
    size_t len;
};

int spawn_stack_init(struct spawn_stack *s, struct err *e);
void spawn_stack_fini(struct spawn_stack *s);

struct spawn_request {
    const char *prog;          /* the path execve gets (no PATH search here) */
    char *const *argv;
    char *const *envp;
    const char *cwd;
    int fds[3];                /* become the child's 0, 1 and 2 (fds[k] >= k) */
    const char *paths[3];      /* or, where not NULL, opened by the child as k */
    pid_t parent;              /* getpid() of the caller */
    /* written by the child when a step fails (then it exited with 127) */
    int failed_errno;
    const char *failed_step;   /* "setpgid", "dup2", the cwd, the program, ... */
};

/* Start the child and wait until it has exec'd (CLONE_VFORK); *pid is its
 * pid (a leader of its own process group).
 * 0, also when a set-up step or execve failed (r->failed_errno != 0: the
 * child exited with status 127 and is to be reaped as usual); ERR_RUNTIME
 * with e set when no child could be made.  errno is not preserved. */
int spawn_start(struct spawn_request *r, struct spawn_stack *s, pid_t *pid, struct err *e);

/*
 * The asynchronous start (local jobs, exec_local.c): clone(CLONE_VM) without
 * CLONE_VFORK, so the caller goes on at once instead of sleeping until the
 * child has been scheduled, set itself up and exec'd -- at load 5-7 that
 * wait was 3.75-5.05 ms of the runner's 5.4-7.9 ms per job (docs/bench.md).
 * The child then runs beside the caller on the same memory, so it must not
 * touch anything the caller may change: it makes raw system calls (inline
 * assembly: a libc wrapper would write the caller's errno, a sanitizer's
 * interceptor its state), on a stack of its own, and reads only its own
 * copy of the request (program, arguments, directory), which the caller
 * keeps until the kernel says the child has left the memory
 * (CLONE_CHILD_CLEARTID: the word is zeroed when the child execs or
 * exits).  Set-up and failure reporting are those of spawn_start; the
 * failure (errno and step) is read once the child has been reaped.
 * Where no raw system calls are written for the architecture (only x86-64
 * has them), spawn_async_start falls back to spawn_start.
 */
struct spawn_async {
    struct spawn_stack stack;   /* mapped on first use, reused */
    struct spawn_request req;   /* the child's copy; strings in block */
    char *block;                /* prog, cwd, paths, argv: owned */
    char **argv;                /* into block: owned */
    pid_t live;                 /* 1 until the child has exec'd or exited (the
                                   kernel zeroes it: CLONE_CHILD_CLEARTID) */
    int asynchronous;           /* started without waiting (else spawn_start) */
};

/* Start like spawn_start, without waiting for the exec.  a must not hold a
 * child still using it (spawn_async_busy).  envp must stay valid until the
 * child has been reaped.  On return a->req.failed_errno is 0 unless the
 * fallback already saw the failure; otherwise read it after reaping. */
int spawn_async_start(struct spawn_async *a, const struct spawn_request *r, pid_t *pid,
                      struct err *e);

/* Whether a's child may still read a's memory (it has not exec'd or exited). */
int spawn_async_busy(const struct spawn_async *a);

/* Free a (its child must have been reaped). */
void spawn_async_fini(struct spawn_async *a);

#endif
