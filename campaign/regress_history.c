/* regress_history: recording every entry of a regression check (see
 * regress_history.h). */
#include "regress_history.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "baseline_db.h"
#include "db.h"
#include "sysinfo.h"
#include "util/canon.h"

/* The attempt directory of a job's latest successful run (absolute when it
 * still exists), appended to `dirs`. */
static void add_run_dir(sqlite3_stmt *q, long long job_id, json_t *dirs)
{
    sqlite3_reset(q);
    sqlite3_bind_int64(q, 1, job_id);
    if (sqlite3_step(q) != SQLITE_ROW || sqlite3_column_type(q, 0) == SQLITE_NULL)
        return;
    const char *d = (const char *)sqlite3_column_text(q, 0);
    char abs[PATH_MAX];
    json_array_append_new(dirs, json_string(realpath(d, abs) ? abs : d));
}

/* The run directories behind an entry: the jobs of the point a value was
 * averaged over, or the job that did not succeed; none for an order (it
 * comes from a whole series). */
static json_t *run_dirs_of(const struct cmp_item *it, const struct study_analysis *a,
                           sqlite3_stmt *q)
{
    json_t *dirs = json_array();
    if (strcmp(it->what, "value") == 0) {
        for (int p = 0; p < a->npts; p++)
            if (strcmp(a->pts[p].label, it->where) == 0) {
                for (int k = 0; k < a->pts[p].njobs; k++)
                    add_run_dir(q, a->d->jobs[a->pts[p].jobs[k]].id, dirs);
                break;
            }
    } else if (strcmp(it->what, "job") == 0) {
        for (long j = 0; j < a->d->njobs; j++)
            if (strncmp(it->where, a->d->jobs[j].key, strlen(a->d->jobs[j].key)) == 0) {
                add_run_dir(q, a->d->jobs[j].id, dirs);
                break;
            }
    }
    return dirs;
}

static const char *unit_of(const struct cmp_item *it, const struct study_analysis *a)
{
    /* a value, and the value a refined series converged at, carry the
     * metric's unit; an order or a level is a pure number */
    if (strcmp(it->what, "value") != 0 && strcmp(it->what, "converged") != 0)
        return "1";
    int m = rdata_metric(a->d, it->metric);
    return m >= 0 && a->d->unit[m] ? a->d->unit[m] : "1";
}

static void bind_real(sqlite3_stmt *st, int col, double x)
{
    if (isfinite(x))
        sqlite3_bind_double(st, col, x);
    else
        sqlite3_bind_null(st, col);
}

static int insert_values(sqlite3 *db, long long check_id, const struct cmp_report *r,
                         const struct study_analysis *a, struct err *e)
{
    sqlite3_stmt *ins = NULL, *dir = NULL;
    int rc = db_prepare(db, "INSERT INTO regress_values (check_id, seq, metric, what, point, unit, "
                            "baseline, value, tolerance, verdict, run_dirs, note) VALUES (?1, ?2, "
                            "?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)",
                        &ins, e);
    if (!rc)
        rc = db_prepare(db, "SELECT run_dir FROM runs WHERE job_id = ?1 AND status = 'done' "
                            "ORDER BY attempt DESC LIMIT 1",
                        &dir, e);
    for (int i = 0; i < r->n && !rc; i++) {
        const struct cmp_item *it = &r->it[i];
        json_t *dirs = run_dirs_of(it, a, dir);
        char *dtext = canon_json(dirs);
        json_decref(dirs);
        sqlite3_reset(ins);
        sqlite3_bind_int64(ins, 1, check_id);
        sqlite3_bind_int(ins, 2, i);
        sqlite3_bind_text(ins, 3, it->metric, -1, SQLITE_STATIC);
        sqlite3_bind_text(ins, 4, it->what, -1, SQLITE_STATIC);
        sqlite3_bind_text(ins, 5, it->where, -1, SQLITE_STATIC);
        sqlite3_bind_text(ins, 6, unit_of(it, a), -1, SQLITE_TRANSIENT);
        bind_real(ins, 7, it->base);
        bind_real(ins, 8, it->now);
        bind_real(ins, 9, it->tol);
        sqlite3_bind_text(ins, 10, cmp_verdict_names[it->verdict], -1, SQLITE_STATIC);
        sqlite3_bind_text(ins, 11, dtext ? dtext : "[]", -1, SQLITE_TRANSIENT);
        sqlite3_bind_text(ins, 12, it->note, -1, SQLITE_STATIC);
        free(dtext);
        if (sqlite3_step(ins) != SQLITE_DONE)
            rc = db_fail(db, e, "recording the regression history");
    }
    sqlite3_finalize(ins);
    sqlite3_finalize(dir);
    return rc;
}

int regress_history_record(sqlite3 *db, long long baseline_id, const char *solver,
                           const struct cmp_report *r, const struct study_analysis *a,
                           struct err *e)
{
    int rc = db_begin(db, e);
    if (rc)
        return rc;
    rc = baseline_db_check(db, baseline_id, solver, r, e);
    long long check_id = sqlite3_last_insert_rowid(db);   /* the row just inserted */
    sqlite3_stmt *st = NULL;
    if (!rc)
        rc = db_prepare(db, "UPDATE regress_checks SET machine = ?2 WHERE id = ?1", &st, e);
    if (!rc) {
        char host[256];
        sys_hostname(host, sizeof host);
        sqlite3_bind_int64(st, 1, check_id);
        sqlite3_bind_text(st, 2, host, -1, SQLITE_TRANSIENT);
        if (sqlite3_step(st) != SQLITE_DONE)
            rc = db_fail(db, e, "recording the machine of a regression check");
    }
    sqlite3_finalize(st);
    if (!rc)
        rc = insert_values(db, check_id, r, a, e);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}
