/*
 * Two `cascade run` processes on one database and one study at the same
 * time: leases taken in BEGIN IMMEDIATE transactions mean no job is ever run
 * twice -- each job has exactly one run, all done, and both runners return
 * when the study is complete.  Both do work (the jobs are shared out).
 * Heartbeats renew the leases, so a job running longer than the lease is
 * not taken over by the other runner.  A runner frozen (SIGSTOP) past its
 * lease loses the job to a second runner; its solver, still running, writes
 * only its own attempt directory, so the files the second runner recorded
 * keep their checksums; woken up (SIGCONT), the first runner stops its
 * solver if it still runs, records nothing and exits cleanly.
 */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "helpers/ct.h"
#include "util/sha256.h"

Test(campaign_concurrent, two_runners_never_run_a_job_twice, .timeout = 90)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "shared.yaml",
             "name: shared\n"
             "base: {fake: {action: sleep, seconds: 0.05}}\n"
             "sweep:\n"
             "  grid:\n"
             "    fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\n"
             "    fake.y: [1, 2, 3]\n");
    const char *argv[] = {ct_cascade_bin(), "run", "shared.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 36);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 36, "some job was run twice");
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT job_id) FROM runs WHERE status = 'done'"), 36);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT runner) FROM runs"), 2,
                 "one runner did all the work: the test shows nothing");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_concurrent, heartbeats_keep_long_jobs, .timeout = 90)
{
    /* jobs of 3.2 s under 2 s leases: only the heartbeats (every third of the
     * lease) stop the second runner from taking over jobs the first still
     * runs (2 s leaves room for a heavily loaded machine) */
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "long.yaml",
             "name: long\n"
             "base: {fake: {action: sleep, seconds: 3.2}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "long.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--lease", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 4, "a running job was taken over");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 4);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_concurrent, two_runners_share_a_preparation_job, .timeout = 90)
{
    /* one runner takes the preparation job; the other waits for it (it is
     * leased elsewhere) and then takes its share of the jobs that read it */
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "prep.yaml",
             "name: prep\n"
             "base: {fake: {action: sleep, seconds: 0.1, read: '${prep.p}/state.txt'}}\n"
             "prep:\n"
             "  p: {base: {fake: {action: sleep, seconds: 0.8, write: state.txt}}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}}\n");
    const char *argv[] = {ct_cascade_bin(), "run", "prep.yaml", "--solver", ct_standin(),
                          "--jobs", "2", "--quiet", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    pid_t b = ct_spawn(dir, NULL, argv, "b.log");
    cr_assert_eq(ct_wait(a), 0, "runner a failed (see %s/a.log)", dir);
    cr_assert_eq(ct_wait(b), 0, "runner b failed (see %s/b.log)", dir);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 13, "some job was run twice");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 13);
    /* every sweep job read the file the preparation job wrote, after it finished */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'read_bytes' AND "
                            "value > 0"),
                 12);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs s JOIN jobs j ON j.id = s.job_id, "
                            "runs p JOIN jobs pj ON pj.id = p.job_id AND pj.kind = 'prep' "
                            "WHERE j.kind = 'sweep' AND s.started < p.finished"),
                 0, "a job started before the preparation job it reads had finished");
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* Wait up to `seconds` for a file to exist. */
static int wait_for_file(const char *path, double seconds)
{
    for (int i = 0; i < (int)(seconds * 100); i++) {
        if (access(path, F_OK) == 0)
            return 1;
        usleep(10000);
    }
    return 0;
}

/* Wait until the database shows a 'running' run (the claim is committed). */
static void wait_for_running(const char *dir)
{
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    for (int i = 0; i < 1000; i++) {
        if (access(path, F_OK) == 0) {
            sqlite3 *db = ct_db(dir);
            sqlite3_stmt *st;
            long long n = 0;
            if (sqlite3_prepare_v2(db, "SELECT count(*) FROM runs WHERE status = 'running'", -1,
                                   &st, NULL) == SQLITE_OK) {
                if (sqlite3_step(st) == SQLITE_ROW)
                    n = sqlite3_column_int64(st, 0);
                sqlite3_finalize(st);
            }
            sqlite3_close(db);
            if (n > 0)
                return;
        }
        usleep(10000);
    }
    cr_assert_fail("no running job after 10 s");
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One job whose first attempt sleeps `seconds` (the stand-in's slow_once)
 * and whose later attempts finish at once.  Runner A (1 s lease) starts it
 * and is frozen; runner B takes the job over when A's lease has expired and
 * runs it to the end.  Returns A's pid (stopped); the job's directory in
 * job_dir. */
static pid_t freeze_first_runner(const char *dir, double seconds, char *job_dir, size_t len)
{
    char study[1024], out[8192];
    snprintf(study, sizeof study,
             "name: stale\n"
             "base: {fake: {action: slow_once, seconds: %g, flag: %s/flag, x: 2}}\n",
             seconds, dir);
    ct_write(0, dir, "stale.yaml", study);
    const char *argv[] = {ct_cascade_bin(), "run", "stale.yaml", "--solver", ct_standin(),
                          "--lease", "1", NULL};
    pid_t a = ct_spawn(dir, NULL, argv, "a.log");
    wait_for_running(dir);
    sqlite3 *db = ct_db(dir);
    char run_dir[512];
    ct_text(db, "SELECT run_dir FROM runs WHERE attempt = 1", run_dir, sizeof run_dir);
    sqlite3_close(db);
    cr_assert(strlen(run_dir) > 10 && strcmp(run_dir + strlen(run_dir) - 10, "/attempt-1") == 0,
              "run_dir %s is not an attempt directory", run_dir);
    snprintf(job_dir, len, "%.*s", (int)(strlen(run_dir) - 10), run_dir);
    char pidfile[600];
    snprintf(pidfile, sizeof pidfile, "%s/solver.pid", run_dir);
    cr_assert(wait_for_file(pidfile, 10), "the first attempt's solver did not start");
    cr_assert_eq(kill(a, SIGSTOP), 0);
    usleep(1500000);   /* A's lease (1 s) expires; it cannot renew it */
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "stale.yaml", "--solver", ct_standin(),
                        NULL);
    cr_assert_eq(rc, 0, "runner B: %s", out);
    return a;
}

/* What both tests expect of the database and the files: B's attempt 2 is
 * the recorded one, its files hash as recorded, A recorded nothing. */
static void check_b_recorded(const char *dir, const char *job_dir)
{
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 2);
    /* attempt 1 as B closed it when it took the lease over: A wrote nothing
     * after (no status, no files, no metrics) */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE attempt = 1 AND status = 'cancelled' "
                            "AND message LIKE '%lease%expired%'"),
                 1);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM artifacts a JOIN runs r ON r.id = a.run_id "
                            "WHERE r.attempt = 1"),
                 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM metrics m JOIN runs r ON r.id = m.run_id "
                            "WHERE r.attempt = 1"),
                 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE attempt = 2 AND status = 'done' "
                            "AND runner <> (SELECT runner FROM runs WHERE attempt = 1)"),
                 1);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    /* every file recorded for the done run is in attempt-2 and hashes as recorded */
    sqlite3_stmt *st;
    cr_assert_eq(sqlite3_prepare_v2(db, "SELECT a.path, a.sha256, a.kind FROM artifacts a JOIN "
                                        "runs r ON r.id = a.run_id WHERE r.status = 'done'",
                                    -1, &st, NULL),
                 SQLITE_OK);
    int n = 0, results = 0;
    char want_dir[600];
    snprintf(want_dir, sizeof want_dir, "%s/attempt-2/", job_dir);
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *path = (const char *)sqlite3_column_text(st, 0);
        const char *sha = (const char *)sqlite3_column_text(st, 1);
        cr_assert(strncmp(path, want_dir, strlen(want_dir)) == 0, "%s is not in %s", path,
                  want_dir);
        char hex[65];
        uint64_t bytes;
        cr_assert_eq(sha256_file_hex(path, hex, &bytes), 0, "%s", path);
        cr_assert_str_eq(hex, sha, "%s changed after it was recorded", path);
        results += strcmp((const char *)sqlite3_column_text(st, 2), "result") == 0;
        n++;
    }
    sqlite3_finalize(st);
    cr_assert_geq(n, 4, "case, result, stdout, stderr at least");
    cr_assert_eq(results, 1);
    sqlite3_close(db);
    /* the job's `current` link names the recorded attempt */
    char link[600], target[64] = "";
    snprintf(link, sizeof link, "%s/current", job_dir);
    ssize_t tn = readlink(link, target, sizeof target - 1);
    cr_assert_gt(tn, 0, "no %s", link);
    target[tn] = '\0';
    cr_assert_str_eq(target, "attempt-2");
}

Test(campaign_concurrent, frozen_runner_cannot_overwrite_the_new_attempt, .timeout = 90)
{
    /* A's solver outlives the takeover and writes its result.json while A
     * is still frozen: into its own attempt directory */
    char dir[64], job_dir[512], path[600];
    ct_mkdir(dir, sizeof dir);
    pid_t a = freeze_first_runner(dir, 3.0, job_dir, sizeof job_dir);
    snprintf(path, sizeof path, "%s/attempt-1/result.json", job_dir);
    cr_assert(wait_for_file(path, 15), "the first attempt's solver never finished");
    check_b_recorded(dir, job_dir);
    /* A wakes up to a finished solver whose job is no longer its own */
    cr_assert_eq(kill(a, SIGCONT), 0);
    cr_assert_eq(ct_wait(a), 0, "runner A did not exit cleanly (see %s/a.log)", dir);
    check_b_recorded(dir, job_dir);
    ct_rmrf(dir);
}

Test(campaign_concurrent, woken_runner_stops_its_solver_and_records_nothing, .timeout = 90)
{
    /* A's solver would sleep 60 s: woken up, A finds its lease gone, stops
     * the solver at once and exits cleanly without recording */
    char dir[64], job_dir[512], path[600];
    ct_mkdir(dir, sizeof dir);
    pid_t a = freeze_first_runner(dir, 60.0, job_dir, sizeof job_dir);
    snprintf(path, sizeof path, "%s/attempt-1/solver.pid", job_dir);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f);
    int solver = 0;
    cr_assert_eq(fscanf(f, "%d", &solver), 1);
    fclose(f);
    cr_assert_eq(kill(solver, 0), 0, "the first attempt's solver should still run");
    double t0 = now_s();
    cr_assert_eq(kill(a, SIGCONT), 0);
    cr_assert_eq(ct_wait(a), 0, "runner A did not exit cleanly (see %s/a.log)", dir);
    double waited = now_s() - t0;
    /* A waits for its slots to empty: an exit this soon means it stopped
     * the solver itself rather than waiting the 60 s out */
    cr_assert_lt(waited, 15.0, "runner A took %.1f s: it did not stop its solver", waited);
    cr_assert_neq(kill(solver, 0), 0, "the first attempt's solver still runs");
    snprintf(path, sizeof path, "%s/attempt-1/result.json", job_dir);
    cr_assert_neq(access(path, F_OK), 0, "the stopped solver wrote a result");
    check_b_recorded(dir, job_dir);
    char log[128];
    snprintf(log, sizeof log, "%s/a.log", dir);
    f = fopen(log, "r");
    cr_assert_not_null(f);
    char text[16384];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    cr_assert_not_null(strstr(text, "another runner took the job"), "%s", text);
    ct_rmrf(dir);
}
