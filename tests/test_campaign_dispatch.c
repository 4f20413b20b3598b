/*
 * What the runner's per-job path leaves behind (campaign/launch.c,
 * store.c, runner.c; docs/campaign.md "Running"), checked from outside:
 *
 *   - each attempt has its own directory with case.yaml, stdout and stderr,
 *     and <job>/current names the latest recorded attempt: created in place
 *     for the first, replaced for a retry, with no temporary name left;
 *   - every recorded file's size and SHA-256 (computed here with
 *     sha256sum, not with the runner's code) match the file on disk, empty
 *     files included;
 *   - an attempt directory that an earlier database left under runs/ is
 *     emptied before the attempt runs, and case.yaml is the new one;
 *   - a done job's outcome, committed with the next job's claim (one
 *     transaction per job), is in the database when the run ends, for every
 *     job, also with several slots;
 *   - the job claimed ahead while every slot is busy (its run 'running',
 *     its directory and case.yaml written, no process yet): a runner killed
 *     then leaves it to the next runner, which closes that attempt as
 *     cancelled ("is gone") and runs the job; a runner stopped by SIGINT
 *     undoes the claim (no run row, no lease, no directory, the job
 *     'pending' again in jobs and job_counts).
 */
#include <criterion/criterion.h>
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/ct.h"

static int run_study(const char *dir, const char *file, const char *jobs, char *out, size_t len)
{
    return ct_cascade(dir, NULL, out, len, "run", file, "--solver", ct_standin(), "--jobs", jobs,
                      NULL);
}

/* sha256sum's digest of path into hex (65 bytes). */
static void sha256sum(const char *path, char *hex)
{
    char cmd[4096 + 32];
    snprintf(cmd, sizeof cmd, "sha256sum '%s'", path);
    FILE *p = popen(cmd, "r");
    cr_assert(p, "popen %s", cmd);
    cr_assert_eq(fscanf(p, "%64s", hex), 1, "no digest from %s", cmd);
    pclose(p);
}

/* Every artifact row of the database matches its file on disk. */
static void artifacts_match_disk(const char *dir, long want_rows)
{
    char dbpath[256];
    snprintf(dbpath, sizeof dbpath, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    cr_assert_eq(sqlite3_open_v2(dbpath, &db, SQLITE_OPEN_READONLY, NULL), SQLITE_OK);
    sqlite3_stmt *s = NULL;
    cr_assert_eq(sqlite3_prepare_v2(db, "SELECT path, bytes, sha256 FROM artifacts", -1, &s, NULL),
                 SQLITE_OK);
    long rows = 0, empty = 0;
    while (sqlite3_step(s) == SQLITE_ROW) {
        const char *path = (const char *)sqlite3_column_text(s, 0);
        long long bytes = sqlite3_column_int64(s, 1);
        const char *sha = (const char *)sqlite3_column_text(s, 2);
        struct stat sb;
        cr_assert_eq(stat(path, &sb), 0, "recorded file %s is not on disk", path);
        cr_assert_eq((long long)sb.st_size, bytes, "%s: %lld bytes on disk, %lld recorded", path,
                     (long long)sb.st_size, bytes);
        char hex[65];
        sha256sum(path, hex);
        cr_assert_str_eq(sha, hex, "%s: recorded sha256 %s, sha256sum says %s", path, sha, hex);
        empty += bytes == 0;
        rows++;
    }
    sqlite3_finalize(s);
    sqlite3_close(db);
    cr_assert_eq(rows, want_rows, "%ld artifact rows, expected %ld", rows, want_rows);
    cr_assert_gt(empty, 0, "no empty file among the artifacts (stdout of the stand-in is empty)");
}

/* The names in dir, sorted and joined with ' ' (into out). */
static void listing(const char *dir, char *out, size_t len)
{
    struct dirent **names = NULL;
    int n = scandir(dir, &names, NULL, alphasort);
    cr_assert_geq(n, 0, "cannot list %s", dir);
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        if (names[i]->d_name[0] != '.') {
            size_t used = strlen(out);
            snprintf(out + used, len - used, "%s%s", used ? " " : "", names[i]->d_name);
        }
        free(names[i]);
    }
    free(names);
}

/* The one job directory of study `name` under dir/runs (into out). */
static void job_dir_of(const char *dir, const char *name, const char *key, char *out, size_t len)
{
    snprintf(out, len, "%s/runs/%s/%s", dir, name, key);
}

Test(campaign_dispatch, attempt_layout_and_current_link_after_a_retry, .timeout = 120)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write_flaky_study(dir);
    cr_assert_eq(run_study(dir, "flaky.yaml", "1", out, sizeof out), 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'failed' AND attempt = 1"),
                 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND attempt = 2"), 2);
    sqlite3_stmt *s = NULL;
    cr_assert_eq(sqlite3_prepare_v2(db, "SELECT key FROM jobs ORDER BY key", -1, &s, NULL),
                 SQLITE_OK);
    int jobs = 0;
    while (sqlite3_step(s) == SQLITE_ROW) {
        char job[512], path[1024], names[1024], target[64];
        job_dir_of(dir, "flaky", (const char *)sqlite3_column_text(s, 0), job, sizeof job);
        /* the job directory: the two attempts and the link, nothing else */
        listing(job, names, sizeof names);
        cr_assert_str_eq(names, "attempt-1 attempt-2 current", "%s holds: %s", job, names);
        snprintf(path, sizeof path, "%s/current", job);
        ssize_t n = readlink(path, target, sizeof target - 1);
        cr_assert_gt(n, 0, "%s is not a symlink", path);
        target[n] = '\0';
        cr_assert_str_eq(target, "attempt-2", "current names %s", target);
        /* attempt 1 failed (exit 3: no result.json), attempt 2 succeeded */
        snprintf(path, sizeof path, "%s/attempt-1", job);
        listing(path, names, sizeof names);
        cr_assert_str_eq(names, "case.yaml stderr stdout", "%s holds: %s", path, names);
        snprintf(path, sizeof path, "%s/attempt-2", job);
        listing(path, names, sizeof names);
        cr_assert_str_eq(names, "case.yaml result.json stderr stdout", "%s holds: %s", path,
                         names);
        jobs++;
    }
    sqlite3_finalize(s);
    sqlite3_close(db);
    cr_assert_eq(jobs, 2);
    /* 2 jobs x (3 files of the failed attempt + 4 of the done one) */
    artifacts_match_disk(dir, 14);
    ct_rmrf(dir);
}

Test(campaign_dispatch, an_attempt_directory_of_an_earlier_database_is_emptied, .timeout = 120)
{
    char dir[64], out[8192];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "one.yaml", "name: one\nbase: {fake: {action: ok, x: 2}}\n");
    cr_assert_eq(run_study(dir, "one.yaml", "1", out, sizeof out), 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    char run_dir[1024];
    ct_text(db, "SELECT run_dir FROM runs", run_dir, sizeof run_dir);
    sqlite3_close(db);
    /* a new database: attempt 1 again, in the directory the old one used */
    char path[1200];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    cr_assert_eq(unlink(path), 0);
    snprintf(path, sizeof path, "%s/cascade.db-wal", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/cascade.db-shm", dir);
    unlink(path);
    ct_write(1, run_dir, "old.h5", "left by the earlier database\n");
    ct_write(2, run_dir, "case.yaml", "stale: true\n");
    cr_assert_eq(run_study(dir, "one.yaml", "1", out, sizeof out), 0, "%s", out);
    char names[1024];
    listing(run_dir, names, sizeof names);
    cr_assert_str_eq(names, "case.yaml result.json stderr stdout", "%s holds: %s", run_dir, names);
    snprintf(path, sizeof path, "%s/case.yaml", run_dir);
    FILE *f = fopen(path, "r");
    cr_assert(f);
    char first[256] = "";
    cr_assert(fgets(first, sizeof first, f));
    fclose(f);
    cr_assert(strncmp(first, "# job ", 6) == 0, "case.yaml was not rewritten: %s", first);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 1);
    sqlite3_close(db);
    artifacts_match_disk(dir, 4);
    ct_rmrf(dir);
}

/* Each done job's outcome is committed with the next claim or, for the
 * last ones, before the runner waits or ends: all of them are recorded,
 * with their metrics, with one slot and with three. */
Test(campaign_dispatch, every_deferred_outcome_is_committed, .timeout = 180)
{
    const char *slots[] = {"1", "3"};
    for (size_t k = 0; k < sizeof slots / sizeof slots[0]; k++) {
        char dir[64], out[16384];
        ct_mkdir(dir, sizeof dir);
        ct_write(0, dir, "many.yaml",
                 "name: many\nbase: {fake: {action: ok}}\n"
                 "sweep: {grid: {fake.x: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}}\n");
        cr_assert_eq(run_study(dir, "many.yaml", slots[k], out, sizeof out), 0, "%s", out);
        cr_assert(strstr(out, "12 done (0 earlier), 0 failed"), "%s", out);
        sqlite3 *db = ct_db(dir);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 12,
                     "--jobs %s", slots[k]);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 12, "--jobs %s", slots[k]);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0, "--jobs %s", slots[k]);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 12);
        /* x_squared = x^2 of each job: sum over x = 1..12 is 650 */
        cr_assert_float_eq(ct_real(db, "SELECT sum(value) FROM metrics WHERE name = 'x_squared'"),
                           650.0, 1e-9, "--jobs %s", slots[k]);
        cr_assert_eq(ct_int(db, "SELECT n FROM job_counts WHERE state = 'done'"), 12);
        sqlite3_close(db);
        artifacts_match_disk(dir, 48);
        ct_rmrf(dir);
    }
}

/* --- the job claimed ahead ------------------------------------------------ */

/* Three jobs, one slot: the first sleeps `seconds` (it creates the flag;
 * the others, finding it, do not sleep). */
static void write_slow_first(const char *dir, double seconds)
{
    char text[512];
    snprintf(text, sizeof text,
             "name: ahead\nbase: {fake: {action: slow_once, seconds: %g, flag: %s/flag}}\n"
             "sweep: {grid: {fake.x: [1, 2, 3]}}\n",
             seconds, dir);
    ct_write(0, dir, "ahead.yaml", text);
}

static long long count_now(const char *dir, const char *sql)
{
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    if (access(path, F_OK) != 0)
        return -1;
    sqlite3 *db = NULL;
    long long n = -1;
    sqlite3_stmt *st = NULL;
    if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK &&
        sqlite3_prepare_v2(db, sql, -1, &st, NULL) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
        n = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(db);
    return n;
}

/* Start the runner (one slot) and wait until the first job runs and the
 * second is claimed ahead: two 'running' runs, the second's directory
 * holding case.yaml and nothing else (its process not started).  Returns
 * the runner's pid; the second attempt's directory into ahead_dir. */
static pid_t run_until_claimed_ahead(const char *dir, char *ahead_dir, size_t len)
{
    const char *argv[] = {ct_cascade_bin(), "run", "ahead.yaml", "--solver", ct_standin(), "--jobs",
                          "1", NULL};
    pid_t pid = ct_spawn(dir, NULL, argv, "first.log");
    long long n = -1;
    for (int i = 0; i < 2000 && n < 2; i++) {
        n = count_now(dir, "SELECT count(*) FROM runs WHERE status = 'running'");
        if (n < 2)
            usleep(10000);
    }
    cr_assert_eq(n, 2, "no job was claimed ahead within 20 s (runs 'running': %lld)", n);
    sqlite3 *db = ct_db(dir);
    ct_text(db, "SELECT run_dir FROM runs ORDER BY id LIMIT 1 OFFSET 1", ahead_dir, len);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 2);
    sqlite3_close(db);
    /* the claim is committed before its directory is written (runner.c
     * claim_entry): wait for the directory, not only for the row */
    char names[512] = "";
    struct stat sb;
    for (int i = 0; i < 2000 && stat(ahead_dir, &sb) != 0; i++)
        usleep(10000);
    for (int i = 0; i < 2000; i++) {
        listing(ahead_dir, names, sizeof names);
        if (names[0])
            break;
        usleep(10000);
    }
    cr_assert_str_eq(names, "case.yaml", "the job claimed ahead was started: %s holds %s",
                     ahead_dir, names);
    return pid;
}

Test(campaign_dispatch, a_killed_runner_leaves_the_job_claimed_ahead_to_the_next, .timeout = 120)
{
    char dir[64], out[16384], ahead[4096];
    ct_mkdir(dir, sizeof dir);
    write_slow_first(dir, 30);
    pid_t pid = run_until_claimed_ahead(dir, ahead, sizeof ahead);
    cr_assert_eq(kill(pid, SIGKILL), 0);
    cr_assert_eq(ct_wait(pid), 128 + SIGKILL);
    /* the first job's solver dies with the runner; the next runner reaps
     * both runs (its lease is the dead runner's) and runs all three jobs */
    cr_assert_eq(run_study(dir, "ahead.yaml", "1", out, sizeof out), 0, "%s", out);
    cr_assert(strstr(out, "3 done (0 earlier), 0 failed"), "%s", out);
    sqlite3 *db = ct_db(dir);
    char sql[4096 + 256];
    snprintf(sql, sizeof sql,
             "SELECT count(*) FROM runs WHERE run_dir = '%s' AND status = 'cancelled' "
             "AND failure_class = 'infrastructure' AND message LIKE '%%is gone%%'",
             ahead);
    cr_assert_eq(ct_int(db, sql), 1, "the attempt claimed ahead was not closed as cancelled");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled'"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM (SELECT job_id FROM runs WHERE status = 'done' "
                            "GROUP BY job_id HAVING count(*) = 1)"),
                 3, "a job has no done run or more than one");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'running'"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    cr_assert_eq(ct_int(db, "SELECT n FROM job_counts WHERE state = 'done'"), 3);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_dispatch, sigint_undoes_the_claim_ahead, .timeout = 120)
{
    char dir[64], out[16384], ahead[4096];
    ct_mkdir(dir, sizeof dir);
    write_slow_first(dir, 5);
    pid_t pid = run_until_claimed_ahead(dir, ahead, sizeof ahead);
    cr_assert_eq(kill(pid, SIGINT), 0);
    cr_assert_eq(ct_wait(pid), 130);
    sqlite3 *db = ct_db(dir);
    /* the running job was let finish; the one claimed ahead is as if never
     * claimed, and so is the third */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 1);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done'"), 1);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'pending' AND "
                            "last_run_id IS NULL AND solver IS NULL"),
                 2);
    cr_assert_eq(ct_int(db, "SELECT n FROM job_counts WHERE state = 'pending'"), 2);
    cr_assert_eq(ct_int(db, "SELECT coalesce(sum(n), 0) FROM job_counts WHERE state = 'running'"),
                 0);
    sqlite3_close(db);
    struct stat sb;
    cr_assert_neq(stat(ahead, &sb), 0, "%s (claimed ahead, never started) is still there", ahead);
    /* the next runner runs the other two, their first attempts */
    cr_assert_eq(run_study(dir, "ahead.yaml", "1", out, sizeof out), 0, "%s", out);
    cr_assert(strstr(out, "3 done (1 earlier), 0 failed"), "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'done' AND attempt = 1"), 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 3);
    sqlite3_close(db);
    ct_rmrf(dir);
}
