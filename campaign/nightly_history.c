/* nightly_history: reading the history of a study (see nightly_history.h). */
#include "nightly_history.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "baseline.h"
#include "db.h"

void np_study_free(struct np_study *s)
{
    for (int i = 0; i < s->nnights; i++)
        json_decref(s->nights[i].dirs);
    free(s->nights);
    for (int i = 0; i < s->nent; i++) {
        struct np_entry *x = &s->ent[i];
        free(x->metric);
        free(x->what);
        free(x->point);
        free(x->unit);
        free(x->base);
        free(x->val);
        free(x->tol);
        free(x->verdict);
    }
    free(s->ent);
    memset(s, 0, sizeof *s);
}

static const char *col_text(sqlite3_stmt *st, int c)
{
    const char *t = (const char *)sqlite3_column_text(st, c);
    return t ? t : "";
}

static double col_real(sqlite3_stmt *st, int c)
{
    return sqlite3_column_type(st, c) == SQLITE_NULL ? NAN : sqlite3_column_double(st, c);
}

static struct np_entry *entry_of(struct np_study *s, const char *metric, const char *what,
                                 const char *point, const char *unit)
{
    for (int i = 0; i < s->nent; i++)
        if (strcmp(s->ent[i].metric, metric) == 0 && strcmp(s->ent[i].what, what) == 0 &&
            strcmp(s->ent[i].point, point) == 0)
            return &s->ent[i];
    if (s->nent == s->cap) {
        int cap = s->cap ? 2 * s->cap : 32;
        struct np_entry *g = realloc(s->ent, (size_t)cap * sizeof *g);
        if (!g)
            return NULL;
        s->ent = g;
        s->cap = cap;
    }
    struct np_entry *x = &s->ent[s->nent];
    memset(x, 0, sizeof *x);
    size_t n = (size_t)s->nnights;
    x->metric = strdup(metric);
    x->what = strdup(what);
    x->point = strdup(point);
    x->unit = strdup(unit);
    x->base = malloc(n * sizeof *x->base);
    x->val = malloc(n * sizeof *x->val);
    x->tol = malloc(n * sizeof *x->tol);
    x->verdict = malloc(n * sizeof *x->verdict);
    s->nent++;
    if (!x->metric || !x->what || !x->point || !x->unit || !x->base || !x->val || !x->tol ||
        !x->verdict)
        return NULL;
    for (size_t i = 0; i < n; i++) {
        x->base[i] = x->val[i] = x->tol[i] = NAN;
        x->verdict[i] = -1;
    }
    return x;
}

static int verdict_code(const char *name)
{
    for (int v = 0; cmp_verdict_names[v]; v++)
        if (strcmp(cmp_verdict_names[v], name) == 0)
            return v;
    return -1;
}

int np_study_load(sqlite3 *db, const char *name, int max_nights, struct np_study *s,
                      struct err *e)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name);
    sqlite3_stmt *st = NULL;
    int rc = db_prepare(db,
                        "SELECT c.id, c.checked, c.solver_git, c.solver_version, "
                        "coalesce(c.machine, ''), c.passed, c.compared, c.regressed, "
                        "EXISTS (SELECT 1 FROM regress_values v WHERE v.check_id = c.id) "
                        "FROM regress_checks c JOIN baselines b ON b.id = c.baseline_id "
                        "JOIN studies s ON s.id = b.study_id WHERE s.name = ?1 "
                        "ORDER BY c.checked DESC, c.id DESC LIMIT ?2",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 2, max_nights);
    int cap = 0;
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        if (s->nnights == cap) {
            cap = cap ? 2 * cap : 16;
            struct np_night *g = realloc(s->nights, (size_t)cap * sizeof *g);
            if (!g) {
                rc = err_nomem(e, "nightly page");
                break;
            }
            s->nights = g;
        }
        struct np_night *n = &s->nights[s->nnights++];
        memset(n, 0, sizeof *n);
        n->id = sqlite3_column_int64(st, 0);
        snprintf(n->checked, sizeof n->checked, "%s", col_text(st, 1));
        snprintf(n->git, sizeof n->git, "%s", col_text(st, 2));
        snprintf(n->version, sizeof n->version, "%s", col_text(st, 3));
        snprintf(n->machine, sizeof n->machine, "%s", col_text(st, 4));
        n->passed = sqlite3_column_int(st, 5);
        n->compared = sqlite3_column_int(st, 6);
        n->regressed = sqlite3_column_int(st, 7);
        n->recorded = sqlite3_column_int(st, 8);
        n->dirs = json_array();
    }
    sqlite3_finalize(st);
    /* oldest first */
    for (int i = 0, j = s->nnights - 1; i < j; i++, j--) {
        struct np_night t = s->nights[i];
        s->nights[i] = s->nights[j];
        s->nights[j] = t;
    }
    if (!rc)
        rc = db_prepare(db,
                        "SELECT metric, what, point, unit, baseline, value, tolerance, verdict, "
                        "run_dirs FROM regress_values WHERE check_id = ?1 ORDER BY seq",
                        &st, e);
    for (int k = 0; !rc && k < s->nnights; k++) {
        sqlite3_reset(st);
        sqlite3_bind_int64(st, 1, s->nights[k].id);
        while (!rc && sqlite3_step(st) == SQLITE_ROW) {
            struct np_entry *x = entry_of(s, col_text(st, 0), col_text(st, 1), col_text(st, 2),
                                          col_text(st, 3));
            if (!x) {
                rc = err_nomem(e, "nightly page");
                break;
            }
            x->base[k] = col_real(st, 4);
            x->val[k] = col_real(st, 5);
            x->tol[k] = col_real(st, 6);
            x->verdict[k] = verdict_code(col_text(st, 7));
            json_t *dirs = json_loads(col_text(st, 8), 0, NULL);
            size_t i;
            json_t *d;
            json_array_foreach(dirs, i, d)
            {
                int seen = 0;
                size_t j;
                json_t *o;
                json_array_foreach(s->nights[k].dirs, j, o) seen |= json_equal(o, d);
                if (!seen)
                    json_array_append(s->nights[k].dirs, d);
            }
            json_decref(dirs);
        }
    }
    sqlite3_finalize(st);
    if (rc)
        np_study_free(s);
    return rc;
}

int np_study_names(sqlite3 *db, const char *only, json_t *names, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT DISTINCT s.name FROM regress_checks c JOIN baselines b ON "
                            "b.id = c.baseline_id JOIN studies s ON s.id = b.study_id WHERE ?1 "
                            "IS NULL OR s.name = ?1 ORDER BY s.name",
                        &st, e);
    if (rc)
        return rc;
    if (only)
        sqlite3_bind_text(st, 1, only, -1, SQLITE_STATIC);
    while (sqlite3_step(st) == SQLITE_ROW)
        json_array_append_new(names, json_string(col_text(st, 0)));
    sqlite3_finalize(st);
    return 0;
}

int np_bad_verdict(int v)
{
    return v == CMP_REGRESSED || v == CMP_MISSING || v == CMP_FAILED;
}

double np_deviation(const struct np_entry *x, int k)
{
    double d = x->val[k] - x->base[k];
    if (!isfinite(d))
        return NAN;
    if (x->tol[k] > 0)
        return d / x->tol[k];
    return d == 0 ? 0 : d > 0 ? INFINITY : -INFINITY;
}

