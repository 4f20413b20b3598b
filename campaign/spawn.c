/* spawn: clone(CLONE_VM | CLONE_VFORK) + execve with the job's set-up (spawn.h). */
#define _GNU_SOURCE   /* clone, close_range */
#include "spawn.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <unistd.h>

#ifndef CLOSE_RANGE_CLOEXEC
#define CLOSE_RANGE_CLOEXEC (1U << 2)
#endif

/* The child makes a dozen system calls through thin libc wrappers; 64 KiB
 * is generous for them even under AddressSanitizer's interceptors, and a
 * guard page below turns an overflow into a fault rather than a write
 * into the runner's heap. */
#define SPAWN_STACK_BYTES (64u * 1024u)

int spawn_stack_init(struct spawn_stack *s, struct err *e)
{
    long page = sysconf(_SC_PAGESIZE);
    size_t guard = page > 0 ? (size_t)page : 4096;
    s->len = SPAWN_STACK_BYTES + guard;
    s->base = mmap(NULL, s->len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK,
                   -1, 0);
    if (s->base == MAP_FAILED) {
        s->base = NULL;
        return err_set(e, ERR_RUNTIME, "cannot map a stack for starting jobs: %s", strerror(errno));
    }
    if (mprotect(s->base, guard, PROT_NONE) != 0) {
        int rc = err_set(e, ERR_RUNTIME, "cannot protect the job-start stack: %s", strerror(errno));
        spawn_stack_fini(s);
        return rc;
    }
    return 0;
}

void spawn_stack_fini(struct spawn_stack *s)
{
    if (s->base)
        munmap(s->base, s->len);
    s->base = NULL;
    s->len = 0;
}

/* The signals the runner takes synchronously, and SIGPIPE: default in the
 * job whatever the runner had (exec_local.c blocks the first four). */
static const int reset_always[] = {SIGCHLD, SIGINT, SIGTERM, SIGHUP, SIGPIPE};

/* Runs on the spawn stack with the caller's memory: system calls only, and
 * one function, so nothing in it is instrumented: AddressSanitizer would
 * poison shadow memory for frames on a stack it does not know, and its
 * no-return hook before _exit would unpoison the caller's. */
__attribute__((no_sanitize_address)) static int child_main(void *arg)
{
    struct spawn_request *r = arg;
    const char *step;
    /* every caught signal to SIG_DFL first: all are blocked (the caller's
     * mask, inherited), so none could run a handler yet */
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    for (int sig = 1; sig < NSIG; sig++) {
        struct sigaction old;
        if (sig == SIGKILL || sig == SIGSTOP || sigaction(sig, NULL, &old) != 0)
            continue;   /* glibc's internal signals answer EINVAL: not ours */
        if (old.sa_handler != SIG_DFL && old.sa_handler != SIG_IGN)
            sigaction(sig, &dfl, NULL);
    }
    for (size_t i = 0; i < sizeof reset_always / sizeof reset_always[0]; i++)
        sigaction(reset_always[i], &dfl, NULL);
    step = "setpgid";
    if (setpgid(0, 0) != 0)
        goto fail;
    step = "prctl(PR_SET_PDEATHSIG)";
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0)
        goto fail;
    if (getppid() != r->parent) {   /* the caller was killed meanwhile */
        step = "the runner is gone";
        errno = ESRCH;
        goto fail;
    }
    sigset_t none;
    sigemptyset(&none);
    step = "sigprocmask";
    if (sigprocmask(SIG_SETMASK, &none, NULL) != 0)
        goto fail;
    /* dup2 clears close-on-exec on the copies and the originals close at
     * exec -- unless one already is its target (the runner started with
     * that descriptor closed): then dup2 does nothing, so clear it here.
     * The caller opened fds[] in order, so fds[k] >= k and no dup2
     * overwrites a source still to be copied. */
    step = "dup2";
    for (int k = 0; k < 3; k++) {
        if (r->paths[k]) {
            /* 0..k-1 are in place, so the new descriptor is >= k */
            step = r->paths[k];
            int fd = open(r->paths[k], k ? O_WRONLY | O_CREAT | O_TRUNC : O_RDONLY, 0666);
            if (fd < 0 || (fd != k && (dup2(fd, k) < 0 || close(fd) != 0)))
                goto fail;
            step = "dup2";
            continue;
        }
        if (r->fds[k] == k ? fcntl(k, F_SETFD, 0) != 0 : dup2(r->fds[k], k) < 0)
            goto fail;
    }
    step = "close_range";
    if (close_range(3, ~0U, CLOSE_RANGE_CLOEXEC) != 0)
        goto fail;
    step = r->cwd;
    if (chdir(r->cwd) != 0)
        goto fail;
    step = r->prog;
    execve(r->prog, r->argv, r->envp);
fail:
    r->failed_errno = errno ? errno : EINVAL;
    r->failed_step = step;
    _exit(127);
}

int spawn_start(struct spawn_request *r, struct spawn_stack *s, pid_t *pid, struct err *e)
{
    r->failed_errno = 0;
    r->failed_step = NULL;
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    /* the stack grows down on every architecture Linux runs this on here */
    char *top = (char *)s->base + s->len;
    top -= (size_t)top % 64;
    pid_t p = clone(child_main, top, CLONE_VM | CLONE_VFORK | SIGCHLD, r);
    int clone_errno = errno;
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (p < 0)
        return err_set(e, ERR_RUNTIME, "clone: %s", strerror(clone_errno));
    *pid = p;
    return 0;
}
