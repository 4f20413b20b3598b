/*
 * runs_slurm_running (schema version 10): the partial index of the runs in
 * Slurm now.  A version-9 file with runs in and out of Slurm, live and
 * ended, of active and edited-away jobs of two studies is migrated: the
 * index holds exactly the live Slurm runs, applying the migration's SQL a
 * second time changes nothing, and `cascade status` counts the queued and
 * running Slurm jobs as walking the study's running jobs did (the same
 * file without the index, which status takes for an unmigrated one).
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "../campaign/db.h"
#include "helpers/ct.h"

static void exec_ok(sqlite3 *db, const char *sql)
{
    struct err e = {0};
    cr_assert_eq(db_exec(db, sql, &e), 0, "%s\n%s", e.msg, sql);
}

/* Study a (jobs 1-8) and study b (job 9). */
static void studies(sqlite3 *db)
{
    exec_ok(db, "INSERT INTO studies (id, name, spec_path, spec_text, spec_hash, created, updated) "
                "VALUES (1, 'a', '/a.yaml', 'x', 'h', 't', 't'), (2, 'b', '/b.yaml', 'x', 'h', 't', 't');"
                "WITH RECURSIVE k(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM k WHERE i < 8) "
                "INSERT INTO jobs (id, study_id, key, kind, seq, params, case_json) "
                "SELECT i, 1, 'a' || i, 'sweep', i, '{}', '{}' FROM k;"
                "INSERT INTO jobs (id, study_id, key, kind, seq, params, case_json) "
                "VALUES (9, 2, 'b1', 'sweep', 0, '{}', '{}');");
}

/* A run; slurm_id NULL (NULL state too) for a local one. */
static void run(sqlite3 *db, int job, int attempt, const char *status, const char *slurm_id,
                const char *slurm_state)
{
    char sql[768];
    snprintf(sql, sizeof sql,
             "INSERT INTO runs (job_id, attempt, status, started, host, runner, launcher, "
             "solver_version, solver_git, run_dir, slurm_job_id, slurm_state) VALUES (%d, %d, "
             "'%s', 't', 'h', 'r', 'slurm', 'v', 'g', '/d', %s%s%s, %s%s%s)",
             job, attempt, status, slurm_id ? "'" : "", slurm_id ? slurm_id : "NULL",
             slurm_id ? "'" : "", slurm_state ? "'" : "", slurm_state ? slurm_state : "NULL",
             slurm_state ? "'" : "");
    exec_ok(db, sql);
}

/* The version-9 file: in study a two queued and two running in Slurm
 * (one of them a second attempt after a cancelled one), a local running
 * job, a finished Slurm job, a pending job and an edited-away job still
 * in Slurm; in study b one running in Slurm. */
static void version9_file(const char *path)
{
    sqlite3 *db = NULL;
    struct err e = {0};
    int n;
    const struct db_migration *m = db_migrations(&n);
    cr_assert_geq(n, 10);
    cr_assert_eq(sqlite3_open(path, &db), SQLITE_OK);
    cr_assert_eq(db_migrate(db, m, 9, &e), 0, "%s", e.msg);
    exec_ok(db, "PRAGMA foreign_keys = ON");
    studies(db);
    run(db, 1, 1, "running", "100_0", "PENDING");
    run(db, 2, 1, "running", "100_1", "RUNNING");
    run(db, 3, 1, "running", "100_2", "RUNNING");
    run(db, 4, 1, "running", NULL, NULL);
    run(db, 5, 1, "done", "100_4", "COMPLETED");
    run(db, 6, 1, "cancelled", "100_5", "CANCELLED");
    run(db, 6, 2, "running", "101_0", "PENDING");
    run(db, 8, 1, "running", "100_7", "RUNNING");
    exec_ok(db, "UPDATE jobs SET active = 0 WHERE id = 8");
    run(db, 9, 1, "running", "102_0", "RUNNING");
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), 9);
    sqlite3_close(db);
}

static long long live_slurm_runs_indexed(sqlite3 *db)
{
    return ct_int(db, "SELECT count(*) FROM runs INDEXED BY runs_slurm_running "
                      "WHERE slurm_job_id IS NOT NULL AND status = 'running'");
}

Test(campaign_slurm_index, migration_indexes_the_live_slurm_runs_and_is_idempotent)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    version9_file(path);
    sqlite3 *db = NULL;
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);   /* migrates */
    int n;
    const struct db_migration *m = db_migrations(&n);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), n);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM sqlite_master WHERE type = 'index' AND "
                            "name = 'runs_slurm_running'"),
                 1);
    /* jobs 1, 2, 3, 6 (attempt 2), 8 and 9: live and in Slurm */
    cr_assert_eq(live_slurm_runs_indexed(db), 6);
    /* the index follows status changes: job 2 finishes, job 4 (local) too */
    exec_ok(db, "UPDATE runs SET status = 'done', slurm_state = 'COMPLETED' WHERE job_id = 2");
    exec_ok(db, "UPDATE runs SET status = 'done' WHERE job_id = 4");
    cr_assert_eq(live_slurm_runs_indexed(db), 5);
    /* migration 10 again (as a file applied by hand would be): no error,
     * the same index, the version unchanged */
    cr_assert_eq(strncmp(m[9].name, "0010_", 5), 0, "%s", m[9].name);
    exec_ok(db, m[9].sql);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM sqlite_master WHERE type = 'index' AND "
                            "name = 'runs_slurm_running'"),
                 1);
    cr_assert_eq(live_slurm_runs_indexed(db), 5);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), n);
    db_close(&db);
    ct_rmrf(dir);
}

Test(campaign_slurm_index, status_counts_slurm_jobs_as_walking_the_jobs_did)
{
    char dir[64], path[128], out[16384], old[16384];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    version9_file(path);
    /* the unmigrated file first (status opens read-only, never migrates) */
    cr_assert_eq(ct_cascade(dir, NULL, old, sizeof old, "status", "a", NULL), 0, "%s", old);
    sqlite3 *db = NULL;
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);   /* migrates */
    db_close(&db);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "status", "a", NULL), 0, "%s", out);
    /* queued: jobs 1 and 6; running: 2 and 3 (8 is edited away, 9 is b's) */
    cr_assert(strstr(out, "in Slurm: 2 queued, 2 running"), "%s", out);
    cr_assert(strstr(out, "7 jobs: 1 done, 0 failed, 5 running"), "%s", out);
    cr_assert_str_eq(out, old);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "status", "b", NULL), 0, "%s", out);
    cr_assert(strstr(out, "in Slurm: 0 queued, 1 running"), "%s", out);
    ct_rmrf(dir);
}
