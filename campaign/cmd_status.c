/* cascade status: how far each study (or one) has come. */
#include <string.h>

#include "cli.h"
#include "db.h"
#include "refine_state.h"
#include "sysinfo.h"
#include "table.h"

static const char *usage =
    "usage: cascade status [STUDY] [--db FILE]\n"
    "\n"
    "Without STUDY: one line per study (jobs, done, failed, running, pending).\n"
    "With STUDY: its counts by state, the jobs running now and the jobs not done\n"
    "with their reasons and failure classes (failed counts failed, crashed,\n"
    "timeout and diverged; an infrastructure failure is cancelled and runs again).\n"
    "Jobs shown as running whose runner is gone will run again with the next\n"
    "'cascade run'.  The database is opened read-only.\n";

#define FAILED_STATES "('failed', 'crashed', 'timeout', 'diverged')"

/* Schema version 7 and later keep job counts per study, state and solver
 * (db/migrations/0007_job_counts.sql): status reads those instead of
 * counting the jobs.  Older files (opened read-only, so not migrated) are
 * counted the old way. */
static int has_schema_object(sqlite3 *db, const char *type, const char *name)
{
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM sqlite_master WHERE type = ?1 AND name = ?2", -1,
                           &st, NULL) != SQLITE_OK)
        return 0;
    sqlite3_bind_text(st, 1, type, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, name, -1, SQLITE_STATIC);
    int yes = sqlite3_step(st) == SQLITE_ROW;
    sqlite3_finalize(st);
    return yes;
}

static int has_job_counts(sqlite3 *db)
{
    return has_schema_object(db, "table", "job_counts");
}

static int overview(sqlite3 *db, struct err *e)
{
    sqlite3_stmt *st;
    int rc = has_job_counts(db)
        ? db_prepare(
        db,
        "SELECT s.name AS study, coalesce(sum(c.n), 0) AS jobs, "
        "coalesce(sum(c.n) FILTER (WHERE c.state = 'done'), 0) AS done, "
        "coalesce(sum(c.n) FILTER (WHERE c.state IN " FAILED_STATES "), 0) AS failed, "
        "coalesce(sum(c.n) FILTER (WHERE c.state = 'running'), 0) AS running, "
        "coalesce(sum(c.n) FILTER (WHERE c.state = 'pending'), 0) AS pending, "
        "coalesce(sum(c.n) FILTER (WHERE c.state = 'cancelled'), 0) AS cancelled, "
        "s.updated AS updated "
        "FROM studies s LEFT JOIN job_counts c ON c.study_id = s.id "
        "GROUP BY s.id ORDER BY s.name",
        &st, e)
        : db_prepare(
        db,
        "SELECT s.name AS study, count(j.id) AS jobs, "
        "count(*) FILTER (WHERE j.state = 'done') AS done, "
        "count(*) FILTER (WHERE j.state IN " FAILED_STATES ") AS failed, "
        "count(*) FILTER (WHERE j.state = 'running') AS running, "
        "count(*) FILTER (WHERE j.state = 'pending') AS pending, "
        "count(*) FILTER (WHERE j.state = 'cancelled') AS cancelled, s.updated AS updated "
        "FROM studies s LEFT JOIN jobs j ON j.study_id = s.id AND j.active = 1 "
        "GROUP BY s.id ORDER BY s.name",
        &st, e);
    if (rc)
        return rc;
    long n;
    rc = table_print(db, st, TABLE_TEXT, stdout, &n, e);
    sqlite3_finalize(st);
    if (!rc && n == 0)
        printf("(no studies yet: cascade run STUDY.yaml)\n");
    return rc;
}

/* Running jobs whose runner is gone: *stale of them run again, *orphans
 * (in Slurm) are adopted by the next runner. */
static int stale_running(sqlite3 *db, long long study_id, long *stale, long *orphans,
                         struct err *e)
{
    sqlite3_stmt *st;
    *stale = *orphans = 0;
    int rc = db_prepare(db,
                        /* CROSS JOIN: leases drive (one per job running now); the
                         * planner would otherwise walk every job of the study */
                        "SELECT l.runner, l.expires, r.slurm_job_id IS NOT NULL FROM leases l "
                        "CROSS JOIN jobs j ON j.id = l.job_id JOIN runs r ON r.id = l.run_id "
                        "WHERE j.study_id = ?1",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    double now = sys_now();
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *runner = (const char *)sqlite3_column_text(st, 0);
        if (sys_runner_alive(runner) == 0 || sqlite3_column_double(st, 1) < now)
            (*(sqlite3_column_int(st, 2) ? orphans : stale))++;
    }
    sqlite3_finalize(st);
    return 0;
}

/* The first 20 jobs not done and not running, in expansion order, as one
 * statement: the first 20 of each such state present (from job_counts),
 * each read in seq order from jobs_study_state_seq, merged.  A single
 * "state NOT IN (...) ORDER BY seq" would walk past every done job of the
 * study first.  States are bound, never written into the SQL. */
#define NOT_DONE_MAX_STATES 16
static int not_done_by_state(sqlite3 *db, long long study_id, sqlite3_stmt **out, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "SELECT state FROM job_counts WHERE study_id = ?1 AND "
                        "state NOT IN ('done', 'running') GROUP BY state HAVING sum(n) > 0 "
                        "ORDER BY state",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    char states[NOT_DONE_MAX_STATES][32];
    int ns = 0;
    while (ns < NOT_DONE_MAX_STATES && sqlite3_step(st) == SQLITE_ROW)
        snprintf(states[ns++], sizeof states[0], "%s", (const char *)sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    char sql[8192];
    size_t len = (size_t)snprintf(sql, sizeof sql, "SELECT key, state, attempt, class, params, "
                                                   "reason FROM (");
    for (int k = 0; k < ns; k++)
        len += (size_t)snprintf(
            sql + len, sizeof sql - len,
            "%sSELECT * FROM (SELECT j.seq AS seq, j.key AS key, j.state AS state, "
            "r.attempt AS attempt, coalesce(r.failure_class, '') AS class, j.params AS params, "
            "coalesce(r.message, '') AS reason FROM jobs j "
            "LEFT JOIN runs r ON r.id = j.last_run_id WHERE j.study_id = ?1 AND j.active = 1 "
            "AND j.state = ?%d ORDER BY j.seq LIMIT 20)",
            k ? " UNION ALL " : "", k + 2);
    if (ns == 0)   /* the counts say nothing is left: an empty table all the same */
        len += (size_t)snprintf(sql + len, sizeof sql - len,
                                "SELECT 0 AS seq, '' AS key, '' AS state, 0 AS attempt, "
                                "'' AS class, '' AS params, '' AS reason WHERE 0");
    snprintf(sql + len, sizeof sql - len, ") ORDER BY seq LIMIT 20");
    if ((rc = db_prepare(db, sql, &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    for (int k = 0; k < ns; k++)
        sqlite3_bind_text(st, k + 2, states[k], -1, SQLITE_TRANSIENT);
    *out = st;
    return 0;
}

static int one_study(sqlite3 *db, const char *name, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT id, spec_path, description FROM studies WHERE name = ?1", &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_ROW) {
        sqlite3_finalize(st);
        return err_set(e, ERR_INPUT, "no study named '%s' in the database (cascade status lists them)",
                       name);
    }
    long long id = sqlite3_column_int64(st, 0);
    printf("study %s (%s)\n", name, (const char *)sqlite3_column_text(st, 1));
    const char *desc = (const char *)sqlite3_column_text(st, 2);
    if (desc && desc[0])
        printf("  %s\n", desc);
    sqlite3_finalize(st);

    long total = 0, done = 0, failed = 0, running = 0;
    char states[1024] = "";
    const int counted = has_job_counts(db);
    if ((rc = db_prepare(db,
                         counted ? "SELECT state, sum(n) FROM job_counts WHERE study_id = ?1 "
                                   "GROUP BY state HAVING sum(n) > 0 ORDER BY 2 DESC, 1"
                                 : "SELECT state, count(*) FROM jobs WHERE study_id = ?1 AND "
                                   "active = 1 GROUP BY state ORDER BY 2 DESC, 1",
                         &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, id);
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *s = (const char *)sqlite3_column_text(st, 0);
        long c = (long)sqlite3_column_int64(st, 1);
        total += c;
        if (strcmp(s, "done") == 0)
            done += c;
        else if (strcmp(s, "running") == 0)
            running += c;
        else if (strcmp(s, "failed") == 0 || strcmp(s, "crashed") == 0 ||
                 strcmp(s, "timeout") == 0 || strcmp(s, "diverged") == 0)
            failed += c;
        size_t used = strlen(states);
        snprintf(states + used, sizeof states - used, "%s%s %ld", used ? ", " : "", s, c);
    }
    sqlite3_finalize(st);
    printf("  %ld jobs: %ld done, %ld failed, %ld running, %ld other (%s)\n", total, done, failed,
           running, total - done - failed - running, states[0] ? states : "none");
    long stale, orphans;
    if ((rc = stale_running(db, id, &stale, &orphans, e)))
        return rc;
    if (running) {
        /* Slurm: queued or running as the runner last saw them (no Slurm
         * call).  From schema version 10 the runs in Slurm now drive, read
         * from their partial index (db/migrations/0010_slurm_running.sql):
         * walking the study's running jobs instead costs a read of runs
         * per job, 10,000 of them on the bench's million. */
        if ((rc = db_prepare(db,
                             has_schema_object(db, "index", "runs_slurm_running")
                                 ? "SELECT count(*) FILTER (WHERE r.slurm_state = 'PENDING'), "
                                   "count(*) FILTER (WHERE r.slurm_state = 'RUNNING') "
                                   "FROM runs r INDEXED BY runs_slurm_running "
                                   "CROSS JOIN jobs j ON j.id = r.job_id "
                                   "WHERE r.slurm_job_id IS NOT NULL AND r.status = 'running' "
                                   "AND j.last_run_id = r.id AND j.study_id = ?1 "
                                   "AND j.active = 1 AND j.state = 'running'"
                                 : "SELECT count(*) FILTER (WHERE r.slurm_state = 'PENDING'), "
                                   "count(*) FILTER (WHERE r.slurm_state = 'RUNNING') FROM jobs j "
                                   "JOIN runs r ON r.id = j.last_run_id WHERE j.study_id = ?1 "
                                   "AND j.active = 1 AND j.state = 'running' "
                                   "AND r.slurm_job_id IS NOT NULL",
                             &st, e)))
            return rc;
        sqlite3_bind_int64(st, 1, id);
        if (sqlite3_step(st) == SQLITE_ROW &&
            sqlite3_column_int64(st, 0) + sqlite3_column_int64(st, 1) > 0)
            printf("  in Slurm: %lld queued, %lld running (as the runner last saw them)\n",
                   (long long)sqlite3_column_int64(st, 0), (long long)sqlite3_column_int64(st, 1));
        sqlite3_finalize(st);
    }
    if (orphans)
        printf("  %ld job%s in Slurm with no runner following; the next 'cascade run' "
               "adopts %s\n",
               orphans, orphans == 1 ? "" : "s", orphans == 1 ? "it" : "them");
    if (stale)
        printf("  %ld running job%s belong to a runner that is gone; the next 'cascade run' "
               "runs them again\n",
               stale, stale == 1 ? "" : "s");
    if ((rc = db_prepare(db,
                         counted ? "SELECT nullif(solver, ''), sum(n) FROM job_counts WHERE "
                                   "study_id = ?1 AND state = 'done' GROUP BY solver "
                                   "HAVING sum(n) > 0 ORDER BY 2 DESC, 1"
                                 : "SELECT solver, count(*) FROM jobs WHERE study_id = ?1 AND "
                                   "active = 1 AND state = 'done' GROUP BY solver ORDER BY 2 DESC, 1",
                         &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, id);
    while (sqlite3_step(st) == SQLITE_ROW)
        printf("  done with solver %s: %lld\n", (const char *)sqlite3_column_text(st, 0),
               (long long)sqlite3_column_int64(st, 1));
    sqlite3_finalize(st);
    if ((rc = refine_state_print(db, id, stdout, e)))
        return rc;
    long n;
    if (running) {
        printf("\nrunning:\n");
        if ((rc = db_prepare(db,
                             "SELECT j.key AS key, j.params AS params, r.host AS host, r.attempt AS attempt, "
                             "r.started AS started, r.runner AS runner FROM jobs j "
                             "JOIN runs r ON r.id = j.last_run_id WHERE j.study_id = ?1 "
                             "AND j.active = 1 AND j.state = 'running' ORDER BY j.seq LIMIT 20",
                             &st, e)))
            return rc;
        sqlite3_bind_int64(st, 1, id);
        rc = table_print(db, st, TABLE_TEXT, stdout, &n, e);
        sqlite3_finalize(st);
        if (rc)
            return rc;
    }
    if (total - done - running > 0) {
        printf("\nnot done (first 20 of %ld):\n", total - done - running);
        if (counted) {
            rc = not_done_by_state(db, id, &st, e);
        } else {
            rc = db_prepare(db,
                            "SELECT j.key AS key, j.state AS state, r.attempt AS attempt, "
                            "coalesce(r.failure_class, '') AS class, "
                            "j.params AS params, coalesce(r.message, '') AS reason FROM jobs j "
                            "LEFT JOIN runs r ON r.id = j.last_run_id WHERE j.study_id = ?1 "
                            "AND j.active = 1 AND j.state NOT IN ('done', 'running') "
                            "ORDER BY j.seq LIMIT 20",
                            &st, e);
            if (!rc)
                sqlite3_bind_int64(st, 1, id);
        }
        if (rc)
            return rc;
        rc = table_print(db, st, TABLE_TEXT, stdout, &n, e);
        sqlite3_finalize(st);
    }
    return rc;
}

int cmd_status(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL;
    int bad = cli_study_db_args(argc, argv, usage, &study, &db_path);
    if (bad)
        return bad;
    struct err e = {0};
    sqlite3 *db = NULL;
    int rc = db_open_readonly(db_path, &db, &e);
    if (!rc)
        rc = study ? one_study(db, study, &e) : overview(db, &e);
    db_close(&db);
    if (rc)
        fprintf(stderr, "error: %s\n", e.msg);
    return cli_exit_code(rc);
}
