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
 *   - fds[0..2] become its 0, 1, 2 and every other descriptor is
 *     close-on-exec, whether the runner opened it so or inherited it
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
    int fds[3];                /* become the child's 0, 1 and 2 */
    pid_t parent;              /* getpid() of the caller */
    /* written by the child when a step fails (then it exited with 127) */
    int failed_errno;
    const char *failed_step;   /* "setpgid", "dup2", the cwd, the program, ... */
};

/* Start the child; *pid is its pid (a leader of its own process group).
 * 0, also when a set-up step or execve failed (r->failed_errno != 0: the
 * child exited with status 127 and is to be reaped as usual); ERR_RUNTIME
 * with e set when no child could be made.  errno is not preserved. */
int spawn_start(struct spawn_request *r, struct spawn_stack *s, pid_t *pid, struct err *e);

#endif
