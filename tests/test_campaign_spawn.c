/*
 * How a job's process is started (campaign/spawn.h): without fork, with
 * the set-up fork + exec gave it.  A runner started the way a careless
 * shell or make would start it -- SIGPIPE, SIGINT and SIGUSR1 ignored, a
 * descriptor open without close-on-exec, a pipe's write end among its
 * descriptors, fault-injection variables set -- runs stand-in jobs that
 * report their own state (action probe): empty signal mask, SIGPIPE and
 * SIGINT back to default while SIGUSR1 stays ignored (as exec leaves it),
 * a process group of their own, SIGKILL as parent-death signal, no
 * descriptor beyond 0-2 and no CASCADE_FAULT_* variable; the solver's
 * `info` and `resolve --batch`, started before the jobs, hold no
 * descriptor beyond 0-2 either (the stand-in fails when they do).  A program that
 * cannot be started, or a directory that cannot be entered, leaves its
 * reason in the job's stderr file and ends with 127 (an infrastructure
 * failure, not the job's).
 */
#include <criterion/criterion.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "campaign/backend.h"
#include "helpers/ct.h"

/* The stray descriptor the runner inherits (no close-on-exec). */
#define STRAY_FD 9

/* `cascade run s.yaml` in dir, started as described above; its output
 * into out (read through the stray pipe's other end too: EOF there means
 * no process holds it any more). */
static int run_carelessly(const char *dir, char *out, size_t len)
{
    int p[2], stray[2];
    cr_assert_eq(pipe(p), 0);
    cr_assert_eq(pipe(stray), 0);
    pid_t pid = fork();
    cr_assert(pid >= 0);
    if (pid == 0) {
        if (chdir(dir) != 0)
            _exit(126);
        putenv("CASCADE_FAULT_IO=0");
        putenv("CASCADE_FAULT_WRITE=0");
        putenv("CASCADE_FAKE_STRICT_FDS=1");   /* `info` and `resolve` too */
        signal(SIGPIPE, SIG_IGN);
        signal(SIGINT, SIG_IGN);
        signal(SIGUSR1, SIG_IGN);
        if (dup2(stray[1], STRAY_FD) < 0)
            _exit(126);
        dup2(p[1], 1);
        dup2(p[1], 2);
        close(p[0]);
        close(p[1]);
        close(stray[0]);
        close(stray[1]);
        const char *argv[] = {ct_cascade_bin(), "run", "s.yaml", "--solver", ct_standin(),
                              "--jobs", "2", NULL};
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(p[1]);
    close(stray[1]);
    size_t n = 0;
    char buf[4096];
    ssize_t got;
    while ((got = read(p[0], buf, sizeof buf)) > 0) {
        size_t take = (size_t)got < len - 1 - n ? (size_t)got : len - 1 - n;
        memcpy(out + n, buf, take);
        n += take;
    }
    out[n] = '\0';
    close(p[0]);
    int rc = ct_wait(pid);
    /* the runner has exited; its jobs were reaped before: nothing may hold
     * the stray pipe now (a read would block forever otherwise) */
    cr_assert_eq(fcntl(stray[0], F_SETFL, O_NONBLOCK), 0);
    cr_assert_eq(read(stray[0], buf, sizeof buf), 0, "the stray pipe is still open somewhere");
    close(stray[0]);
    return rc;
}

Test(campaign_spawn, job_gets_the_set_up_fork_and_exec_gave, .timeout = 120)
{
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml",
             "name: probe\nbase: {fake: {action: probe}}\nsweep: {grid: {fake.x: [1, 2, 3, 4]}}\n");
    int rc = run_carelessly(dir, out, sizeof out);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 4, "%s", out);
    /* one value per metric over the four jobs, and which */
    struct {
        const char *metric;
        double want;
    } const expect[] = {
        {"sig_blocked", 0},
        {"own_group", 1},
        {"pdeathsig", SIGKILL},
        {"extra_fds", 0},
        {"fault_env", 0},
    };
    for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++) {
        char sql[256];
        snprintf(sql, sizeof sql,
                 "SELECT count(*) FROM metrics WHERE name = '%s' AND value = %.17g",
                 expect[i].metric, expect[i].want);
        long long n = ct_int(db, sql);
        snprintf(sql, sizeof sql, "SELECT group_concat(value) FROM metrics WHERE name = '%s'",
                 expect[i].metric);
        char got[256];
        ct_text(db, sql, got, sizeof got);
        cr_assert_eq(n, 4, "%s: want %.17g in each of the 4 jobs, got %s", expect[i].metric,
                     expect[i].want, got);
    }
    /* ignored: SIGUSR1 still (exec keeps an ignored signal ignored, and so
     * did fork + exec); the runner's own signals and SIGPIPE back to
     * default.  (Other bits are the environment's: under Criterion the
     * real-time signal 32 is ignored, and it is passed on as it was.) */
    unsigned long long must = 1ull << (SIGUSR1 - 1), never = 0;
    const int dfl[] = {SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGCHLD};
    for (size_t i = 0; i < sizeof dfl / sizeof dfl[0]; i++)
        never |= 1ull << (dfl[i] - 1);
    char sql[256];
    snprintf(sql, sizeof sql,
             "SELECT count(*) FROM metrics WHERE name = 'sig_ignored' AND "
             "(CAST(value AS INTEGER) & %llu) = %llu AND (CAST(value AS INTEGER) & %llu) = 0",
             must, must, never);
    cr_assert_eq(ct_int(db, sql), 4, "sig_ignored: SIGUSR1 not ignored or a default one ignored");
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* --- a start that fails, through the executor itself ----------------------- */

struct seen {
    int calls;
    enum run_status status;
    enum failure_class failure;
    int exit_code;
    char message[OUTCOME_MSG_MAX];
};

static void on_done(void *ctx, int slot, struct outcome *o)
{
    (void)slot;
    struct seen *s = ctx;
    s->calls++;
    s->status = o->status;
    s->failure = o->failure;
    s->exit_code = o->exit_code;
    snprintf(s->message, sizeof s->message, "%s", o->message);
    outcome_free(o);
}

/* Start argv in cwd (attempt directory dir/attempt-1) and wait for it. */
static struct seen start_and_wait(const char *dir, const char *cwd, const char *prog)
{
    struct launch_spec L;
    memset(&L, 0, sizeof L);
    snprintf(L.run_dir, sizeof L.run_dir, "%s/attempt-1", dir);
    snprintf(L.cwd, sizeof L.cwd, "%s", cwd);
    L.case_yaml = strdup("fake: {action: ok}\n");
    char *argv[] = {strdup(prog), strdup("run"), NULL};
    L.argv = argv;
    L.argc = 2;
    struct exec_local *x = exec_local_create(1);
    cr_assert_not_null(x);
    struct err e = {0};
    cr_assert_eq(exec_local_start(x, 0, &L, &e), 0, "%s", e.msg);
    struct seen s = {0};
    for (int i = 0; i < 400 && s.calls == 0; i++)
        exec_local_wait(x, 0.05, on_done, &s);
    cr_assert_eq(s.calls, 1, "the child was not reaped within 20 s");
    cr_assert_eq(exec_local_busy(x), 0);
    exec_local_destroy(&x);
    free(argv[0]);
    free(argv[1]);
    free(L.case_yaml);
    return s;
}

Test(campaign_spawn, a_program_that_cannot_start_says_why, .timeout = 60)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    struct seen o = start_and_wait(dir, dir, "/nonexistent/cascade-solver");
    cr_assert_eq(o.exit_code, 127);
    cr_assert_eq(o.status, RS_CANCELLED);
    cr_assert_eq(o.failure, FC_INFRA);
    cr_assert(strstr(o.message, "could not start the solver: cascade: cannot start the job: "
                                "/nonexistent/cascade-solver: No such file or directory"),
              "%s", o.message);
    ct_rmrf(dir);
}

Test(campaign_spawn, a_directory_that_cannot_be_entered_says_why, .timeout = 60)
{
    char dir[64], gone[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(gone, sizeof gone, "%s/no-such-study-dir", dir);
    struct seen o = start_and_wait(dir, gone, ct_standin());
    cr_assert_eq(o.exit_code, 127);
    cr_assert_eq(o.failure, FC_INFRA);
    char want[256];
    snprintf(want, sizeof want, "cannot start the job: %s: No such file or directory", gone);
    cr_assert(strstr(o.message, want), "%s", o.message);
    ct_rmrf(dir);
}
