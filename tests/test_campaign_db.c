/*
 * The results database: a new file gets the newest schema (PRAGMA
 * user_version = number of migrations) in WAL mode with foreign keys on;
 * opening again migrates nothing; migrations apply in order inside one
 * transaction (a failing one leaves the file as it was); a database newer
 * than the program is refused; the migration files are numbered as their
 * versions; jobs.state follows the latest run through the triggers; the
 * read-only connection refuses writes (cascade query refuses a statement that
 * may write before it runs: VACUUM INTO creates no file); schema constraints hold; many
 * processes opening one fresh file at once all succeed (the WAL switch
 * takes no busy handler).  A database cascade may not write is refused at
 * once, naming the file (every error of the db layer names it).
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../campaign/db.h"
#include "helpers/ct.h"

static sqlite3 *fresh(const char *dir, char *path, size_t len)
{
    snprintf(path, len, "%s/cascade.db", dir);
    sqlite3 *db = NULL;
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);
    return db;
}

Test(campaign_db, new_database_has_newest_schema)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    sqlite3 *db = fresh(dir, path, sizeof path);
    int n;
    db_migrations(&n);
    cr_assert_geq(n, 1);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), n);
    char mode[32];
    ct_text(db, "PRAGMA journal_mode", mode, sizeof mode);
    cr_assert_str_eq(mode, "wal");
    cr_assert_eq(ct_int(db, "PRAGMA foreign_keys"), 1);
    const char *tables[] = {"studies", "study_axes", "jobs", "job_params", "job_deps", "runs",
                            "metrics", "artifacts", "leases", NULL};
    for (int i = 0; tables[i]; i++) {
        char sql[160];
        snprintf(sql, sizeof sql, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND "
                                  "name = '%s'", tables[i]);
        cr_assert_eq(ct_int(db, sql), 1, "table %s missing", tables[i]);
    }
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM sqlite_master WHERE type = 'view' AND name IN "
                            "('results', 'run_metrics', 'job_status')"),
                 3);
    db_close(&db);
    /* opening again changes nothing */
    struct err e = {0};
    cr_assert_eq(db_open(path, &db, &e), 0, "%s", e.msg);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), n);
    db_close(&db);
    ct_rmrf(dir);
}

Test(campaign_db, migration_files_are_numbered)
{
    int n;
    const struct db_migration *m = db_migrations(&n);
    cr_assert_str_eq(m[0].name, "schema.sql");
    for (int i = 1; i < n; i++) {
        char want[8];
        snprintf(want, sizeof want, "%04d_", i + 1);
        cr_assert(strncmp(m[i].name, want, 5) == 0, "migration %d is %s; want %s*", i + 1,
                  m[i].name, want);
    }
}

Test(campaign_db, migrations_apply_in_order_or_not_at_all)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/m.db", dir);
    sqlite3 *db;
    cr_assert_eq(sqlite3_open(path, &db), SQLITE_OK);
    const struct db_migration list[] = {
        {"schema.sql", "CREATE TABLE a (x INTEGER);"},
        {"0002_b.sql", "CREATE TABLE b (y INTEGER); INSERT INTO a VALUES (1);"},
        {"0003_bad.sql", "CREATE TABLE c (z INTEGER); INSERT INTO nowhere VALUES (1);"},
    };
    struct err e = {0};
    cr_assert_eq(db_migrate(db, list, 2, &e), 0, "%s", e.msg);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM a"), 1);
    /* version 3 fails half-way: table c must not exist, the version stays 2 */
    cr_assert_eq(db_migrate(db, list, 3, &e), ERR_RUNTIME);
    cr_assert_not_null(strstr(e.msg, "0003_bad.sql"), "%s", e.msg);
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM sqlite_master WHERE name = 'c'"), 0);
    /* a database newer than the program is refused */
    cr_assert_eq(db_migrate(db, list, 1, &e), ERR_INPUT);
    cr_assert_not_null(strstr(e.msg, "newer"), "%s", e.msg);
    sqlite3_close(db);
    ct_rmrf(dir);
}

Test(campaign_db, state_follows_latest_run_and_constraints_hold)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    sqlite3 *db = fresh(dir, path, sizeof path);
    struct err e = {0};
    cr_assert_eq(db_exec(db,
                         "INSERT INTO studies (id, name, spec_path, spec_text, spec_hash, created, "
                         "updated) VALUES (1, 's', '/s.yaml', 'x', 'h', 't', 't');"
                         "INSERT INTO jobs (id, study_id, key, kind, seq, params, case_json) "
                         "VALUES (1, 1, 'k', 'sweep', 0, '{}', '{}');"
                         "INSERT INTO runs (job_id, attempt, status, started, host, runner, "
                         "launcher, solver_version, solver_git, run_dir) VALUES "
                         "(1, 1, 'running', 't', 'h', 'r', 'local', 'v', 'g', '/d');",
                         &e),
                 0, "%s", e.msg);
    cr_assert_eq(ct_int(db, "SELECT state = 'running' FROM jobs WHERE id = 1"), 1);
    cr_assert_eq(db_exec(db, "UPDATE runs SET status = 'timeout' WHERE id = 1", &e), 0, "%s", e.msg);
    cr_assert_eq(ct_int(db, "SELECT state = 'timeout' FROM jobs WHERE id = 1"), 1);
    cr_assert_eq(db_exec(db,
                         "INSERT INTO runs (job_id, attempt, status, started, host, runner, "
                         "launcher, solver_version, solver_git, run_dir) VALUES "
                         "(1, 2, 'done', 't', 'h', 'r', 'local', 'v', 'g', '/d');"
                         "UPDATE runs SET status = 'cancelled' WHERE id = 1;",
                         &e),
                 0, "%s", e.msg);
    /* an update of an older attempt does not touch the job's state */
    cr_assert_eq(ct_int(db, "SELECT state = 'done' FROM jobs WHERE id = 1"), 1);
    /* foreign keys, status classes and one attempt number per job are enforced */
    cr_assert_neq(db_exec(db, "INSERT INTO metrics VALUES (99, 'x', 1.0, '1')", &e), 0);
    cr_assert_neq(db_exec(db, "UPDATE runs SET status = 'weird' WHERE id = 2", &e), 0);
    cr_assert_neq(db_exec(db,
                          "INSERT INTO runs (job_id, attempt, status, started, host, runner, "
                          "launcher, solver_version, solver_git, run_dir) VALUES "
                          "(1, 2, 'done', 't', 'h', 'r', 'local', 'v', 'g', '/d')",
                          &e),
                  0);
    db_close(&db);
    /* the read-only connection (cascade query) cannot write */
    cr_assert_eq(db_open_readonly(path, &db, &e), 0, "%s", e.msg);
    cr_assert_neq(db_exec(db, "DELETE FROM runs", &e), 0);
    db_close(&db);
    char out[4096];
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", "DELETE FROM runs", NULL), 2,
                 "%s", out);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", "SELECT count(*) AS n FROM runs",
                            "--csv", NULL),
                 0, "%s", out);
    cr_assert_str_eq(out, "n\n2\n");
    /* a write that SQLite would refuse only after creating a file (VACUUM
     * INTO) is refused before it runs: no file appears */
    char copy[160], sql[256];
    snprintf(copy, sizeof copy, "%s/copy.db", dir);
    snprintf(sql, sizeof sql, "VACUUM INTO '%s'", copy);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", sql, NULL), 2, "%s", out);
    cr_assert_not_null(strstr(out, "read-only"), "%s", out);
    cr_assert_neq(access(copy, F_OK), 0, "query created %s", copy);
    /* ... also after a statement that ran (nothing of a refused script runs after it) */
    snprintf(sql, sizeof sql, "SELECT 1 AS one; VACUUM INTO '%s'", copy);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", sql, NULL), 2, "%s", out);
    cr_assert_neq(access(copy, F_OK), 0, "query created %s", copy);
    /* reading statements still run, and EXPLAIN of a write only describes it */
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", "PRAGMA table_info(runs)",
                            "--csv", NULL),
                 0, "%s", out);
    snprintf(sql, sizeof sql, "EXPLAIN VACUUM INTO '%s'", copy);
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "query", sql, "--csv", NULL), 0, "%s",
                 out);
    cr_assert_neq(access(copy, F_OK), 0, "EXPLAIN created %s", copy);
    ct_rmrf(dir);
}

/* Version 3 classes the failures recorded before it: a failure to start
 * (now cancelled, so the job runs again) and a run whose runner went away
 * were the infrastructure's, every other failure the job's. */
Test(campaign_db, failure_classes_of_earlier_runs)
{
    char dir[64], path[128];
    ct_mkdir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/v2.db", dir);
    sqlite3 *db;
    cr_assert_eq(sqlite3_open(path, &db), SQLITE_OK);
    int n;
    const struct db_migration *list = db_migrations(&n);
    cr_assert_geq(n, 3);
    cr_assert_str_eq(list[2].name, "0003_failure_class.sql");
    struct err e = {0};
    cr_assert_eq(db_migrate(db, list, 2, &e), 0, "%s", e.msg);
    cr_assert_eq(db_exec(db,
                         "INSERT INTO studies (id, name, spec_path, spec_text, spec_hash, created, "
                         "updated) VALUES (1, 's', '/s.yaml', 'x', 'h', 't', 't');"
                         "INSERT INTO jobs (id, study_id, key, kind, seq, params, case_json) "
                         "VALUES (1, 1, 'k', 'sweep', 0, '{}', '{}');"
                         "INSERT INTO runs (job_id, attempt, status, message, started, host, "
                         "runner, launcher, solver_version, solver_git, run_dir) VALUES "
                         "(1, 1, 'failed', 'could not start: cannot write /r/case.yaml', 't', "
                         "'h', 'r', 'local', 'v', 'g', '/d'),"
                         "(1, 2, 'failed', 'exit 3: bad', 't', 'h', 'r', 'local', 'v', 'g', '/d'),"
                         "(1, 3, 'crashed', 'crashed: killed by signal 11 (Segmentation fault)', "
                         "'t', 'h', 'r', 'local', 'v', 'g', '/d'),"
                         "(1, 4, 'cancelled', 'runner h:1:2 is gone (killed?); the job will run "
                         "again', 't', 'h', 'r', 'local', 'v', 'g', '/d'),"
                         "(1, 5, 'cancelled', 'cancelled: the runner was asked to stop', 't', "
                         "'h', 'r', 'local', 'v', 'g', '/d'),"
                         "(1, 6, 'done', NULL, 't', 'h', 'r', 'local', 'v', 'g', '/d');",
                         &e),
                 0, "%s", e.msg);
    cr_assert_eq(db_migrate(db, list, n, &e), 0, "%s", e.msg);
    const char *want[][2] = {{"cancelled", "infrastructure"}, {"failed", "job"},
                             {"crashed", "job"},           {"cancelled", "infrastructure"},
                             {"cancelled", ""},            {"done", ""}};
    for (int a = 1; a <= 6; a++) {
        char sql[128], got[64], expect[64];
        snprintf(sql, sizeof sql,
                 "SELECT status || ' ' || coalesce(failure_class, '') FROM runs WHERE attempt = %d",
                 a);
        ct_text(db, sql, got, sizeof got);
        snprintf(expect, sizeof expect, "%s %s", want[a - 1][0], want[a - 1][1]);
        cr_assert_str_eq(got, expect, "attempt %d", a);
    }
    /* the new column takes only the three classes; job_status shows it */
    cr_assert_neq(db_exec(db, "UPDATE runs SET failure_class = 'weird' WHERE attempt = 1", &e), 0);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM job_status WHERE failure_class IS NULL "
                            "AND state = 'done'"),
                 1);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* Runners started together race to create and convert the same file. */
Test(campaign_db, concurrent_first_opens_all_succeed, .timeout = 120)
{
    enum { NPROC = 12, ROUNDS = 10 };
    for (int round = 0; round < ROUNDS; round++) {
        char dir[64], path[128];
        ct_mkdir(dir, sizeof dir);
        snprintf(path, sizeof path, "%s/cascade.db", dir);
        pid_t pids[NPROC];
        int gate[2];   /* the children wait until the parent closes it */
        cr_assert_eq(pipe(gate), 0);
        for (int k = 0; k < NPROC; k++) {
            pids[k] = fork();
            cr_assert_geq(pids[k], 0);
            if (pids[k] == 0) {
                char c;
                close(gate[1]);
                while (read(gate[0], &c, 1) > 0)
                    ;
                sqlite3 *db = NULL;
                struct err e = {0};
                int rc = db_open(path, &db, &e);
                if (rc)
                    fprintf(stderr, "open %d: %s\n", k, e.msg);
                db_close(&db);
                _exit(rc ? 1 : 0);
            }
        }
        close(gate[0]);
        close(gate[1]);
        int failed = 0;
        for (int k = 0; k < NPROC; k++) {
            int status = 0;
            waitpid(pids[k], &status, 0);
            if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
                failed++;
        }
        cr_assert_eq(failed, 0, "round %d: %d of %d concurrent opens failed", round, failed, NPROC);
        ct_rmrf(dir);
    }
}

Test(campaign_db, read_only_database_is_named, .timeout = 60)
{
    char dir[64], out[16384], db_path[128];
    ct_mkdir(dir, sizeof dir);
    cr_assert_eq(chmod(dir, 0755), 0);   /* the unprivileged run reads the study */
    ct_write(0, dir, "ro.yaml", "name: ro\nbase: {fake: {x: 1}}\n");
    cr_assert_eq(ct_cascade(dir, NULL, out, sizeof out, "run", "ro.yaml", "--solver", ct_standin(),
                            NULL),
                 0, "%s", out);
    snprintf(db_path, sizeof db_path, "%s/cascade.db", dir);
    cr_assert_eq(chmod(db_path, 0444), 0);
    /* as root, file permissions stop nothing: the run drops to nobody, who
     * may not write the database (nor create its journal in dir) */
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int rc = ct_cascade_unprivileged(dir, out, sizeof out, "run", "ro.yaml", "--solver",
                                     ct_standin(), NULL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    cr_assert_eq(rc, 1, "%s", out);
    /* at once: waiting out the busy timeout would not make the file writable */
    double took = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    cr_assert_lt(took, 10.0, "took %.1f s", took);
    char want[192];
    snprintf(want, sizeof want, "database %s: cannot open for writing (read-only", db_path);
    cr_assert_not_null(strstr(out, want), "%s", out);
    ct_rmrf(dir);
}
