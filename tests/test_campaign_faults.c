/*
 * Fault injection through the stand-in solver (tests/standin/fake_solver.c):
 * jobs that crash (SIGSEGV), hang past the time limit (with a child process
 * of their own, which must die with them; one ignores SIGTERM and must get
 * SIGKILL after the grace period), exit 3, or report divergence are
 * each recorded in their class with their exit code or signal, message and
 * stderr tail, while every other job of the campaign completes with its
 * metrics and checksummed files; a job that fails once is retried and then
 * succeeds (and with retries: 0 it is not); a new solver version runs the done jobs again.
 */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
    char dir[64], out[8192], text[1024];
    ct_mkdir(dir, sizeof dir);
    snprintf(text, sizeof text,
             "name: flaky\n"
             "base: {fake: {action: fail_once}}\n"
             "sweep: {zip: {fake.x: [1, 2], fake.flag: [%s/flag1, %s/flag2]}}\n"
             "retries: 1\n",
             dir, dir);
    ct_write(0, dir, "flaky.yaml", text);
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
