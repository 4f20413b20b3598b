/* cascade retry: make a study's jobs run again. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "util/mem.h"

static const char *usage =
    "usage: cascade retry STUDY [--failed] [--db FILE] [--no-run] [run options]\n"
    "\n"
    "Forgives the earlier attempts of the study's jobs, so that they run again\n"
    "even when done (or, with --failed, only the jobs whose latest attempt\n"
    "failed, crashed, timed out, diverged or was cancelled, including those that\n"
    "used up their retries), then runs the study from its file as 'cascade run'\n"
    "would; the earlier runs stay in the database.  --no-run only marks the jobs.\n"
    "Other options (--jobs, --runs, --solver, --lease, --quiet) go to 'cascade run'.\n";

int cmd_retry(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL;
    int failed_only = 0, no_run = 0;
    char **run_argv = mem_calloc((size_t)argc + 4, sizeof *run_argv);
    int run_argc = 1;   /* slot 0: the study file */
    if (!run_argv)
        return 1;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path))) {
            if (m < 0) {
                free(run_argv);
                return 2;
            }
        } else if (strcmp(argv[i], "--failed") == 0) {
            failed_only = 1;
        } else if (strcmp(argv[i], "--no-run") == 0) {
            no_run = 1;
        } else if (argv[i][0] != '-' && !study) {
            study = argv[i];
        } else {
            run_argv[run_argc++] = argv[i];   /* checked by cascade run */
        }
    }
    if (!study) {
        free(run_argv);
        return cli_usage_error(usage, "give a study name");
    }
    struct err e = {0};
    sqlite3 *db = NULL;
    sqlite3_stmt *st = NULL;
    char spec_path[4096] = "";
    int changed = 0;
    int rc = db_open(db_path, &db, &e);
    if (!rc)
        rc = db_begin(db, &e);
    if (!rc)
        rc = db_prepare(db, "SELECT id, spec_path FROM studies WHERE name = ?1", &st, &e);
    long long sid = 0;
    if (!rc) {
        sqlite3_bind_text(st, 1, study, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW) {
            sid = sqlite3_column_int64(st, 0);
            snprintf(spec_path, sizeof spec_path, "%s", (const char *)sqlite3_column_text(st, 1));
        } else {
            rc = err_set(&e, ERR_INPUT, "no study named '%s' in %s", study, db_path);
        }
        sqlite3_finalize(st);
    }
    if (!rc) {
        char sql[512];
        snprintf(sql, sizeof sql,
                 "UPDATE jobs SET state = 'pending', retry_after = "
                 "(SELECT coalesce(max(attempt), 0) FROM runs WHERE job_id = jobs.id) "
                 "WHERE study_id = %lld AND active = 1 AND id NOT IN (SELECT job_id FROM leases) "
                 "%s",
                 sid,
                 failed_only ? "AND state IN ('failed', 'crashed', 'timeout', 'diverged', "
                               "'cancelled')"
                             : "");
        rc = db_exec(db, sql, &e);
        changed = sqlite3_changes(db);
    }
    if (!rc)
        rc = db_commit(db, &e);
    if (rc)
        db_rollback(db);
    db_close(&db);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        free(run_argv);
        return cli_exit_code(rc);
    }
    fprintf(stderr, "[cascade] study %s: %d job%s will run again\n", study, changed,
            changed == 1 ? "" : "s");
    if (no_run) {
        printf("run them with: cascade run %s --db %s\n", spec_path, db_path);
        free(run_argv);
        return 0;
    }
    run_argv[0] = spec_path;
    run_argv[run_argc++] = "--db";
    run_argv[run_argc++] = (char *)db_path;
    int code = cmd_run(run_argc, run_argv);
    free(run_argv);
    return code;
}
