/* rdata: reading a study's jobs and results for a report (see rdata.h). */
#include "rdata.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "util/mem.h"

/* A copy of a text column (NULL for NULL); *oom set when memory ran out. */
static char *dup_col(sqlite3_stmt *st, int col, int *oom)
{
    const unsigned char *t = sqlite3_column_text(st, col);
    char *c = t ? mem_strdup((const char *)t) : NULL;
    if (t && !c)
        *oom = 1;
    return c;
}

static int load_study(sqlite3 *db, const char *name, struct rdata *d, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT id, description, spec_path, spec_text FROM studies "
                            "WHERE name = ?1",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_ROW) {
        sqlite3_finalize(st);
        return err_set(e, ERR_INPUT, "no study named '%s' in the database (cascade status lists "
                                     "them; run it first with cascade run)",
                       name);
    }
    int oom = 0;
    d->study_id = sqlite3_column_int64(st, 0);
    snprintf(d->name, sizeof d->name, "%s", name);
    d->description = dup_col(st, 1, &oom);
    d->spec_path = dup_col(st, 2, &oom);
    d->spec_text = dup_col(st, 3, &oom);
    sqlite3_finalize(st);
    return oom ? err_nomem(e, "study") : 0;
}

static int load_axes(sqlite3 *db, struct rdata *d, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT name, grp, kind, vals FROM study_axes WHERE study_id = ?1 "
                            "ORDER BY position",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, d->study_id);
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        struct rd_axis *g = mem_realloc(d->axes, (size_t)(d->naxes + 1) * sizeof *g);
        if (!g) {
            rc = err_nomem(e, "axes");
            break;
        }
        d->axes = g;
        struct rd_axis *a = &d->axes[d->naxes];
        memset(a, 0, sizeof *a);
        snprintf(a->name, sizeof a->name, "%s", (const char *)sqlite3_column_text(st, 0));
        a->grp = sqlite3_column_int(st, 1);
        const char *kind = (const char *)sqlite3_column_text(st, 2);
        /* a swept seed is a repeat in all but name: results are averaged over it */
        a->repeat = strcmp(kind, "repeat") == 0 || strcmp(a->name, "seed") == 0;
        a->values = json_loads((const char *)sqlite3_column_text(st, 3), JSON_DECODE_ANY, NULL);
        if (!json_is_array(a->values)) {
            json_decref(a->values);
            rc = db_err(db, e, ERR_RUNTIME, "study_axes.vals of %s is not a JSON list", a->name);
            break;
        }
        d->naxes++;
    }
    sqlite3_finalize(st);
    return rc;
}

static int load_jobs(sqlite3 *db, struct rdata *d, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "SELECT j.id, j.key, j.kind, j.name, j.seq, j.params, j.state, r.attempt, "
                        "r.message, r.exit_code, r.signal FROM jobs j "
                        "LEFT JOIN runs r ON r.id = j.last_run_id "
                        "WHERE j.study_id = ?1 AND j.active = 1 ORDER BY j.seq",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, d->study_id);
    long cap = 0;
    int oom = 0;
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        if (d->njobs == cap) {
            cap = cap ? 2 * cap : 64;
            struct rd_job *g = mem_realloc(d->jobs, (size_t)cap * sizeof *g);
            if (!g) {
                rc = err_nomem(e, "jobs");
                break;
            }
            d->jobs = g;
        }
        struct rd_job *j = &d->jobs[d->njobs];
        memset(j, 0, sizeof *j);
        j->id = sqlite3_column_int64(st, 0);
        snprintf(j->key, sizeof j->key, "%s", (const char *)sqlite3_column_text(st, 1));
        j->prep = strcmp((const char *)sqlite3_column_text(st, 2), "prep") == 0;
        j->name = dup_col(st, 3, &oom);
        j->seq = (long)sqlite3_column_int64(st, 4);
        j->params = json_loads((const char *)sqlite3_column_text(st, 5), 0, NULL);
        if (!j->params)
            j->params = json_object();
        snprintf(j->state, sizeof j->state, "%s", (const char *)sqlite3_column_text(st, 6));
        j->attempt = sqlite3_column_type(st, 7) == SQLITE_NULL ? 0 : sqlite3_column_int(st, 7);
        j->message = dup_col(st, 8, &oom);
        j->exit_code = sqlite3_column_type(st, 9) == SQLITE_NULL ? -1 : sqlite3_column_int(st, 9);
        j->signal = sqlite3_column_type(st, 10) == SQLITE_NULL ? -1 : sqlite3_column_int(st, 10);
        d->njobs++;
        if (oom)
            rc = err_nomem(e, "jobs");
    }
    sqlite3_finalize(st);
    return rc;
}

struct id_index {
    long long id;
    long idx;
};

static int cmp_id(const void *a, const void *b)
{
    long long x = ((const struct id_index *)a)->id, y = ((const struct id_index *)b)->id;
    return x < y ? -1 : x > y;
}

/* The position of job `id` through an index sorted by id, or -1. */
static long find_job(const struct id_index *ix, long n, long long id)
{
    struct id_index key = {id, 0};
    const struct id_index *hit = bsearch(&key, ix, (size_t)n, sizeof *ix, cmp_id);
    return hit ? hit->idx : -1;
}

static int load_metrics(sqlite3 *db, struct rdata *d, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT DISTINCT metric, unit FROM results WHERE study = ?1 "
                            "ORDER BY metric",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, d->name, -1, SQLITE_STATIC);
    int oom = 0;
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        const char *m = (const char *)sqlite3_column_text(st, 0);
        if (rdata_metric(d, m) >= 0)
            continue;   /* two units for one metric: the first wins */
        char **gm = mem_realloc(d->metric, (size_t)(d->nmetrics + 1) * sizeof *gm);
        if (gm)
            d->metric = gm;
        char **gu = gm ? mem_realloc(d->unit, (size_t)(d->nmetrics + 1) * sizeof *gu) : NULL;
        if (gu)
            d->unit = gu;
        if (!gm || !gu) {
            rc = err_nomem(e, "metrics");
            break;
        }
        d->metric[d->nmetrics] = mem_strdup(m);
        d->unit[d->nmetrics] = dup_col(st, 1, &oom);
        d->nmetrics++;
        if (oom || !d->metric[d->nmetrics - 1])
            rc = err_nomem(e, "metrics");
    }
    sqlite3_finalize(st);
    for (long i = 0; !rc && i < d->njobs; i++) {
        d->jobs[i].val = mem_alloc((size_t)(d->nmetrics ? d->nmetrics : 1) * sizeof(double));
        if (!d->jobs[i].val)
            return err_nomem(e, "metric values");
        for (int m = 0; m < d->nmetrics; m++)
            d->jobs[i].val[m] = NAN;
    }
    if (rc || (rc = db_prepare(db,
                               "SELECT job_id, metric, value, solver_version || ' (' || "
                               "solver_git || ')' FROM results WHERE study = ?1",
                               &st, e)))
        return rc;
    struct id_index *ix = mem_alloc((size_t)(d->njobs ? d->njobs : 1) * sizeof *ix);
    if (!ix) {
        sqlite3_finalize(st);
        return err_nomem(e, "job index");
    }
    for (long i = 0; i < d->njobs; i++)
        ix[i] = (struct id_index){d->jobs[i].id, i};
    qsort(ix, (size_t)d->njobs, sizeof *ix, cmp_id);
    sqlite3_bind_text(st, 1, d->name, -1, SQLITE_STATIC);
    while (sqlite3_step(st) == SQLITE_ROW) {
        long j = find_job(ix, d->njobs, sqlite3_column_int64(st, 0));
        int m = rdata_metric(d, (const char *)sqlite3_column_text(st, 1));
        if (j < 0 || m < 0)
            continue;
        if (sqlite3_column_type(st, 2) != SQLITE_NULL)
            d->jobs[j].val[m] = sqlite3_column_double(st, 2);
        if (!d->jobs[j].solver)
            d->jobs[j].solver = dup_col(st, 3, &oom);
        if (oom)
            break;
    }
    sqlite3_finalize(st);
    free(ix);
    return oom ? err_nomem(e, "results") : 0;
}

int rdata_load(sqlite3 *db, const char *name, struct rdata *d, struct err *e)
{
    memset(d, 0, sizeof *d);
    int rc = load_study(db, name, d, e);
    if (!rc)
        rc = load_axes(db, d, e);
    if (!rc)
        rc = load_jobs(db, d, e);
    if (!rc)
        rc = load_metrics(db, d, e);
    if (rc)
        rdata_free(d);
    return rc;
}

void rdata_free(struct rdata *d)
{
    free(d->description);
    free(d->spec_path);
    free(d->spec_text);
    for (int a = 0; a < d->naxes; a++)
        json_decref(d->axes[a].values);
    free(d->axes);
    for (long i = 0; i < d->njobs; i++) {
        struct rd_job *j = &d->jobs[i];
        free(j->name);
        json_decref(j->params);
        free(j->message);
        free(j->solver);
        free(j->val);
    }
    free(d->jobs);
    for (int m = 0; m < d->nmetrics; m++) {
        free(d->metric[m]);
        free(d->unit[m]);
    }
    free(d->metric);
    free(d->unit);
    memset(d, 0, sizeof *d);
}

int rdata_metric(const struct rdata *d, const char *name)
{
    for (int m = 0; m < d->nmetrics; m++)
        if (strcmp(d->metric[m], name) == 0)
            return m;
    return -1;
}

int rdata_axis(const struct rdata *d, const char *name)
{
    for (int a = 0; a < d->naxes; a++)
        if (strcmp(d->axes[a].name, name) == 0)
            return a;
    return -1;
}

void rdata_order_metrics(struct rdata *d, const char *const *names, int n)
{
    int next = 0;
    for (int k = 0; k < n; k++) {
        int m = rdata_metric(d, names[k]);
        if (m < next)
            continue;   /* absent, or already placed */
        /* rotate m to position `next` in the name, unit and value columns */
        char *nm = d->metric[m], *un = d->unit[m];
        memmove(d->metric + next + 1, d->metric + next, (size_t)(m - next) * sizeof *d->metric);
        memmove(d->unit + next + 1, d->unit + next, (size_t)(m - next) * sizeof *d->unit);
        d->metric[next] = nm;
        d->unit[next] = un;
        for (long i = 0; i < d->njobs; i++) {
            double *v = d->jobs[i].val, x = v[m];
            memmove(v + next + 1, v + next, (size_t)(m - next) * sizeof *v);
            v[next] = x;
        }
        next++;
    }
}
