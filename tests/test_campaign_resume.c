/*
 * Stopping and resuming: SIGKILL the runner in the middle of a campaign and
 * run it again -- every job ends with exactly one done run, the runs the
 * killed runner left 'running' are closed as cancelled, no lease is left and
 * PRAGMA integrity_check says ok.  SIGINT: the runner starts nothing new,
 * lets the running jobs finish, records them and exits 130; the next run
 * does the rest.
 */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "helpers/ct.h"

#define NJOBS 10

static const char *study =
    "name: slow\n"
    "base: {fake: {action: sleep, seconds: 0.25}}\n"
    "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]}}\n";

/* Wait until the database shows at least n runs with the given status. */
static void wait_for_runs(const char *dir, const char *status, int n)
{
    char path[128], sql[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    snprintf(sql, sizeof sql, "SELECT count(*) FROM runs WHERE status = '%s'", status);
    for (int i = 0; i < 1000; i++) {
        if (access(path, F_OK) == 0) {
            sqlite3 *db = ct_db(dir);
            sqlite3_stmt *st;
            long long got = -1;
            if (sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK) {
                if (sqlite3_step(st) == SQLITE_ROW)
                    got = sqlite3_column_int64(st, 0);
                sqlite3_finalize(st);
            }
            sqlite3_close(db);
            if (got >= n)
                return;
        }
        usleep(10000);
    }
    cr_assert_fail("no %d '%s' runs after 10 s", n, status);
}

static void check_exactly_once(const char *dir)
{
    sqlite3 *db = ct_db(dir);
    char ok[32];
    ct_text(db, "PRAGMA integrity_check", ok, sizeof ok);
    cr_assert_str_eq(ok, "ok");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM pragma_foreign_key_check"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), NJOBS);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), NJOBS);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM (SELECT job_id FROM runs WHERE status = 'done' "
                            "GROUP BY job_id HAVING count(*) = 1)"),
                 NJOBS, "a job has no done run or more than one");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'running'"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'x_squared'"), NJOBS);
    sqlite3_close(db);
}

Test(campaign_resume, sigkill_then_resume, .timeout = 60)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "slow.yaml", study);
    const char *argv[] = {ct_cascade_bin(), "run", "slow.yaml", "--solver", ct_standin(), "--jobs",
                          "2", NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "first.log");
    wait_for_runs(dir, "done", 3);
    kill(pid, SIGKILL);
    cr_assert_eq(ct_wait(pid), 128 + SIGKILL);
    sqlite3 *db = ct_db(dir);
    long long done_before = ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'");
    long long left_running = ct_int(db, "SELECT count(*) FROM runs WHERE status = 'running'");
    sqlite3_close(db);
    cr_assert_lt(done_before, NJOBS, "the runner finished before it was killed");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "slow.yaml", "--solver", ct_standin(),
                        "--jobs", "2", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "earlier"), "%s", out);
    check_exactly_once(dir);
    db = ct_db(dir);
    /* the runs the killed runner held are closed, with the reason */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled' AND "
                            "message LIKE '%is gone%'"),
                 left_running);
    /* the second runner ran exactly the jobs the first had not finished */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND runner <> "
                            "(SELECT runner FROM runs ORDER BY id LIMIT 1)"),
                 NJOBS - done_before);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_resume, sigint_finishes_running_jobs, .timeout = 60)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "slow.yaml", study);
    const char *argv[] = {ct_cascade_bin(), "run", "slow.yaml", "--solver", ct_standin(), "--jobs",
                          "2", NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "first.log");
    wait_for_runs(dir, "done", 2);
    kill(pid, SIGINT);
    cr_assert_eq(ct_wait(pid), 130);
    sqlite3 *db = ct_db(dir);
    /* nothing left running or cancelled: the running jobs were let finish */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status IN ('running', 'cancelled')"),
                 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    long long done = ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'");
    sqlite3_close(db);
    cr_assert_lt(done, NJOBS, "the runner did not stop starting jobs");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "slow.yaml", "--solver", ct_standin(),
                        "--jobs", "2", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    check_exactly_once(dir);
    ct_rmrf(dir);
}

Test(campaign_resume, second_sigint_cancels, .timeout = 60)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "hang.yaml",
             "name: hang\nbase: {fake: {action: hang}}\nsweep: {grid: {fake.x: [1, 2, 3]}}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "hang.yaml", "--solver", ct_standin(), "--jobs",
                          "2", NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "run.log");
    wait_for_runs(dir, "running", 2);
    usleep(100000);
    kill(pid, SIGINT);
    usleep(100000);
    kill(pid, SIGINT);
    cr_assert_eq(ct_wait(pid), 130);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled'"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 2, "a third job was started");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}
