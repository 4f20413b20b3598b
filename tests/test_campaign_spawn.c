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
 * cannot be started, a directory that cannot be entered, or a stdout that
 * cannot be created (the child creates it), leaves its reason in the job's
 * stderr file and ends with 127 (an infrastructure failure, not the job's).  The runner does not wait for a job's exec
 * (spawn_async_start): a job reads its own copy of the command line, which
 * the runner frees and overwrites at once, and a job cancelled the moment
 * it was started is already in its own process group, which the SIGTERM
 * ends (not the SIGKILL 2 s later).
 */
#include <criterion/criterion.h>
#include <fcntl.h>
#include <jansson.h>
#include <sys/stat.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "campaign/backend.h"
#include "campaign/spawn.h"
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

/* The child creates the job's stdout and stderr itself: one that cannot be
 * created (a directory of that name in the way) is a start that failed,
 * with the path and the reason in the message and in stderr. */
Test(campaign_spawn, a_stdout_that_cannot_be_created_says_why, .timeout = 60)
{
    char dir[64], in_way[128], errf[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(in_way, sizeof in_way, "%s/attempt-1/stdout", dir);
    snprintf(errf, sizeof errf, "%s/attempt-1", dir);
    cr_assert_eq(mkdir(errf, 0777), 0);
    cr_assert_eq(mkdir(in_way, 0777), 0);
    struct seen o = start_and_wait(dir, dir, ct_standin());
    cr_assert_eq(o.exit_code, 127);
    cr_assert_eq(o.status, RS_CANCELLED);
    cr_assert_eq(o.failure, FC_INFRA);
    char want[256];
    snprintf(want, sizeof want, "could not start the solver: cascade: cannot start the job: %s: "
                                "Is a directory", in_way);
    cr_assert(strstr(o.message, want), "%s", o.message);
    char tail[1024];
    snprintf(errf, sizeof errf, "%s/attempt-1/stderr", dir);
    outcome_file_tail(errf, 1, tail, sizeof tail);
    cr_assert(strstr(tail, "Is a directory"), "stderr says: %s", tail);
    ct_rmrf(dir);
}

/* --- the start the runner does not wait for (spawn_async_start) ------------ */

struct counted {
    int calls;
    enum run_status status[8];
    double wall_s[8];
};

static void count_done(void *ctx, int slot, struct outcome *o)
{
    struct counted *c = ctx;
    c->calls++;
    c->status[slot] = o->status;
    c->wall_s[slot] = o->wall_s;
    outcome_free(o);
}

/* A launch of argv (copied) with its attempt directory dir/attempt-<slot>. */
static void make_launch(struct launch_spec *L, const char *dir, int slot,
                        const char *const *argv)
{
    memset(L, 0, sizeof *L);
    snprintf(L->run_dir, sizeof L->run_dir, "%s/attempt-%d", dir, slot + 1);
    snprintf(L->cwd, sizeof L->cwd, "%s", dir);
    L->case_yaml = strdup("fake: {action: ok}\n");
    while (argv[L->argc])
        L->argc++;
    L->argv = calloc((size_t)L->argc + 1, sizeof *L->argv);
    for (int i = 0; i < L->argc; i++)
        L->argv[i] = strdup(argv[i]);
}

static void wait_all(struct exec_local *x, struct counted *c, int n)
{
    for (int i = 0; i < 600 && c->calls < n; i++)
        exec_local_wait(x, 0.05, count_done, c);
    cr_assert_eq(c->calls, n, "%d of %d jobs reaped within 30 s", c->calls, n);
}

/* The runner frees the command line as soon as the start returns, maybe
 * before the child (running beside it on the same memory) has exec'd: the
 * child must read a copy of its own.  Eight starts in a row, each command
 * line overwritten and freed at once; each job prints what it got. */
Test(campaign_spawn, the_job_reads_its_own_copy_of_the_command, .timeout = 60)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    struct exec_local *x = exec_local_create(8);
    cr_assert_not_null(x);
    for (int k = 0; k < 8; k++) {
        char word[32];
        snprintf(word, sizeof word, "argument-of-job-%d", k);
        const char *argv[] = {"/bin/echo", word, NULL};
        struct launch_spec L;
        make_launch(&L, dir, k, argv);
        struct err e = {0};
        cr_assert_eq(exec_local_start(x, k, &L, &e), 0, "%s", e.msg);
        for (int i = 0; i < L.argc; i++)
            memset(L.argv[i], 'X', strlen(L.argv[i]));
        memset(L.cwd, 0, sizeof L.cwd);
        launch_free(&L);
    }
    struct counted c = {0};
    wait_all(x, &c, 8);
    exec_local_destroy(&x);
    for (int k = 0; k < 8; k++) {
        char path[128], got[256] = "", want[64];
        snprintf(path, sizeof path, "%s/attempt-%d/stdout", dir, k + 1);
        FILE *f = fopen(path, "r");
        cr_assert_not_null(f, "no %s", path);
        cr_assert_not_null(fgets(got, sizeof got, f), "%s is empty", path);
        fclose(f);
        snprintf(want, sizeof want, "argument-of-job-%d\n", k);
        cr_assert_str_eq(got, want, "job %d printed %s", k, got);
    }
    ct_rmrf(dir);
}

/* The runner does not wait for the child's set-up, so a cancel (or a
 * timeout) may come before the child has made its process group: the
 * runner makes it too, at once, so the SIGTERM to the group reaches every
 * process of the job (a shell and its background sleep) rather than
 * nothing -- which would leave the job running until the SIGKILL 2 s
 * later, or for good if that missed too.  Cancelled at once, the job ends
 * well within the grace period. */
Test(campaign_spawn, a_job_cancelled_at_its_start_ends_with_its_group, .timeout = 60)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    struct exec_local *x = exec_local_create(2);
    cr_assert_not_null(x);
    const char *argv[] = {"/bin/sh", "-c", "sleep 30 & sleep 30; wait", NULL};
    for (int k = 0; k < 2; k++) {
        struct launch_spec L;
        make_launch(&L, dir, k, argv);
        struct err e = {0};
        cr_assert_eq(exec_local_start(x, k, &L, &e), 0, "%s", e.msg);
        exec_local_cancel(x, k);
        launch_free(&L);
    }
    struct counted c = {0};
    wait_all(x, &c, 2);
    exec_local_destroy(&x);
    for (int k = 0; k < 2; k++) {
        cr_assert_eq(c.status[k], RS_CANCELLED, "job %d: status %s", k,
                     run_status_name(c.status[k]));
        /* SIGTERM ended it, not the SIGKILL after the 2 s grace */
        cr_assert_lt(c.wall_s[k], 1.9, "job %d took %.2f s to end after its cancel", k,
                     c.wall_s[k]);
    }
    ct_rmrf(dir);
}

/* The start that waits for the exec (spawn_start): what spawn_async_start
 * falls back to on architectures without its raw system calls, so it is
 * not what runs the jobs here.  Run directly with the stand-in's probe,
 * a stray descriptor open and SIGUSR1 ignored: the same set-up, and the
 * stdout and stderr files the child was asked to create. */
static double probe_metric(json_t *res, const char *name)
{
    json_t *v = json_object_get(json_object_get(json_object_get(res, "metrics"), name), "value");
    cr_assert(json_is_number(v), "result.json has no metric %s", name);
    return json_number_value(v);
}

Test(campaign_spawn, the_waiting_start_gives_the_same_set_up, .timeout = 60)
{
    char dir[64], out[128], casef[128], outf[128], errf[128], res[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(casef, sizeof casef, "%s", ct_write(0, dir, "case.yaml", "fake: {action: probe}\n"));
    snprintf(out, sizeof out, "%s/out", dir);
    cr_assert_eq(mkdir(out, 0777), 0);
    snprintf(outf, sizeof outf, "%s/stdout", out);
    snprintf(errf, sizeof errf, "%s/stderr", out);
    char *argv[] = {(char *)ct_standin(), "run", casef, "--out", out, "--threads", "1",
                    "--quiet", "--no-progress", NULL};
    char *envp[] = {"PATH=/usr/bin:/bin", NULL};
    int stray = open("/dev/null", O_RDONLY);   /* no close-on-exec */
    cr_assert_geq(stray, 3);
    signal(SIGUSR1, SIG_IGN);
    struct spawn_stack st;
    struct err e = {0};
    cr_assert_eq(spawn_stack_init(&st, &e), 0, "%s", e.msg);
    struct spawn_request r = {argv[0], argv, envp, dir, {-1, -1, -1},
                              {"/dev/null", outf, errf}, getpid(), 0, NULL};
    pid_t pid = 0;
    cr_assert_eq(spawn_start(&r, &st, &pid, &e), 0, "%s", e.msg);
    cr_assert_eq(r.failed_errno, 0, "%s: %s", r.failed_step, strerror(r.failed_errno));
    int status = 0;
    cr_assert_eq(waitpid(pid, &status, 0), pid);
    spawn_stack_fini(&st);
    close(stray);
    signal(SIGUSR1, SIG_DFL);
    cr_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0, "status %d", status);
    cr_assert_eq(access(outf, F_OK), 0, "no %s", outf);
    cr_assert_eq(access(errf, F_OK), 0, "no %s", errf);
    snprintf(res, sizeof res, "%s/result.json", out);
    json_error_t je;
    json_t *j = json_load_file(res, 0, &je);
    cr_assert_not_null(j, "%s: %s", res, je.text);
    cr_assert_eq(probe_metric(j, "sig_blocked"), 0);
    cr_assert_eq(probe_metric(j, "own_group"), 1);
    cr_assert_eq(probe_metric(j, "pdeathsig"), SIGKILL);
    cr_assert_eq(probe_metric(j, "extra_fds"), 0);
    unsigned long long ign = (unsigned long long)probe_metric(j, "sig_ignored");
    cr_assert(ign & (1ull << (SIGUSR1 - 1)), "SIGUSR1 no longer ignored: %llx", ign);
    json_decref(j);
    ct_rmrf(dir);
}

/* Whether process pid has ended (gone, or a zombie nobody reaped yet). */
static int ended(pid_t pid)
{
    char path[64], buf[512];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return 1;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    const char *paren = strrchr(buf, ')');   /* "pid (comm) S ..." */
    return !paren || paren[1] == '\0' || paren[2] == 'Z' || paren[2] == 'X';
}

/* The runner does not wait for the child, so it may die before the child
 * has asked for PR_SET_PDEATHSIG: the child then finds its parent changed
 * and exits instead of starting the job.  A runner (a forked process here)
 * starts a long job and is killed the moment the start returns; the job
 * must end too, in either order of events. */
Test(campaign_spawn, a_job_started_as_the_runner_dies_dies_too, .timeout = 60)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    for (int round = 0; round < 5; round++) {
        int p[2];
        cr_assert_eq(pipe(p), 0);
        pid_t runner = fork();
        cr_assert(runner >= 0);
        if (runner == 0) {
            close(p[0]);
            struct exec_local *x = exec_local_create(1);
            const char *argv[] = {"/bin/sleep", "30", NULL};
            struct launch_spec L;
            make_launch(&L, dir, round, argv);
            struct err e = {0};
            if (!x || exec_local_start(x, 0, &L, &e) != 0)
                _exit(3);
            pid_t job = exec_local_pid(x, 0);
            if (write(p[1], &job, sizeof job) != (ssize_t)sizeof job)
                _exit(4);
            kill(getpid(), SIGKILL);
        }
        close(p[1]);
        pid_t job = 0;
        cr_assert_eq(read(p[0], &job, sizeof job), (ssize_t)sizeof job, "the runner failed");
        close(p[0]);
        cr_assert_eq(ct_wait(runner), 128 + SIGKILL);
        int gone = 0;
        for (int i = 0; i < 100 && !gone; i++) {
            gone = ended(job);
            if (!gone)
                usleep(50000);
        }
        cr_assert(gone, "round %d: job %d still runs 5 s after its runner was killed", round,
                  (int)job);
    }
    ct_rmrf(dir);
}
