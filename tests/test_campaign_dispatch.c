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
 *     job, also with several slots.
 */
#include <criterion/criterion.h>
#include <dirent.h>
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
