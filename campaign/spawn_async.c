/* spawn_async: a job start the caller does not wait for -- clone(CLONE_VM)
 * without CLONE_VFORK, the child made of raw system calls (spawn.h). */
#define _GNU_SOURCE   /* clone */
#include "spawn.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "util/mem.h"

#ifndef SYS_close_range
#define SYS_close_range 436   /* the same number on every architecture */
#endif
#ifndef CLOSE_RANGE_CLOEXEC
#define CLOSE_RANGE_CLOEXEC (1U << 2)
#endif

/* The size of the kernel's signal set, which rt_sigaction and
 * rt_sigprocmask want (not glibc's 128-byte sigset_t). */
#define KSIGSET_BYTES 8

/* Raw system calls are written for x86-64 only (where this was written and
 * tested); elsewhere spawn_async_start falls back to the waiting spawn_start. */
#if defined(__x86_64__)
#define SPAWN_RAW 1
/* A system call without libc: no errno, no interceptor, -errno on failure. */
__attribute__((always_inline, no_sanitize_address)) static inline long
raw_call(long n, long a, long b, long c, long d)
{
    register long r10 __asm__("r10") = d;
    long ret;
    __asm__ volatile("syscall"
                     : "=a"(ret)
                     : "a"(n), "D"(a), "S"(b), "d"(c), "r"(r10)
                     : "rcx", "r11", "memory");
    return ret;
}
#else
#define SPAWN_RAW 0
#endif

#if SPAWN_RAW
/* The kernel's struct sigaction is 4 words on x86-64 (handler first); all
 * zero is SIG_DFL with no flags and an empty mask.  Read-only data, so the
 * child reads it without touching the caller's state. */
static const unsigned long kdefault[8];
static const unsigned long kempty_mask;

/* The child: on its own stack, beside the caller on the same memory.
 * Only raw system calls and reads of its own request; the set-up steps and
 * their order are spawn.c's (spawn.h). */
__attribute__((no_sanitize_address)) static int async_child(void *arg)
{
    struct spawn_request *r = arg;
    const char *step;
    long rc;
    /* every caught signal to SIG_DFL first (all are blocked: the caller's
     * mask at the clone), the runner's own and SIGPIPE always; ignored
     * ones stay ignored, as exec leaves them */
    for (long sig = 1; sig < NSIG; sig++) {
        if (sig == SIGKILL || sig == SIGSTOP)
            continue;
        int reset = sig == SIGCHLD || sig == SIGINT || sig == SIGTERM || sig == SIGHUP ||
                    sig == SIGPIPE;
        unsigned long old[8];
        if (!reset && raw_call(SYS_rt_sigaction, sig, 0, (long)old, KSIGSET_BYTES) == 0)
            reset = old[0] != (unsigned long)(uintptr_t)SIG_DFL &&
                    old[0] != (unsigned long)(uintptr_t)SIG_IGN;
        if (reset)
            raw_call(SYS_rt_sigaction, sig, (long)kdefault, 0, KSIGSET_BYTES);
    }
    step = "setpgid";
    if ((rc = raw_call(SYS_setpgid, 0, 0, 0, 0)) < 0)
        goto fail;
    step = "prctl(PR_SET_PDEATHSIG)";
    if ((rc = raw_call(SYS_prctl, PR_SET_PDEATHSIG, SIGKILL, 0, 0)) < 0)
        goto fail;
    if (raw_call(SYS_getppid, 0, 0, 0, 0) != r->parent) {   /* the caller was killed meanwhile */
        step = "the runner is gone";
        rc = -ESRCH;
        goto fail;
    }
    step = "sigprocmask";
    if ((rc = raw_call(SYS_rt_sigprocmask, SIG_SETMASK, (long)&kempty_mask, 0, KSIGSET_BYTES)) <
        0)
        goto fail;
    /* a file to open as k, or dup3 as spawn.c's dup2 (the caller opened
     * fds[] in order, so fds[k] >= k); a descriptor already in place only
     * loses close-on-exec */
    step = "dup2";
    for (int k = 0; k < 3; k++) {
        if (r->paths[k]) {
            /* 0..k-1 are in place, so the new descriptor is >= k */
            step = r->paths[k];
            long fd = raw_call(SYS_openat, AT_FDCWD, (long)r->paths[k],
                               k ? O_WRONLY | O_CREAT | O_TRUNC : O_RDONLY, 0666);
            if ((rc = fd) < 0)
                goto fail;
            if (fd != k && ((rc = raw_call(SYS_dup3, fd, k, 0, 0)) < 0 ||
                            (rc = raw_call(SYS_close, fd, 0, 0, 0)) < 0))
                goto fail;
            step = "dup2";
            continue;
        }
        rc = r->fds[k] == k ? raw_call(SYS_fcntl, k, F_SETFD, 0, 0)
                            : raw_call(SYS_dup3, r->fds[k], k, 0, 0);
        if (rc < 0)
            goto fail;
    }
    step = "close_range";
    if ((rc = raw_call(SYS_close_range, 3, (long)~0U, CLOSE_RANGE_CLOEXEC, 0)) < 0)
        goto fail;
    step = r->cwd;
    if ((rc = raw_call(SYS_chdir, (long)r->cwd, 0, 0, 0)) < 0)
        goto fail;
    step = r->prog;
    rc = raw_call(SYS_execve, (long)r->prog, (long)r->argv, (long)r->envp, 0);
fail:
    r->failed_errno = rc < 0 && rc > -4096 ? (int)-rc : EINVAL;
    r->failed_step = step;
    return 127;   /* glibc's clone calls exit with it */
}
#endif

int spawn_async_busy(const struct spawn_async *a)
{
    return __atomic_load_n(&a->live, __ATOMIC_ACQUIRE) != 0;
}

/* Copy prog, cwd, paths and argv into a's own block (the caller frees its copy
 * as soon as the start returns, while the child may not have read it). */
static int copy_request(struct spawn_async *a, const struct spawn_request *r, struct err *e)
{
    size_t n = 0, bytes = strlen(r->prog) + strlen(r->cwd) + 2;
    for (int k = 0; k < 3; k++)
        bytes += r->paths[k] ? strlen(r->paths[k]) + 1 : 0;
    while (r->argv[n])
        bytes += strlen(r->argv[n++]) + 1;
    char *block = mem_realloc(a->block, bytes);
    if (!block)
        return err_nomem(e, "job start");
    a->block = block;
    char **argv = mem_realloc(a->argv, (n + 1) * sizeof *argv);
    if (!argv)
        return err_nomem(e, "job start");
    a->argv = argv;
    char *p = block;
    a->req = *r;
    a->req.prog = strcpy(p, r->prog);
    p += strlen(p) + 1;
    a->req.cwd = strcpy(p, r->cwd);
    p += strlen(p) + 1;
    for (int k = 0; k < 3; k++)
        if (r->paths[k]) {
            a->req.paths[k] = strcpy(p, r->paths[k]);
            p += strlen(p) + 1;
        }
    for (size_t i = 0; i < n; i++) {
        argv[i] = strcpy(p, r->argv[i]);
        p += strlen(p) + 1;
    }
    argv[n] = NULL;
    a->req.argv = argv;
    a->req.failed_errno = 0;
    a->req.failed_step = NULL;
    return 0;
}

int spawn_async_start(struct spawn_async *a, const struct spawn_request *r, pid_t *pid,
                      struct err *e)
{
    /* a child reaped has left the memory; this wait is for a caller that
     * reuses a before reaping (none does) */
    while (spawn_async_busy(a))
        syscall(SYS_futex, &a->live, FUTEX_WAIT, 1, NULL, NULL, 0);
    if (!a->stack.base && spawn_stack_init(&a->stack, e) != 0)
        return ERR_RUNTIME;
    int rc = copy_request(a, r, e);
    if (rc)
        return rc;
#if SPAWN_RAW
    a->asynchronous = 1;
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    char *top = (char *)a->stack.base + a->stack.len;
    top -= (size_t)(uintptr_t)top % 64;
    __atomic_store_n(&a->live, 1, __ATOMIC_RELEASE);
    pid_t p = clone(async_child, top, CLONE_VM | CLONE_CHILD_CLEARTID | SIGCHLD, &a->req, NULL,
                    NULL, &a->live);
    int clone_errno = errno;
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (p < 0) {
        __atomic_store_n(&a->live, 0, __ATOMIC_RELEASE);
        return err_set(e, ERR_RUNTIME, "clone: %s", strerror(clone_errno));
    }
    *pid = p;
    return 0;
#else
    a->asynchronous = 0;
    return spawn_start(&a->req, &a->stack, pid, e);
#endif
}

void spawn_async_fini(struct spawn_async *a)
{
    spawn_stack_fini(&a->stack);
    free(a->block);
    free(a->argv);
    a->block = NULL;
    a->argv = NULL;
}
