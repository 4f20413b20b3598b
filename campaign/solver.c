/* solver: finding cascade-solver, `info`, and `resolve --batch`. */
#define _GNU_SOURCE   /* pipe2, close_range */
#include "solver.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "childenv.h"

#ifndef CLOSE_RANGE_CLOEXEC
#define CLOSE_RANGE_CLOEXEC (1U << 2)
#endif

static int executable(const char *p)
{
    return access(p, X_OK) == 0;
}

static int locate(char *out, size_t len, const char *given)
{
    if (given && given[0]) {
        snprintf(out, len, "%s", given);
        return executable(out) ? 0 : -1;
    }
    const char *env = getenv("CASCADE_SOLVER");
    if (env && env[0]) {
        snprintf(out, len, "%s", env);
        return executable(out) ? 0 : -1;
    }
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = '\0';
        snprintf(out, len, "%s/cascade-solver", dirname(self));
        if (executable(out))
            return 0;
    }
    const char *path = getenv("PATH");
    if (path) {
        char buf[8192];
        snprintf(buf, sizeof buf, "%s", path);
        char *save = NULL;
        for (char *d = strtok_r(buf, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
            snprintf(out, len, "%s/cascade-solver", d);
            if (executable(out))
                return 0;
        }
    }
    snprintf(out, len, "cascade-solver");
    return -1;
}

/* Start `argv` with stdin from in_fd (or /dev/null) and stdout to a pipe.
 * The child gets descriptors 0-2 and nothing else: the pipe and /dev/null
 * are opened close-on-exec, and whatever the runner itself inherited
 * without close-on-exec (a careless shell's or make's descriptors) is
 * marked so in the child before execve, as spawn.c does for jobs.  Only
 * `info` and `resolve` start this way, once per command, so fork's cost
 * does not matter here. */
static pid_t start(char *const *argv, int in_fd, int *out_fd, struct err *e)
{
    int p[2];
    if (pipe2(p, O_CLOEXEC) != 0)
        return err_set(e, ERR_RUNTIME, "pipe: %s", strerror(errno)), -1;
    int nul = in_fd >= 0 ? -1 : open("/dev/null", O_RDONLY | O_CLOEXEC);
    char **env = childenv_create();
    if (!env || (in_fd < 0 && nul < 0)) {
        int open_errno = errno;
        free(env);
        close(p[0]);
        close(p[1]);
        if (nul >= 0)
            close(nul);
        if (!env)
            return err_nomem(e, "environment"), -1;
        return err_set(e, ERR_RUNTIME, "/dev/null: %s", strerror(open_errno)), -1;
    }
    pid_t pid = fork();
    if (pid < 0) {
        int fork_errno = errno;
        free(env);
        close(p[0]);
        close(p[1]);
        if (nul >= 0)
            close(nul);
        return err_set(e, ERR_RUNTIME, "fork: %s", strerror(fork_errno)), -1;
    }
    if (pid == 0) {
        /* dup2 clears close-on-exec on the copies */
        if (dup2(in_fd >= 0 ? in_fd : nul, 0) < 0 || dup2(p[1], 1) < 0 ||
            close_range(3, ~0U, CLOSE_RANGE_CLOEXEC) != 0)
            _exit(127);
        execve(argv[0], argv, env);
        _exit(127);
    }
    free(env);
    close(p[1]);
    if (nul >= 0)
        close(nul);
    *out_fd = p[0];
    return pid;
}

static int finish(pid_t pid, const char *what, const char *path, struct err *e)
{
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return err_set(e, ERR_RUNTIME, "%s %s: wait: %s", path, what, strerror(errno));
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
        return 0;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
        return err_set(e, ERR_RUNTIME, "cannot execute solver '%s'", path);
    return err_set(e, ERR_RUNTIME, "solver '%s %s' failed (%s %d)", path, what,
                   WIFEXITED(status) ? "exit" : "signal",
                   WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
}

int solver_open(struct solver *s, const char *given, struct err *e)
{
    memset(s, 0, sizeof *s);
    if (locate(s->path, sizeof s->path, given) != 0)
        return err_set(e, ERR_INPUT,
                       "cannot find the solver '%s' (give --solver PATH or set CASCADE_SOLVER)",
                       s->path);
    char *argv[] = {s->path, "info", NULL};
    int fd;
    pid_t pid = start(argv, -1, &fd, e);
    if (pid < 0)
        return ERR_RUNTIME;
    FILE *f = fdopen(fd, "r");
    json_error_t je;
    json_t *info = f ? json_loadf(f, 0, &je) : NULL;
    if (f)
        fclose(f);
    else
        close(fd);
    int rc = finish(pid, "info", s->path, e);
    if (!rc && !json_is_object(info))
        rc = err_set(e, ERR_RUNTIME, "'%s info' did not print JSON: %s", s->path, je.text);
    if (!rc) {
        const char *v = json_string_value(json_object_get(info, "version"));
        const char *g = json_string_value(json_object_get(info, "git_hash"));
        if (!v || !g)
            rc = err_set(e, ERR_RUNTIME, "'%s info' lacks version or git_hash", s->path);
        else {
            snprintf(s->version, sizeof s->version, "%s", v);
            snprintf(s->git, sizeof s->git, "%s", g);
        }
    }
    json_decref(info);
    return rc;
}

int solver_resolve(const struct solver *s, FILE *in, long nlines, solver_answer_fn fn, void *ctx,
                   struct err *e)
{
    fflush(in);
    rewind(in);
    char *argv[] = {(char *)s->path, "resolve", "--batch", NULL};
    int fd;
    pid_t pid = start(argv, fileno(in), &fd, e);
    if (pid < 0)
        return ERR_RUNTIME;
    FILE *out = fdopen(fd, "r");
    if (!out) {
        close(fd);
        finish(pid, "resolve --batch", s->path, e);
        return err_set(e, ERR_RUNTIME, "fdopen: %s", strerror(errno));
    }
    char *line = NULL;
    size_t cap = 0;
    long n = 0;
    int rc = 0;
    while (getline(&line, &cap, out) >= 0) {
        if (rc)
            continue;   /* drain, so the solver is not stopped by a full pipe */
        json_error_t je;
        json_t *answer = json_loads(line, 0, &je);
        if (!json_is_object(answer))
            rc = err_set(e, ERR_RUNTIME, "solver resolve: answer %ld is not JSON: %s", n + 1,
                         je.text);
        else if (n >= nlines)
            rc = err_set(e, ERR_RUNTIME, "solver resolve: more answers than cases");
        else
            rc = fn(ctx, n, answer, e);
        json_decref(answer);
        n++;
    }
    free(line);
    fclose(out);
    struct err e2 = {0};
    int rc2 = finish(pid, "resolve --batch", s->path, &e2);
    if (!rc && rc2) {
        *e = e2;
        rc = rc2;
    }
    if (!rc && n != nlines)
        rc = err_set(e, ERR_RUNTIME, "solver resolve: %ld answers for %ld cases", n, nlines);
    return rc;
}
