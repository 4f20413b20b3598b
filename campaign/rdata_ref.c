/* rdata_ref: imported reference rows for reports (see rdata_ref.h). */
#include "rdata_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "report_json.h"
#include "resolution.h"
#include "util/mem.h"

int rdata_has_table(sqlite3 *db, const char *name)
{
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM sqlite_master WHERE type IN ('table', 'view') AND "
                               "name = ?1",
                           -1, &st, NULL) != SQLITE_OK)
        return 0;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    int has = sqlite3_step(st) == SQLITE_ROW;
    sqlite3_finalize(st);
    return has;
}

int rdata_sources(sqlite3 *db, long long study_id, json_t **names, struct err *e)
{
    *names = json_array();
    if (!rdata_has_table(db, "imports"))
        return 0;
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT source FROM imports WHERE study_id = ?1 ORDER BY source", &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    while (sqlite3_step(st) == SQLITE_ROW)
        json_array_append_new(*names, json_string((const char *)sqlite3_column_text(st, 0)));
    sqlite3_finalize(st);
    return 0;
}

static void free_jobs(struct rdata *d)
{
    for (long i = 0; i < d->njobs; i++) {
        struct rd_job *j = &d->jobs[i];
        free(j->name);
        json_decref(j->params);
        free(j->message);
        free(j->solver);
        free(j->val);
    }
    free(d->jobs);
    d->jobs = NULL;
    d->njobs = 0;
    for (int m = 0; m < d->nmetrics; m++) {
        free(d->metric[m]);
        free(d->unit[m]);
    }
    free(d->metric);
    free(d->unit);
    d->metric = d->unit = NULL;
    d->nmetrics = 0;
}

static int add_metric(struct rdata *d, const char *name, const char *unit)
{
    char **gm = mem_realloc(d->metric, (size_t)(d->nmetrics + 1) * sizeof *gm);
    if (!gm)
        return -1;
    d->metric = gm;
    char **gu = mem_realloc(d->unit, (size_t)(d->nmetrics + 1) * sizeof *gu);
    if (!gu)
        return -1;
    d->unit = gu;
    d->metric[d->nmetrics] = mem_strdup(name);
    d->unit[d->nmetrics] = mem_strdup(unit);
    d->nmetrics++;
    return 0;
}

int rdata_use_source(sqlite3 *db, struct rdata *d, const char *source, struct err *e)
{
    if (!rdata_has_table(db, "imports"))
        return err_set(e, ERR_INPUT, "study %s has no imported source '%s' (cascade import)",
                       d->name, source);
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT id FROM imports WHERE study_id = ?1 AND source = ?2", &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, d->study_id);
    sqlite3_bind_text(st, 2, source, -1, SQLITE_STATIC);
    long long import_id = sqlite3_step(st) == SQLITE_ROW ? sqlite3_column_int64(st, 0) : 0;
    sqlite3_finalize(st);
    if (!import_id) {
        json_t *names = NULL;
        rdata_sources(db, d->study_id, &names, e);
        char *list = json_dumps(names, JSON_COMPACT);
        rc = err_set(e, ERR_INPUT, "study %s has no imported source '%s' (it has %s)", d->name,
                     source, json_array_size(names) ? list : "none: cascade import adds one");
        free(list);
        json_decref(names);
        return rc;
    }
    free_jobs(d);
    if ((rc = db_prepare(db, "SELECT DISTINCT v.metric, v.unit FROM import_values v JOIN "
                             "import_rows r ON r.id = v.row_id WHERE r.import_id = ?1 ORDER BY "
                             "v.metric",
                         &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, import_id);
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        const char *m = (const char *)sqlite3_column_text(st, 0);
        if (rdata_metric(d, m) < 0 && add_metric(d, m, (const char *)sqlite3_column_text(st, 1)))
            rc = err_nomem(e, "metrics");
    }
    sqlite3_finalize(st);
    if (rc || (rc = db_prepare(db, "SELECT id, line, params FROM import_rows WHERE import_id = ?1 "
                                   "ORDER BY id",
                               &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, import_id);
    long cap = 0;
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        if (d->njobs == cap) {
            cap = cap ? 2 * cap : 16;
            struct rd_job *g = mem_realloc(d->jobs, (size_t)cap * sizeof *g);
            if (!g) {
                rc = err_nomem(e, "rows");
                break;
            }
            d->jobs = g;
        }
        struct rd_job *j = &d->jobs[d->njobs];
        memset(j, 0, sizeof *j);
        j->id = sqlite3_column_int64(st, 0);
        snprintf(j->key, sizeof j->key, "line-%d", sqlite3_column_int(st, 1));
        j->seq = d->njobs;
        j->params = json_loads((const char *)sqlite3_column_text(st, 2), 0, NULL);
        if (!j->params)
            j->params = json_object();
        snprintf(j->state, sizeof j->state, "done");
        j->attempt = 1;
        j->exit_code = j->signal = -1;
        size_t n = strlen(source) + 16;
        j->solver = mem_alloc(n);
        j->val = mem_alloc((size_t)(d->nmetrics ? d->nmetrics : 1) * sizeof *j->val);
        if (!j->solver || !j->val) {
            free(j->solver);
            free(j->val);
            json_decref(j->params);
            rc = err_nomem(e, "rows");
            break;
        }
        snprintf(j->solver, n, "reference: %s", source);
        for (int m = 0; m < d->nmetrics; m++)
            j->val[m] = NAN;
        d->njobs++;
    }
    sqlite3_finalize(st);
    if (rc || (rc = db_prepare(db, "SELECT v.row_id, v.metric, v.value FROM import_values v JOIN "
                                   "import_rows r ON r.id = v.row_id WHERE r.import_id = ?1",
                               &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, import_id);
    while (sqlite3_step(st) == SQLITE_ROW) {
        long long row = sqlite3_column_int64(st, 0);
        int m = rdata_metric(d, (const char *)sqlite3_column_text(st, 1));
        for (long i = 0; m >= 0 && i < d->njobs; i++)
            if (d->jobs[i].id == row && sqlite3_column_type(st, 2) != SQLITE_NULL)
                d->jobs[i].val[m] = sqlite3_column_double(st, 2);
    }
    sqlite3_finalize(st);
    return 0;
}

int rdata_ref_rows(sqlite3 *db, long long study_id, json_t **rows, struct err *e)
{
    *rows = json_array();
    if (!rdata_has_table(db, "imports"))
        return 0;
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT i.source, r.line, r.params, v.metric, v.unit, v.value FROM "
                            "import_values v JOIN import_rows r ON r.id = v.row_id JOIN imports i "
                            "ON i.id = r.import_id WHERE i.study_id = ?1 ORDER BY i.source, r.id, "
                            "v.metric",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    while (sqlite3_step(st) == SQLITE_ROW) {
        json_t *params = json_loads((const char *)sqlite3_column_text(st, 2), 0, NULL);
        json_t *o = json_pack("{s:s, s:i, s:o, s:s, s:s}", "source",
                              (const char *)sqlite3_column_text(st, 0), "line",
                              sqlite3_column_int(st, 1), "params", params ? params : json_object(),
                              "metric", (const char *)sqlite3_column_text(st, 3), "unit",
                              (const char *)sqlite3_column_text(st, 4));
        if (!o)
            continue;
        json_object_set_new(o, "value", sqlite3_column_type(st, 5) == SQLITE_NULL
                                            ? json_null()
                                            : report_json_num(sqlite3_column_double(st, 5)));
        json_array_append_new(*rows, o);
    }
    sqlite3_finalize(st);
    return 0;
}

/* Equal parameter values: numbers by value (2 and 2.0 alike), the rest by
 * their JSON text. */
static int same_value(const json_t *a, const json_t *b)
{
    double x = res_number(a), y = res_number(b);
    if (isfinite(x) || isfinite(y))
        return x == y;
    return json_equal((json_t *)a, (json_t *)b);
}

static int point_matches(const struct sa_point *pt, const json_t *params)
{
    if (json_object_size(pt->params) != json_object_size(params))
        return 0;
    const char *k;
    json_t *v;
    json_object_foreach((json_t *)pt->params, k, v)
    {
        json_t *w = json_object_get(params, k);
        if (!w || !same_value(v, w))
            return 0;
    }
    return 1;
}

void rdata_ref_compare(json_t *rows, const struct study_analysis *a)
{
    size_t i;
    json_t *row;
    json_array_foreach(rows, i, row)
    {
        const json_t *params = json_object_get(row, "params");
        int m = rdata_metric(a->d, json_string_value(json_object_get(row, "metric")));
        double camp = NAN;
        for (int p = 0; m >= 0 && p < a->npts; p++)
            if (point_matches(&a->pts[p], params))
                camp = a->pts[p].mean[m];
        double ref = json_number_value(json_object_get(row, "value"));
        int have = isfinite(camp) && json_is_number(json_object_get(row, "value"));
        json_object_set_new(row, "campaign", report_json_num(camp));
        json_object_set_new(row, "diff", have ? report_json_num(camp - ref) : json_null());
        json_object_set_new(row, "rel", have && ref != 0 ? report_json_num((camp - ref) / fabs(ref))
                                                         : json_null());
    }
}
