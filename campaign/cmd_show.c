/* cascade show: everything about one job. */
#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "table.h"
#include "util/mem.h"
#include "util/yamldoc.h"

static const char *usage =
    "usage: cascade show KEY [--db FILE] [--case]\n"
    "\n"
    "Shows a job: its study, swept parameters, state, run directory, every\n"
    "attempt (status, exit code or signal, wall time, peak memory, host, solver),\n"
    "the metrics and files of its latest attempt and, when it did not succeed,\n"
    "the tail of its stderr.  KEY may be abbreviated to a unique prefix (at\n"
    "least 4 hex digits).  --case also prints the resolved case as YAML.\n";

static int print_rows(sqlite3 *db, const char *title, const char *sql, long long id, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, sql, &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, id);
    printf("\n%s:\n", title);
    long n;
    rc = table_print(db, st, TABLE_TEXT, stdout, &n, e);
    sqlite3_finalize(st);
    return rc;
}

static int show_job(sqlite3 *db, long long job_id, int with_case, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "SELECT j.key, s.name, j.kind, j.name, j.seq, j.params, j.state, "
                        "j.case_json, j.last_run_id, r.run_dir, r.stderr_tail, j.active "
                        "FROM jobs j JOIN studies s ON s.id = j.study_id "
                        "LEFT JOIN runs r ON r.id = j.last_run_id WHERE j.id = ?1",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, job_id);
    if (sqlite3_step(st) != SQLITE_ROW) {
        sqlite3_finalize(st);
        return err_set(e, ERR_RUNTIME, "job %lld vanished", job_id);
    }
#define COL(i) ((const char *)sqlite3_column_text(st, i))
    printf("job %s  (study %s, %s%s%s #%lld%s)\n", COL(0), COL(1), COL(2), COL(3) ? " " : "",
           COL(3) ? COL(3) : "", (long long)sqlite3_column_int64(st, 4),
           sqlite3_column_int(st, 11) ? "" : ", no longer in the study file");
    printf("parameters: %s\n", COL(5));
    printf("state: %s\n", COL(6));
    if (COL(9))
        printf("run directory: %s\n", COL(9));
    long long last = sqlite3_column_int64(st, 8);
    char *case_json = COL(7) ? mem_strdup(COL(7)) : NULL;
    char *tail = COL(10) && strcmp(COL(6), "done") != 0 ? mem_strdup(COL(10)) : NULL;
#undef COL
    sqlite3_finalize(st);
    rc = print_rows(db, "attempts",
                    "SELECT attempt, status, exit_code AS exit, signal, "
                    "printf('%.2f', wall_s) AS wall_s, printf('%.1f', peak_rss_mib) AS rss_mib, "
                    "host, solver_version || ' (' || solver_git || ')' AS solver, started, "
                    "coalesce(message, '') AS message FROM runs WHERE job_id = ?1 ORDER BY attempt",
                    job_id, e);
    if (!rc && last)
        rc = print_rows(db, "metrics (latest attempt)",
                        "SELECT name, value, unit FROM metrics WHERE run_id = ?1 ORDER BY name",
                        last, e);
    if (!rc && last)
        rc = print_rows(db, "files (latest attempt)",
                        "SELECT kind, path, bytes, sha256 FROM artifacts WHERE run_id = ?1 "
                        "ORDER BY path",
                        last, e);
    if (!rc && tail && tail[0])
        printf("\nstderr (last lines):\n%s\n", tail);
    if (!rc && with_case && case_json) {
        json_t *doc = json_loads(case_json, 0, NULL);
        printf("\ncase (resolved):\n");
        if (doc && yamldoc_write(stdout, doc) != 0)
            rc = err_nomem(e, "case");
        json_decref(doc);
    }
    free(case_json);
    free(tail);
    return rc;
}

int cmd_show(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *key = NULL;
    int with_case = 0;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path))) {
            if (m < 0)
                return 2;
        } else if (strcmp(argv[i], "--case") == 0) {
            with_case = 1;
        } else if (argv[i][0] != '-' && !key) {
            key = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!key)
        return cli_usage_error(usage, "give a job key");
    size_t kl = strlen(key);
    if (kl < 4 || kl > 16 || strspn(key, "0123456789abcdef") != kl)
        return cli_usage_error(usage, "'%s' is not a job key (4 to 16 hex digits)", key);
    struct err e = {0};
    sqlite3 *db = NULL;
    int rc = db_open_readonly(db_path, &db, &e);
    sqlite3_stmt *st = NULL;
    if (!rc)
        rc = db_prepare(db,
                        "SELECT id, key FROM jobs WHERE key >= ?1 AND key < ?1 || 'g' "
                        "ORDER BY active DESC, key, id",
                        &st, &e);
    long long ids[64];
    int n = 0, distinct = 0;
    char first[17] = "";
    if (!rc) {
        sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
        while (sqlite3_step(st) == SQLITE_ROW && n < 64) {
            const char *k = (const char *)sqlite3_column_text(st, 1);
            if (!n || strcmp(k, first) != 0) {
                distinct++;
                if (distinct > 1)
                    fprintf(stderr, "%s%s\n", distinct == 2 ? "candidates:\n  " : "  ", k);
                if (distinct == 2)
                    fprintf(stderr, "  %s\n", first);
                snprintf(first, sizeof first, "%s", k);
            }
            ids[n++] = sqlite3_column_int64(st, 0);
        }
        sqlite3_finalize(st);
        if (n == 0)
            rc = err_set(&e, ERR_INPUT, "no job with key %s%s", key, kl < 16 ? "..." : "");
        else if (distinct > 1)
            rc = err_set(&e, ERR_INPUT, "key prefix %s is ambiguous (see the candidates above)", key);
    }
    for (int i = 0; i < n && !rc; i++) {
        if (i)
            printf("\n");
        rc = show_job(db, ids[i], with_case, &e);
    }
    db_close(&db);
    if (rc)
        fprintf(stderr, "error: %s\n", e.msg);
    return cli_exit_code(rc);
}
