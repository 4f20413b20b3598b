/*
 * Fault injection through the stand-in solver (tests/standin/fake_solver.c):
 * jobs that crash (SIGSEGV), hang past the time limit (with a child process
 * of their own, which must die with them; one ignores SIGTERM and must get
 * SIGKILL after the grace period), exit 3, or report divergence are
 * each recorded in their class with their exit code or signal, message and
 * stderr tail, while every other job of the campaign completes with its
 * metrics and checksummed files; a job that fails once is retried and then
 * succeeds (and with retries: 0 it is not); a new solver version runs the done jobs again.
 *
 * Whom a failure is charged to: a crash that repeats (same signal at the
 * same step, or the same signal when the step is unknown) is not retried
 * again while one at a new step is; a solver killed with SIGKILL says so by
 * name, and so does exit 137.  Infrastructure failures -- a run directory
 * that cannot be created, a solver that cannot be started, a full disk --
 * use up no retries: the runner backs off, stops after three in a row with
 * a message naming the path, marks no job failed, and once the cause is
 * gone every job runs.
 */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/ct.h"
#include "util/sha256.h"

static int run_study(const char *dir, const char *file, char *out, size_t len)
{
    return ct_cascade(dir, NULL, out, len, "run", file, "--solver", ct_standin(), "--jobs", "2",
                      NULL);
}

/* Whether a process is gone (or a zombie nobody reaps), waiting up to 2 s. */
static int process_gone(int pid)
{
    for (int i = 0; i < 200; i++) {
        char path[64], stat[256] = "";
        snprintf(path, sizeof path, "/proc/%d/stat", pid);
        FILE *f = fopen(path, "r");
        if (!f)
            return 1;
        size_t n = fread(stat, 1, sizeof stat - 1, f);
        fclose(f);
        stat[n] = '\0';
        const char *p = strrchr(stat, ')');
        if (p && p[1] == ' ' && p[2] == 'Z')
            return 1;
        usleep(10000);
    }
    return 0;
}

Test(campaign_faults, each_outcome_in_its_class, .timeout = 60)
{
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "faults.yaml",
             "name: faults\n"
             "base: {fake: {action: ok}}\n"
             "sweep:\n"
             "  zip:\n"
             "    fake.action: [ok, crash, ok, hang, exit, ok, diverge, ok, hang]\n"
             "    fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9]\n"
             "    fake.ignore_term: [false, false, false, false, false, false, false, false,"
             " true]\n"
             "timeout: 1.5\n"
             "retries: 0\n");
    int rc = run_study(dir, "faults.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "a campaign with failed jobs exits 1 (got %d): %s", rc, out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 9);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 9, "retries: 0 means one attempt each");
    /* every good job completed with its metrics: x_squared = x^2 */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'x_squared' AND "
                            "value = (SELECT p.value * p.value FROM job_params p "
                            "WHERE p.job_id = results.job_id AND p.name = 'fake.x')"),
                 4);
    /* each fault in its class */
    const char *checks[][2] = {
        {"crash", "status = 'crashed' AND signal = 11 AND exit_code IS NULL AND "
                  "stderr_tail LIKE '%crashing now%'"},
        {"hang", "status = 'timeout' AND message LIKE '%after the limit of 1.5 s%'"},
        {"exit", "status = 'failed' AND exit_code = 3 AND message LIKE 'exit 3:%exiting with code 3%'"},
        {"diverge", "status = 'diverged' AND exit_code = 4 AND message LIKE '%non-finite energy%'"},
    };
    for (int i = 0; i < 4; i++) {
        char sql[512];
        snprintf(sql, sizeof sql,
                 "SELECT count(*) FROM runs r JOIN job_params p ON p.job_id = r.job_id "
                 "AND p.name = 'fake.action' WHERE p.value = '%s' AND %s",
                 checks[i][0], checks[i][1]);
        cr_assert_eq(ct_int(db, sql), i == 1 ? 2 : 1, "%s not recorded as expected", checks[i][0]);
    }
    /* SIGTERM ends the plain hang; the job that ignores it gets SIGKILL after
     * the 2 s grace period */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs r JOIN job_params p ON p.job_id = r.job_id "
                            "AND p.name = 'fake.ignore_term' WHERE r.status = 'timeout' AND ("
                            "(p.value = 0 AND r.signal = 15 AND r.wall_s < 3.0) OR "
                            "(p.value = 1 AND r.signal = 9 AND r.wall_s > 3.0))"),
                 2);
    /* the hung jobs' own children died with their process groups */
    for (int ignore = 0; ignore < 2; ignore++) {
        char run_dir[512], pidfile[600], sql[400];
        snprintf(sql, sizeof sql,
                 "SELECT r.run_dir FROM runs r JOIN job_params p ON p.job_id = r.job_id AND "
                 "p.name = 'fake.ignore_term' JOIN job_params q ON q.job_id = r.job_id AND "
                 "q.name = 'fake.action' WHERE q.value = 'hang' AND p.value = %d",
                 ignore);
        ct_text(db, sql, run_dir, sizeof run_dir);
        snprintf(pidfile, sizeof pidfile, "%s/grandchild.pid", run_dir);
        FILE *f = fopen(pidfile, "r");
        cr_assert_not_null(f);
        int gpid = 0;
        cr_assert_eq(fscanf(f, "%d", &gpid), 1);
        fclose(f);
        cr_assert(process_gone(gpid), "the hung job's child %d survived the timeout", gpid);
    }
    /* files with checksums: result.json of a done job hashes as recorded */
    char path[600], sha[80];
    ct_text(db, "SELECT path FROM artifacts a JOIN runs r ON r.id = a.run_id "
                "WHERE r.status = 'done' AND a.kind = 'result' LIMIT 1", path, sizeof path);
    ct_text(db, "SELECT sha256 FROM artifacts WHERE path = (SELECT path FROM artifacts a "
                "JOIN runs r ON r.id = a.run_id WHERE r.status = 'done' AND a.kind = 'result' "
                "LIMIT 1)", sha, sizeof sha);
    char hex[65];
    uint64_t bytes;
    cr_assert_eq(sha256_file_hex(path, hex, &bytes), 0);
    cr_assert_str_eq(hex, sha);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    /* running again changes nothing: done jobs stay done, failures are not retried */
    rc = run_study(dir, "faults.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 9);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_faults, retries_then_success, .timeout = 60)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write_flaky_study(dir);
    /* each job fails its first attempt (creating its flag file), then succeeds */
    int rc = run_study(dir, "flaky.yaml", out, sizeof out);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'failed' AND exit_code = 3 "
                            "AND attempt = 1"),
                 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND attempt = 2"), 2);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_faults, new_solver_version_reruns, .timeout = 60)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "v.yaml", "name: v\nbase: {fake: {x: 3}}\nsweep: {grid: {fake.y: [1, 2, 3]}}\n");
    cr_assert_eq(run_study(dir, "v.yaml", out, sizeof out), 0, "%s", out);
    cr_assert_eq(run_study(dir, "v.yaml", out, sizeof out), 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 3, "a second run repeated done jobs");
    sqlite3_close(db);
    const char *env[] = {"CASCADE_FAKE_VERSION=fake-2.0", NULL};
    cr_assert_eq(ct_cascade(dir, env, out, sizeof out, "run", "v.yaml", "--solver", ct_standin(),
                            NULL),
                 0, "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND "
                            "solver_version = 'fake-2.0'"),
                 3);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT solver_version) FROM run_metrics WHERE "
                            "metric = 'sum'"),
                 2, "both versions' metrics stay queryable");
    /* the results view shows the newest done run of each job */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'sum' AND "
                            "solver_version = 'fake-2.0'"),
                 3);
    sqlite3_close(db);
    /* retry --failed with nothing failed runs nothing; retry runs everything again */
    cr_assert_eq(ct_cascade(dir, env, out, sizeof out, "retry", "v", "--failed", "--solver",
                            ct_standin(), NULL),
                 0, "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 6);
    sqlite3_close(db);
    cr_assert_eq(ct_cascade(dir, env, out, sizeof out, "retry", "v", "--solver", ct_standin(), NULL),
                 0, "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 9);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE attempt = 3 AND status = 'done'"), 3);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_faults, repeated_crashes_are_deterministic, .timeout = 60)
{
    char dir[64], out[16384], text[1024];
    ct_mkdir(dir, sizeof dir);
    snprintf(text, sizeof text,
             "name: det\n"
             "base: {fake: {action: crash}}\n"
             "sweep:\n"
             "  zip:\n"
             "    fake.x: [1, 2, 3, 4]\n"
             "    fake.action: [crash, crash, crash, exit]\n"
             "    fake.signal: [11, 11, 6, 11]\n"
             "    fake.steps: [5, 5, 0, 0]\n"
             "    fake.counter: ['', '%s/counter', '', '']\n"
             "    fake.code: [3, 3, 3, 137]\n"
             "retries: 3\n",
             dir);
    ct_write(0, dir, "det.yaml", text);
    int rc = run_study(dir, "det.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    sqlite3 *db = ct_db(dir);
#define RUNS_OF(x, cond)                                                                           \
    "SELECT count(*) FROM runs r JOIN job_params p ON p.job_id = r.job_id AND p.name = 'fake.x' " \
    "WHERE p.value = " #x " AND " cond
    /* the same signal at the same step twice: no third attempt */
    cr_assert_eq(ct_int(db, RUNS_OF(1, "1")), 2);
    cr_assert_eq(ct_int(db, RUNS_OF(1, "attempt = 2 AND status = 'crashed' AND signal = 11 AND "
                                       "last_step = 5 AND failure_class = 'deterministic' AND "
                                       "message LIKE '%same signal at step 5 as attempt 1%'")),
                 1);
    /* a new step every time: retried as the study allows (1 + 3 attempts) */
    cr_assert_eq(ct_int(db, RUNS_OF(2, "status = 'crashed' AND failure_class = 'job'")), 4);
    cr_assert_eq(ct_int(db, RUNS_OF(2, "attempt = 4 AND last_step = 8")), 1);
    /* the step unknown (no thermo.csv): the same signal twice is enough */
    cr_assert_eq(ct_int(db, RUNS_OF(3, "1")), 2);
    cr_assert_eq(ct_int(db, RUNS_OF(3, "attempt = 2 AND last_step IS NULL AND "
                                       "failure_class = 'deterministic' AND message LIKE "
                                       "'crashed: killed by signal 6 (SIGABRT); deterministic: "
                                       "the same signal as attempt 1 (step unknown)%'")),
                 1);
    /* exit 137 from what looks like a launcher names the signal; a plain
     * failure, retried */
    cr_assert_eq(ct_int(db, RUNS_OF(4, "status = 'failed' AND exit_code = 137 AND "
                                       "message LIKE 'exit 137 (128 + 9:%signal 9 (SIGKILL))%'")),
                 4);
#undef RUNS_OF
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* Read a pid from a file, waiting up to 10 s for it. */
static int read_pid(const char *path)
{
    for (int i = 0; i < 1000; i++) {
        FILE *f = fopen(path, "r");
        int pid = 0;
        if (f) {
            int got = fscanf(f, "%d", &pid);
            fclose(f);
            if (got == 1 && pid > 0)
                return pid;
        }
        usleep(10000);
    }
    cr_assert_fail("no pid in %s after 10 s", path);
    return 0;
}

Test(campaign_faults, sigkill_of_a_solver_is_named, .timeout = 60)
{
    char dir[64], text[512];
    ct_mkdir(dir, sizeof dir);
    snprintf(text, sizeof text,
             "name: killed\nbase: {fake: {action: slow_once, seconds: 30, flag: %s/flag}}\n"
             "retries: 0\n",
             dir);
    ct_write(0, dir, "killed.yaml", text);
    const char *argv[] = {ct_cascade_bin(), "run", "killed.yaml", "--solver", ct_standin(), NULL};
    pid_t runner = ct_spawn(dir, NULL, argv, "run.log");
    char pidfile[128];
    snprintf(pidfile, sizeof pidfile, "%s/runs/killed", dir);
    /* the one job's attempt directory: runs/killed/<key>/attempt-1 */
    char path[512] = "";
    for (int i = 0; i < 1000 && !path[0]; i++) {
        char cmd[256];
        snprintf(cmd, sizeof cmd, "ls -d %s/*/attempt-1 2>/dev/null", pidfile);
        FILE *p = popen(cmd, "r");
        if (p) {
            if (fgets(path, sizeof path, p))
                path[strcspn(path, "\n")] = '\0';
            pclose(p);
        }
        if (!path[0])
            usleep(10000);
    }
    cr_assert(path[0], "no attempt directory");
    strncat(path, "/solver.pid", sizeof path - strlen(path) - 1);
    int solver = read_pid(path);
    cr_assert_eq(kill(solver, SIGKILL), 0);
    cr_assert_eq(ct_wait(runner), 1, "the job failed: exit 1 (see %s/run.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'crashed' AND signal = 9 "
                            "AND failure_class = 'job' AND "
                            "message = 'crashed: killed by signal 9 (SIGKILL)'"),
                 1);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* What a stop for infrastructure failures leaves: n attempts, all recorded
 * as the infrastructure's (cancelled, message LIKE like), no job failed,
 * and a backoff between the first and the last (0.5 s, then 1 s, after
 * failures one by one; 1 s after two at once -- then one job probes). */
static void check_infra_stop(const char *dir, const char *out, int n, const char *like)
{
    cr_assert_not_null(strstr(out, "stopped after 3 infrastructure failures in a row"), "%s", out);
    sqlite3 *db = ct_db(dir);
    char sql[512];
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), n);
    snprintf(sql, sizeof sql,
             "SELECT count(*) FROM runs WHERE status = 'cancelled' AND "
             "failure_class = 'infrastructure' AND message LIKE '%s'",
             like);
    cr_assert_eq(ct_int(db, sql), n, "%s", out);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state IN ('failed', 'crashed', "
                            "'timeout', 'diverged')"),
                 0, "a job was marked failed");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE failure_class IS NOT "
                            "'infrastructure'"),
                 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    double span = ct_real(db, "SELECT (julianday(max(finished)) - julianday(min(started))) * "
                              "86400 FROM runs");
    cr_assert_geq(span, 0.95, "no backoff: %d failures in %.2f s", n, span);
    sqlite3_close(db);
}

Test(campaign_faults, unwritable_run_directory_stops_without_charging_jobs, .timeout = 60)
{
    char dir[64], out[16384], runs[128], in_the_way[160];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "infra.yaml",
             "name: infra\n"
             "base: {fake: {action: ok}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8]}}\n"
             "retries: 0\n");
    /* runs/infra is a file: no run directory can be made under it (a
     * permission would not stop root; a file in the way stops anyone) */
    snprintf(runs, sizeof runs, "%s/runs", dir);
    cr_assert_eq(mkdir(runs, 0755), 0);
    snprintf(in_the_way, sizeof in_the_way, "%s/infra", runs);
    ct_write(1, runs, "infra", "in the way\n");
    int rc = run_study(dir, "infra.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    char want[256];
    snprintf(want, sizeof want, "cannot create directory %s: a file of that name is in the way",
             in_the_way);
    cr_assert_not_null(strstr(out, want), "the stop does not name %s: %s", in_the_way, out);
    check_infra_stop(dir, out, 3, "could not start: cannot create directory %infra: a file%");
    /* the cause gone, every job runs: retries: 0, yet none was used up */
    cr_assert_eq(unlink(in_the_way), 0);
    rc = run_study(dir, "infra.yaml", out, sizeof out);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 8);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_faults, solver_start_and_disk_failures_are_infrastructure, .timeout = 60)
{
    /* exit 127: the solver could not be started (as when exec fails) */
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "nostart.yaml",
             "name: nostart\n"
             "base: {fake: {action: exit, code: 127}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n");
    int rc = run_study(dir, "nostart.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    check_infra_stop(dir, out, 3, "could not start the solver: %");
    ct_rmrf(dir);
    /* a solver that ran out of disk: the machine's trouble, named with the
     * attempt's directory */
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "full.yaml",
             "name: full\n"
             "base: {fake: {action: exit, code: 1,"
             " message: 'error: result.json: No space left on device'}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n");
    rc = run_study(dir, "full.yaml", out, sizeof out);
    cr_assert_eq(rc, 1, "%s", out);
    check_infra_stop(dir, out, 3, "disk trouble: the solver reported ''No space left on "
                                  "device'' in %/runs/full/%/attempt-1 (exit 1: %");
    ct_rmrf(dir);
}
