/* slurm_cli: fork+exec of Slurm's client programs, output captured. */
#define _GNU_SOURCE   /* pipe2, close_range */
#include "slurm_cli.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef CLOSE_RANGE_CLOEXEC
#define CLOSE_RANGE_CLOEXEC (1U << 2)
#endif

#include "childenv.h"
#include "sysinfo.h"

static const char *const names[SP_COUNT] = {"sbatch", "squeue", "scontrol",
                                            "scancel", "sacct", "sacctmgr"};

const char *slurm_prog_name(enum slurm_prog p)
{
    return names[p];
}

int slurm_cli_init(struct slurm_cli *c, struct err *e)
{
    memset(c, 0, sizeof *c);
    c->env = childenv_create();
    c->timeout_s = 120;
    return c->env ? 0 : err_nomem(e, "environment");
}

void slurm_cli_fini(struct slurm_cli *c)
{
    free(c->env);
    c->env = NULL;
}

/* The program on PATH, into out; -1 when it is not there. */
static int find_on_path(const char *name, char *out, size_t len)
{
    const char *path = getenv("PATH");
    char buf[8192];
    snprintf(buf, sizeof buf, "%s", path ? path : "/usr/bin:/bin");
    char *save = NULL;
    for (char *d = strtok_r(buf, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
        snprintf(out, len, "%s/%s", d, name);
        if (access(out, X_OK) == 0)
            return 0;
    }
    return -1;
}

struct sink {
    char *buf;
    size_t n, cap;
};

static int sink_read(int fd, struct sink *s)
{
    if (s->cap - s->n < 4096) {
        size_t cap = s->cap ? 2 * s->cap : 16384;
        char *g = realloc(s->buf, cap);
        if (!g)
            return -1;
        s->buf = g;
        s->cap = cap;
    }
    ssize_t r = read(fd, s->buf + s->n, s->cap - s->n - 1);
    if (r < 0 && errno == EINTR)
        return 1;
    if (r <= 0)
        return 0;
    s->n += (size_t)r;
    s->buf[s->n] = '\0';
    return 1;
}

int slurm_cli_run(struct slurm_cli *c, enum slurm_prog prog, const char *const *args, char **out,
                  char *errtext, size_t errlen, int *status, struct err *e)
{
    *out = NULL;
    errtext[0] = '\0';
    *status = -1;
    char path[4096];
    if (find_on_path(names[prog], path, sizeof path) != 0)
        return err_set(e, ERR_RUNTIME, "%s is not on PATH (is this a Slurm login node?)",
                       names[prog]);
    size_t nargs = 0;
    while (args[nargs])
        nargs++;
    const char **argv = malloc((nargs + 2) * sizeof *argv);
    if (!argv)
        return err_nomem(e, "arguments");
    argv[0] = names[prog];
    memcpy(argv + 1, args, nargs * sizeof *argv);
    argv[nargs + 1] = NULL;
    int po[2], pe[2];
    if (pipe2(po, O_CLOEXEC) != 0) {
        free(argv);
        return err_set(e, ERR_RUNTIME, "pipe: %s", strerror(errno));
    }
    if (pipe2(pe, O_CLOEXEC) != 0) {
        free(argv);
        close(po[0]);
        close(po[1]);
        return err_set(e, ERR_RUNTIME, "pipe: %s", strerror(errno));
    }
    c->calls[prog]++;
    pid_t pid = fork();
    if (pid < 0) {
        free(argv);
        close(po[0]);
        close(po[1]);
        close(pe[0]);
        close(pe[1]);
        return err_set(e, ERR_RUNTIME, "fork: %s", strerror(errno));
    }
    if (pid == 0) {
        /* its own process group: a Ctrl-C meant for the runner does not cut
         * a submission in half */
        setpgid(0, 0);
        sigset_t none;
        sigemptyset(&none);
        signal(SIGPIPE, SIG_DFL);
        sigprocmask(SIG_SETMASK, &none, NULL);
        /* 0-2 and nothing else: what the runner inherited without
         * close-on-exec is marked so here (dup2 clears it on the copies) */
        int devnull = open("/dev/null", O_RDONLY | O_CLOEXEC);
        if (devnull < 0 || dup2(devnull, 0) < 0 || dup2(po[1], 1) < 0 || dup2(pe[1], 2) < 0 ||
            close_range(3, ~0U, CLOSE_RANGE_CLOEXEC) != 0)
            _exit(127);
        execve(path, (char *const *)argv, c->env);
        dprintf(2, "cannot run %s: %s\n", path, strerror(errno));
        _exit(127);
    }
    free(argv);
    close(po[1]);
    close(pe[1]);
    struct sink so = {0}, se = {0};
    struct pollfd fds[2] = {{po[0], POLLIN, 0}, {pe[0], POLLIN, 0}};
    int open_fds = 2, killed = 0;
    double deadline = sys_mono() + c->timeout_s;
    while (open_fds > 0) {
        double left = deadline - sys_mono();
        if (left <= 0 && !killed) {
            kill(pid, SIGKILL);
            killed = 1;
        }
        int r = poll(fds, 2, left > 0 ? (int)(left * 1000) + 1 : 1000);
        if (r < 0 && errno != EINTR)
            break;
        for (int k = 0; k < 2; k++) {
            if (fds[k].fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP | POLLERR)))
                continue;
            int more = sink_read(fds[k].fd, k ? &se : &so);
            if (more < 0 || !more) {
                close(fds[k].fd);
                fds[k].fd = -1;
                open_fds--;
            }
        }
    }
    for (int k = 0; k < 2; k++)
        if (fds[k].fd >= 0)
            close(fds[k].fd);
    int ws = 0;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {
    }
    *status = WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + WTERMSIG(ws);
    if (se.buf) {
        /* the last lines say why */
        size_t n = se.n;
        while (n > 0 && (se.buf[n - 1] == '\n' || se.buf[n - 1] == ' '))
            se.buf[--n] = '\0';
        const char *tail = n >= errlen ? se.buf + n - (errlen - 1) : se.buf;
        snprintf(errtext, errlen, "%s", tail);
        for (char *p = errtext; *p; p++)
            if (*p == '\n')
                *p = ' ';
    }
    free(se.buf);
    if (killed) {
        free(so.buf);
        return err_set(e, ERR_RUNTIME, "%s did not answer within %.0f s", names[prog],
                       c->timeout_s);
    }
    if (*status == 127 && strstr(errtext, "cannot run")) {
        free(so.buf);
        return err_set(e, ERR_RUNTIME, "%s", errtext);
    }
    *out = so.buf ? so.buf : strdup("");
    if (!*out)
        return err_nomem(e, "output");
    return 0;
}
