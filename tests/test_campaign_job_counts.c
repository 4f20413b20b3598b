/*
 * job_counts (schema version 7): the triggers keep the counts per study,
 * state and solver equal to a count over the active jobs through inserts,
 * runs that change a job's state, a job edited away (active = 0) and back,
 * a deleted job and a deleted study; a database migrated from version 4
 * gets the counts of the jobs it already had.  `cascade status` reads the
 * counts and prints the same tables as counting the jobs did: the "not
 * done" list comes out in expansion order across states, and an old
 * database (read-only, not migrated) is still counted the old way.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "../campaign/db.h"
#include "helpers/ct.h"

/* Rows of job_counts (n > 0) that differ from a count over the jobs, in
 * either direction: 0 when they agree. */
static long long mismatches(sqlite3 *db)
{
    return ct_int(db,
                  "SELECT count(*) FROM ("
                  "SELECT study_id, state, solver, n FROM job_counts WHERE n > 0 "
                  "EXCEPT SELECT study_id, state, coalesce(solver, ''), count(*) FROM jobs "
                  "WHERE active = 1 GROUP BY 1, 2, 3 "
                  "UNION ALL "
                  "SELECT study_id, state, coalesce(solver, ''), count(*) FROM jobs "
                  "WHERE active = 1 GROUP BY 1, 2, 3 "
                  "EXCEPT SELECT study_id, state, solver, n FROM job_counts WHERE n > 0)");
}

static void exec_ok(sqlite3 *db, const char *sql)
{
    struct err e = {0};
    cr_assert_eq(db_exec(db, sql, &e), 0, "%s\n%s", e.msg, sql);
}

/* Two studies, 12 and 3 jobs (seq 0..). */
static void two_studies(sqlite3 *db)
{
    exec_ok(db, "INSERT INTO studies (id, name, spec_path, spec_text, spec_hash, created, updated) "
                "VALUES (1, 'a', '/a.yaml', 'x', 'h', 't', 't'), (2, 'b', '/b.yaml', 'x', 'h', 't', 't');"
                "WITH RECURSIVE k(i) AS (SELECT 0 UNION ALL SELECT i + 1 FROM k WHERE i < 11) "
                "INSERT INTO jobs (study_id, key, kind, seq, params, case_json) "
                "SELECT 1, 'a' || i, 'sweep', i, '{\"i\":' || i || '}', '{}' FROM k;"
                "WITH RECURSIVE k(i) AS (SELECT 0 UNION ALL SELECT i + 1 FROM k WHERE i < 2) "
                "INSERT INTO jobs (study_id, key, kind, seq, params, case_json) "
                "SELECT 2, 'b' || i, 'sweep', i, '{}', '{}' FROM k;");
}

/* A run of job `job` (attempt `attempt`) with status and solver version. */
static void run(sqlite3 *db, int job, int attempt, const char *status, const char *version)
{
    char sql[512];
    snprintf(sql, sizeof sql,
             "INSERT INTO runs (job_id, attempt, status, started, host, runner, launcher, "
             "solver_version, solver_git, run_dir, message) VALUES (%d, %d, '%s', 't', 'h', 'r', "
             "'local', '%s', 'g', '/d', 'why %d')",
             job, attempt, status, version, job);
    exec_ok(db, sql);
}

Test(campaign_job_counts, triggers_keep_counts_equal_to_the_jobs)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);
    two_studies(db);
    cr_assert_eq(ct_int(db, "SELECT n FROM job_counts WHERE study_id = 1 AND state = 'pending'"), 12);
    cr_assert_eq(mismatches(db), 0);
    run(db, 1, 1, "running", "v1");
    run(db, 2, 1, "done", "v1");
    run(db, 3, 1, "done", "v2");
    run(db, 4, 1, "failed", "v1");
    cr_assert_eq(mismatches(db), 0);
    exec_ok(db, "UPDATE runs SET status = 'done' WHERE job_id = 1");   /* running -> done */
    run(db, 4, 2, "done", "v2");                                        /* retried */
    cr_assert_eq(ct_int(db, "SELECT n FROM job_counts WHERE study_id = 1 AND state = 'done' "
                            "AND solver = 'v2 (g)'"),
                 2);
    cr_assert_eq(mismatches(db), 0);
    exec_ok(db, "UPDATE jobs SET active = 0 WHERE id IN (2, 5)");   /* edited away */
    cr_assert_eq(mismatches(db), 0);
    exec_ok(db, "UPDATE jobs SET active = 1 WHERE id = 5");         /* and back */
    exec_ok(db, "DELETE FROM jobs WHERE id = 6");
    cr_assert_eq(mismatches(db), 0);
    cr_assert_eq(ct_int(db, "SELECT sum(n) FROM job_counts WHERE study_id = 1"), 10);
    exec_ok(db, "DELETE FROM studies WHERE id = 2");   /* cascades to its jobs and counts */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM job_counts WHERE study_id = 2"), 0);
    cr_assert_eq(mismatches(db), 0);
    db_close(&db);
    ct_rmrf(dir);
}

Test(campaign_job_counts, migration_counts_existing_jobs)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    struct err e = {0};
    int n;
    const struct db_migration *m = db_migrations(&n);
    cr_assert_geq(n, 7);
    /* a version-4 file with jobs in several states */
    cr_assert_eq(sqlite3_open(path, &db), SQLITE_OK);
    cr_assert_eq(db_migrate(db, m, 4, &e), 0, "%s", e.msg);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), 4);
    two_studies(db);
    run(db, 2, 1, "done", "v1");
    run(db, 3, 1, "failed", "v1");
    exec_ok(db, "UPDATE jobs SET active = 0 WHERE id = 7");
    sqlite3_close(db);
    db = NULL;
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);   /* migrates */
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), n);
    cr_assert_eq(ct_int(db, "SELECT sum(n) FROM job_counts"), 14);
    cr_assert_eq(mismatches(db), 0);
    db_close(&db);
    ct_rmrf(dir);
}

/* status on a study whose early jobs are done and whose failed and pending
 * jobs interleave: the list is in seq order across states, and counted
 * from job_counts it equals the old count (the same database with
 * job_counts dropped, which status takes for an old file). */
Test(campaign_job_counts, status_lists_not_done_in_order_and_matches_counting)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);
    two_studies(db);
    for (int j = 1; j <= 4; j++)
        run(db, j, 1, "done", "v1");
    run(db, 6, 1, "failed", "v1");
    run(db, 9, 1, "timeout", "v1");
    run(db, 10, 1, "running", "v1");
    db_close(&db);
    char out[16384], old[16384];
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "status", "a", NULL), 0, "%s", out);
    cr_assert(strstr(out, "12 jobs: 4 done, 2 failed, 1 running, 5 other"), "%s", out);
    cr_assert(strstr(out, "not done (first 20 of 7):"), "%s", out);
    /* a5 (pending), a6 (failed, seq 5) ... a8 (timeout, seq 8) in seq order */
    const char *order[] = {"a4 ", "a5 ", "a6 ", "a7 ", "a8 ", "a10 ", "a11 "};
    const char *at = strstr(out, "not done");
    for (size_t k = 0; k < sizeof order / sizeof order[0]; k++) {
        const char *next = strstr(at, order[k]);
        cr_assert(next, "%s missing or out of order in\n%s", order[k], out);
        at = next;
    }
    char all[16384], all_old[16384];
    cr_assert_eq(ct_cascade(dir, NULL, all, sizeof all, "status", NULL), 0, "%s", all);
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);
    exec_ok(db, "DROP TABLE job_counts");
    db_close(&db);
    cr_assert_eq(ct_cascade(dir, NULL, old, sizeof old, "status", "a", NULL), 0, "%s", old);
    cr_assert_str_eq(out, old);
    cr_assert_eq(ct_cascade(dir, NULL, all_old, sizeof all_old, "status", NULL), 0, "%s", all_old);
    cr_assert_str_eq(all, all_old);
    ct_rmrf(dir);
}
