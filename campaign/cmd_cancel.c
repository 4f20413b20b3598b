/* cascade cancel: stop what a study has queued or running in Slurm. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "slurm_cli.h"
#include "sysinfo.h"

static const char *usage =
    "usage: cascade cancel STUDY [--db FILE]\n"
    "\n"
    "Cancels (scancel, one call) the Slurm arrays of every attempt of the study\n"
    "that the database shows queued or running in Slurm.  A runner still following the study on\n"
    "this host is told to stop (SIGTERM: it records its jobs as cancelled and\n"
    "submits nothing more); attempts whose runner is gone are recorded as\n"
    "cancelled here.  Cancelled jobs run again at the next 'cascade run'.\n";

struct victim {
    long long run_id;
    char slurm_id[32];
    char runner[320];
};

/* A runner id "host:pid:start" of a live process here: its pid, else 0. */
static int live_pid(const char *runner)
{
    if (sys_runner_alive(runner) != 1)
        return 0;
    const char *c = strchr(runner, ':');
    return c ? atoi(c + 1) : 0;
}

static int record_cancelled(sqlite3 *db, const struct victim *v, int n, struct err *e)
{
    int rc = db_begin(db, e);
    sqlite3_stmt *up = NULL, *del = NULL;
    if (!rc)
        rc = db_prepare(db,
                        "UPDATE runs SET status = 'cancelled', failure_class = NULL, "
                        "message = 'cancelled by cascade cancel', finished = ?2, "
                        "slurm_state = 'CANCELLED' WHERE id = ?1 AND status = 'running'",
                        &up, e);
    if (!rc)
        rc = db_prepare(db, "DELETE FROM leases WHERE run_id = ?1", &del, e);
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    for (int i = 0; i < n && !rc; i++) {
        if (live_pid(v[i].runner))
            continue;
        sqlite3_reset(up);
        sqlite3_bind_int64(up, 1, v[i].run_id);
        sqlite3_bind_text(up, 2, now, -1, SQLITE_STATIC);
        if (sqlite3_step(up) != SQLITE_DONE)
            rc = db_fail(db, e, "recording a cancel");
        sqlite3_reset(del);
        sqlite3_bind_int64(del, 1, v[i].run_id);
        if (!rc && sqlite3_step(del) != SQLITE_DONE)
            rc = db_fail(db, e, "dropping a lease");
    }
    sqlite3_finalize(up);
    sqlite3_finalize(del);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

int cmd_cancel(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL;
    int bad = cli_study_db_args(argc, argv, usage, &study, &db_path);
    if (bad)
        return bad;
    if (!study)
        return cli_usage_error(usage, "give a study name");
    struct err e = {0};
    sqlite3 *db = NULL;
    sqlite3_stmt *st = NULL;
    struct victim *v = NULL;
    int n = 0, cap = 0, known = 0;
    int rc = db_open(db_path, &db, &e);
    if (!rc)
        rc = db_prepare(db, "SELECT count(*) FROM studies WHERE name = ?1", &st, &e);
    if (!rc) {
        sqlite3_bind_text(st, 1, study, -1, SQLITE_STATIC);
        known = sqlite3_step(st) == SQLITE_ROW && sqlite3_column_int(st, 0) > 0;
        sqlite3_finalize(st);
        st = NULL;
        if (!known)
            rc = err_set(&e, ERR_INPUT, "no study '%s' in %s", study, db_path);
    }
    if (!rc)
        rc = db_prepare(db,
                        "SELECT r.id, r.slurm_job_id, coalesce(l.runner, '') FROM runs r "
                        "JOIN jobs j ON j.id = r.job_id JOIN studies s ON s.id = j.study_id "
                        "LEFT JOIN leases l ON l.run_id = r.id "
                        "WHERE s.name = ?1 AND r.status = 'running' "
                        "AND r.slurm_job_id IS NOT NULL ORDER BY r.id",
                        &st, &e);
    if (!rc) {
        sqlite3_bind_text(st, 1, study, -1, SQLITE_STATIC);
        while (sqlite3_step(st) == SQLITE_ROW) {
            if (n == cap) {
                cap = cap ? 2 * cap : 64;
                struct victim *g = realloc(v, (size_t)cap * sizeof *g);
                if (!g) {
                    rc = err_nomem(&e, "cancel");
                    break;
                }
                v = g;
            }
            v[n].run_id = sqlite3_column_int64(st, 0);
            snprintf(v[n].slurm_id, sizeof v[n].slurm_id, "%s", sqlite3_column_text(st, 1));
            snprintf(v[n].runner, sizeof v[n].runner, "%s", sqlite3_column_text(st, 2));
            n++;
        }
        sqlite3_finalize(st);
    }
    int live = 0;
    if (!rc && n) {
        struct slurm_cli cli;
        rc = slurm_cli_init(&cli, &e);
        /* whole arrays: a pending array task cancelled by its own id leaves
         * no record in Slurm, a cancelled array leaves one per task */
        const char **args = rc ? NULL : calloc((size_t)n + 1, sizeof *args);
        if (!rc && !args)
            rc = err_nomem(&e, "cancel");
        int na = 0;
        for (int i = 0; !rc && i < n; i++) {
            v[i].slurm_id[strcspn(v[i].slurm_id, "_")] = '\0';
            int dup = 0;
            for (int k = 0; k < na && !dup; k++)
                dup = strcmp(args[k], v[i].slurm_id) == 0;
            if (!dup)
                args[na++] = v[i].slurm_id;
        }
        char *out = NULL, why[512];
        int status = 0;
        if (!rc)
            rc = slurm_cli_run(&cli, SP_SCANCEL, args, &out, why, sizeof why, &status, &e);
        if (!rc && status != 0)
            /* ids Slurm forgot already are fine: their runs are recorded below */
            fprintf(stderr, "note: scancel: %s\n", why);
        free(out);
        free(args);
        slurm_cli_fini(&cli);
        /* live runners of the study stop and record their own */
        for (int i = 0; !rc && i < n; i++) {
            int pid = live_pid(v[i].runner);
            if (!pid)
                continue;
            live++;
            int first = 1;
            for (int k = 0; k < i; k++)
                first = first && strcmp(v[k].runner, v[i].runner) != 0;
            if (first)
                kill(pid, SIGTERM);
        }
        if (!rc)
            rc = record_cancelled(db, v, n, &e);
    }
    db_close(&db);
    free(v);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    if (!n)
        printf("study %s: nothing queued or running in Slurm\n", study);
    else
        printf("study %s: cancelled %d Slurm job%s (%d followed by a live runner, which records "
               "them)\n",
               study, n, n == 1 ? "" : "s", live);
    return 0;
}
