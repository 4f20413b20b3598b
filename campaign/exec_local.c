/*
 * exec_local: job attempts as child processes of this one.
 *
 * Each child leads its own process group (so a timeout or a cancel reaches
 * every process the job started, and the terminal's Ctrl-C reaches only the
 * runner), dies with the runner (PR_SET_PDEATHSIG), runs in the study's
 * directory with stdout and stderr in files of its run directory, and gets
 * the environment without the runner's MPI variables (childenv.h).  It is
 * started without fork's copy of the runner's page tables and without the
 * runner waiting for its exec (spawn.h, spawn_async_start); a start that
 * failed in the child is written into the job's stderr when it is reaped.
 */
#include "backend.h"

#include <errno.h>
#include <fcntl.h>
#include <malloc.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "childenv.h"
#include "spawn.h"
#include "sysinfo.h"
#include "util/fault.h"
#include "util/mem.h"

#define KILL_GRACE_S 2.0

struct exec_slot {
    int busy;
    pid_t pid;
    double t0;             /* monotonic start */
    double started;        /* Unix start */
    double deadline;       /* monotonic, 0: none */
    double kill_at;        /* monotonic time to send SIGKILL, 0: not yet */
    int timed_out, cancelled;
    double timeout;
    char run_dir[4096];
};

struct exec_local {
    int nslots;
    struct exec_slot *slots;
    char **env;
    struct spawn_async *spawns;   /* per slot: the child's stack and request */
    pid_t pid;                    /* this process: a child checks it is still its parent */
    char host[256];
};

static const int handled_signals[] = {SIGCHLD, SIGINT, SIGTERM, SIGHUP};

static void signal_set(sigset_t *set)
{
    sigemptyset(set);
    for (size_t i = 0; i < sizeof handled_signals / sizeof handled_signals[0]; i++)
        sigaddset(set, handled_signals[i]);
}

void backend_block_signals(void)
{
    sigset_t set;
    signal_set(&set);
    sigprocmask(SIG_BLOCK, &set, NULL);
}

struct exec_local *exec_local_create(int nslots)
{
    struct exec_local *x = mem_calloc(1, sizeof *x);
    if (!x)
        return NULL;
    x->nslots = nslots < 1 ? 1 : nslots;
    /* A job's set-up runs on the runner's memory (spawn.h), often on the
     * other core; every page the runner later gives back to the kernel then
     * costs a TLB shoot-down there (an interrupt, a VM exit under a
     * hypervisor).  glibc gave back the top of the heap after nearly every
     * SQLite statement with a trigger (its statement journal and trigger
     * frames, freed at the statement's end) and faulted it in again on the
     * next: 10-15 % of the runner's CPU time per job (docs/bench.md).  The
     * runner's heap stays at its high-water mark instead (a few MiB). */
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    x->slots = mem_calloc((size_t)x->nslots, sizeof *x->slots);
    x->spawns = mem_calloc((size_t)x->nslots, sizeof *x->spawns);
    x->env = childenv_create();
    x->pid = getpid();
    sys_hostname(x->host, sizeof x->host);
    if (!x->slots || !x->spawns || !x->env) {
        exec_local_destroy(&x);
        return NULL;
    }
    return x;
}

void exec_local_destroy(struct exec_local **px)
{
    struct exec_local *x = px ? *px : NULL;
    if (!x)
        return;
    for (int i = 0; x->slots && i < x->nslots; i++)
        if (x->slots[i].busy) {
            kill(-x->slots[i].pid, SIGKILL);
            waitpid(x->slots[i].pid, NULL, 0);
        }
    for (int i = 0; x->spawns && i < x->nslots; i++)
        spawn_async_fini(&x->spawns[i]);
    free(x->spawns);
    free(x->slots);
    free(x->env);
    free(x);
    *px = NULL;
}

int exec_local_busy(const struct exec_local *x)
{
    int n = 0;
    for (int i = 0; i < x->nslots; i++)
        n += x->slots[i].busy;
    return n;
}

pid_t exec_local_pid(const struct exec_local *x, int slot)
{
    return x->slots[slot].busy ? x->slots[slot].pid : 0;
}

/* argv[0] as a path: as given when it holds '/', else searched on PATH. */
static void find_program(const char *name, char *out, size_t len)
{
    snprintf(out, len, "%s", name);
    if (strchr(name, '/'))
        return;
    const char *path = getenv("PATH");
    char buf[8192];
    snprintf(buf, sizeof buf, "%s", path ? path : "/usr/bin:/bin");
    char *save = NULL;
    for (char *d = strtok_r(buf, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
        snprintf(out, len, "%s/%s", d, name);
        if (access(out, X_OK) == 0)
            return;
    }
    snprintf(out, len, "%s", name);
}

int exec_local_start(struct exec_local *x, int slot, const struct launch_spec *L, struct err *e)
{
    struct exec_slot *s = &x->slots[slot];
    int rc = L->dir_ready ? 0 : launch_setup_dir(L, e);
    if (rc)
        return rc;
    char prog[4096], out_path[4096 + 16], err_path[4096 + 16];
    find_program(L->argv[0], prog, sizeof prog);
    snprintf(out_path, sizeof out_path, "%s/stdout", L->run_dir);
    snprintf(err_path, sizeof err_path, "%s/stderr", L->run_dir);
    /* opened by the child (spawn.h), as a shell's redirection is, beside
     * the runner rather than by it (two new inodes, docs/bench.md).  A
     * child that cannot open one exits 127 and its reason, with the path,
     * reaches the job's stderr and the outcome's message when it is reaped
     * (start_failure).  An injected write fault still fails here, at the
     * same count as when the runner opened them. */
    const char *paths[3] = {"/dev/null", out_path, err_path};
    for (int k = 1; k < 3 && !rc; k++)
        if (fault_write(ENOSPC) != 0)
            rc = err_set(e, ERR_RUNTIME, "cannot create %s: %s", paths[k], strerror(errno));
    struct spawn_request req = {prog, L->argv, x->env, L->cwd, {-1, -1, -1},
                                {paths[0], paths[1], paths[2]}, x->pid, 0, NULL};
    pid_t pid = 0;
    if (!rc)
        rc = spawn_async_start(&x->spawns[slot], &req, &pid, e);
    if (rc)
        return rc;
    setpgid(pid, pid);   /* also here, so a kill(-pid) right away reaches it */
    memset(s, 0, sizeof *s);
    s->busy = 1;
    s->pid = pid;
    s->t0 = sys_mono();
    s->started = sys_now();
    s->timeout = L->timeout;
    s->deadline = L->timeout > 0 ? s->t0 + L->timeout : 0;
    snprintf(s->run_dir, sizeof s->run_dir, "%s", L->run_dir);
    return 0;
}

void exec_local_cancel(struct exec_local *x, int slot)
{
    struct exec_slot *s = &x->slots[slot];
    if (!s->busy || s->cancelled)
        return;
    s->cancelled = !s->timed_out;
    kill(-s->pid, SIGTERM);
    s->kill_at = sys_mono() + KILL_GRACE_S;
}

/* The child exited 127 without starting the program: say why (into why,
 * "" when it did start) and where a job says it, its stderr file (created
 * if the child could not).  Read once the child is reaped: it wrote the
 * reason into its request before exiting. */
static void start_failure(const struct spawn_async *a, const char *run_dir, char *why,
                          size_t len)
{
    why[0] = '\0';
    if (!a->req.failed_errno)
        return;
    snprintf(why, len, "cascade: cannot start the job: %s: %s", a->req.failed_step,
             strerror(a->req.failed_errno));
    char path[4096 + 16];
    snprintf(path, sizeof path, "%s/stderr", run_dir);
    int fd = open(path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0)
        return;
    dprintf(fd, "%s\n", why);
    close(fd);
}

static int reap(struct exec_local *x, backend_done_fn done, void *ctx)
{
    int n = 0;
    for (int i = 0; i < x->nslots; i++) {
        struct exec_slot *s = &x->slots[i];
        if (!s->busy)
            continue;
        int status;
        struct rusage ru;
        pid_t r = wait4(s->pid, &status, WNOHANG, &ru);
        if (r == 0 || (r < 0 && errno == EINTR))
            continue;
        /* the group may outlive its leader: end it before the pid can be reused */
        kill(-s->pid, SIGKILL);
        s->busy = 0;
        char why[OUTCOME_MSG_MAX];
        start_failure(&x->spawns[i], s->run_dir, why, sizeof why);
        struct outcome o;
        memset(&o, 0, sizeof o);
        struct exit_info xi = {r < 0 ? (127 << 8) : status, s->timed_out, s->cancelled, s->timeout,
                               r < 0};
        outcome_collect(&o, s->run_dir, &xi);
        /* the set-up's own reason, also when it was the stderr file that
         * could not be created (outcome.c quotes stderr's last line) */
        if (why[0] && o.failure == FC_INFRA && o.exit_code == 127)
            snprintf(o.message, sizeof o.message, "could not start the solver: %s", why);
        o.started = s->started;
        o.finished = sys_now();
        o.wall_s = sys_mono() - s->t0;
        o.peak_rss_mib = r < 0 ? 0 : (double)ru.ru_maxrss / 1024.0;
        o.pid = (int)s->pid;
        snprintf(o.host, sizeof o.host, "%s", x->host);
        done(ctx, i, &o);
        n++;
    }
    return n;
}

static void enforce_limits(struct exec_local *x, double now)
{
    for (int i = 0; i < x->nslots; i++) {
        struct exec_slot *s = &x->slots[i];
        if (!s->busy)
            continue;
        if (s->deadline > 0 && now >= s->deadline && !s->timed_out && !s->cancelled) {
            s->timed_out = 1;
            kill(-s->pid, SIGTERM);
            s->kill_at = now + KILL_GRACE_S;
        }
        if (s->kill_at > 0 && now >= s->kill_at) {
            kill(-s->pid, SIGKILL);
            s->kill_at = 0;
        }
    }
}

static double next_event(const struct exec_local *x, double now, double max_wait)
{
    double t = max_wait;
    for (int i = 0; i < x->nslots; i++) {
        const struct exec_slot *s = &x->slots[i];
        if (!s->busy)
            continue;
        if (s->deadline > 0 && !s->timed_out && s->deadline - now < t)
            t = s->deadline - now;
        if (s->kill_at > 0 && s->kill_at - now < t)
            t = s->kill_at - now;
    }
    return t < 0 ? 0 : t;
}

int exec_local_wait(struct exec_local *x, double max_wait, backend_done_fn done, void *ctx)
{
    sigset_t set;
    signal_set(&set);
    double now = sys_mono();
    enforce_limits(x, now);
    if (reap(x, done, ctx) > 0)
        max_wait = 0;   /* let the caller refill the slot first */
    double t = next_event(x, now, max_wait);
    struct timespec ts = {(time_t)t, (long)((t - (double)(time_t)t) * 1e9)};
    int sig = sigtimedwait(&set, NULL, &ts);
    int caught = 0;
    if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP)
        caught = sig;
    /* collect every pending SIGCHLD at once */
    struct timespec zero = {0, 0};
    sigset_t chld;
    sigemptyset(&chld);
    sigaddset(&chld, SIGCHLD);
    while (sigtimedwait(&chld, NULL, &zero) > 0) {
    }
    enforce_limits(x, sys_mono());
    reap(x, done, ctx);
    return caught;
}

/* --- the local backend ---------------------------------------------------- */

static int local_start(struct backend *b, int slot, const struct launch_spec *L, struct err *e)
{
    return exec_local_start(b->impl, slot, L, e);
}

static int local_wait(struct backend *b, double max_wait, backend_done_fn done, void *ctx)
{
    return exec_local_wait(b->impl, max_wait, done, ctx);
}

static void local_cancel(struct backend *b, int slot)
{
    exec_local_cancel(b->impl, slot);
}

static void local_destroy(struct backend *b)
{
    struct exec_local *x = b->impl;
    exec_local_destroy(&x);
    b->impl = NULL;
}

int backend_local_create(struct backend *b, int nslots, struct err *e)
{
    memset(b, 0, sizeof *b);
    b->impl = exec_local_create(nslots);
    if (!b->impl)
        return err_nomem(e, "executor");
    b->nslots = nslots < 1 ? 1 : nslots;
    b->claim_ahead = 1;
    b->start = local_start;
    b->wait = local_wait;
    b->cancel = local_cancel;
    b->destroy = local_destroy;
    return 0;
}
