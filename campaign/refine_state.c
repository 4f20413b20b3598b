/* refine_state: the refine_groups table (see refine_state.h). */
#include "refine_state.h"

#include <math.h>
#include <string.h>

#include "db.h"
#include "rdata_ref.h"
#include "report_json.h"
#include "study_analysis.h"
#include "sysinfo.h"

static void bind_num(sqlite3_stmt *st, int i, double x)
{
    if (isfinite(x))
        sqlite3_bind_double(st, i, x);
    else
        sqlite3_bind_null(st, i);
}

int refine_state_write(sqlite3 *db, long long study_id, const struct refine_row *rows, int n,
                       struct err *e)
{
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    int rc = db_begin(db, e);
    if (rc)
        return rc;
    char sql[128];
    snprintf(sql, sizeof sql, "DELETE FROM refine_groups WHERE study_id = %lld", study_id);
    rc = db_exec(db, sql, e);
    sqlite3_stmt *st = NULL;
    if (!rc)
        rc = db_prepare(db,
                        "INSERT INTO refine_groups (study_id, metric, series, axis, levels, finest, "
                        "value, phi_ext, gci_fine, band, asymptotic, state, reason, spent_core_s, "
                        "next_core_s, updated) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, "
                        "?11, ?12, ?13, ?14, ?15, ?16)",
                        &st, e);
    for (int i = 0; i < n && !rc; i++) {
        const struct refine_row *r = &rows[i];
        sqlite3_bind_int64(st, 1, study_id);
        sqlite3_bind_text(st, 2, r->metric, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, r->series, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 4, r->axis, -1, SQLITE_STATIC);
        sqlite3_bind_int(st, 5, r->levels);
        sqlite3_bind_text(st, 6, r->finest, -1, SQLITE_STATIC);
        bind_num(st, 7, r->value);
        bind_num(st, 8, r->phi_ext);
        bind_num(st, 9, r->gci);
        bind_num(st, 10, r->band);
        bind_num(st, 11, r->asymptotic);
        sqlite3_bind_text(st, 12, r->state, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 13, r->reason, -1, SQLITE_STATIC);
        bind_num(st, 14, r->spent_core_s);
        bind_num(st, 15, r->next_core_s);
        sqlite3_bind_text(st, 16, now, -1, SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE)
            rc = db_fail(db, e, "recording the refinement state");
        sqlite3_reset(st);
    }
    sqlite3_finalize(st);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

static json_t *col_num(sqlite3_stmt *st, int i)
{
    return sqlite3_column_type(st, i) == SQLITE_NULL ? json_null()
                                                     : report_json_num(sqlite3_column_double(st, i));
}

int refine_state_json(sqlite3 *db, long long study_id, json_t **out, struct err *e)
{
    *out = json_array();
    if (!rdata_has_table(db, "refine_groups"))
        return 0;
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "SELECT metric, series, axis, levels, finest, value, phi_ext, gci_fine, "
                        "band, asymptotic, state, reason, spent_core_s, next_core_s, updated FROM "
                        "refine_groups WHERE study_id = ?1 ORDER BY metric, series",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    while (sqlite3_step(st) == SQLITE_ROW) {
        json_t *series = json_loads((const char *)sqlite3_column_text(st, 1), 0, NULL);
        json_t *finest = json_loads((const char *)sqlite3_column_text(st, 4), JSON_DECODE_ANY, NULL);
        json_t *o = json_object();
        json_object_set_new(o, "metric", json_string((const char *)sqlite3_column_text(st, 0)));
        json_object_set_new(o, "series", series ? series : json_object());
        json_object_set_new(o, "axis", json_string((const char *)sqlite3_column_text(st, 2)));
        json_object_set_new(o, "levels", json_integer(sqlite3_column_int(st, 3)));
        json_object_set_new(o, "finest", finest ? finest : json_null());
        json_object_set_new(o, "value", col_num(st, 5));
        json_object_set_new(o, "phi_ext", col_num(st, 6));
        json_object_set_new(o, "gci_fine", col_num(st, 7));
        json_object_set_new(o, "band", col_num(st, 8));
        json_object_set_new(o, "asymptotic", col_num(st, 9));
        json_object_set_new(o, "state", json_string((const char *)sqlite3_column_text(st, 10)));
        json_object_set_new(o, "reason", json_string((const char *)sqlite3_column_text(st, 11)));
        json_object_set_new(o, "spent_core_s", col_num(st, 12));
        json_object_set_new(o, "next_core_s", col_num(st, 13));
        json_object_set_new(o, "updated", json_string((const char *)sqlite3_column_text(st, 14)));
        json_array_append_new(*out, o);
    }
    sqlite3_finalize(st);
    return 0;
}

int refine_state_print(sqlite3 *db, long long study_id, FILE *out, struct err *e)
{
    json_t *rows = NULL;
    int rc = refine_state_json(db, study_id, &rows, e);
    if (rc || json_array_size(rows) == 0) {
        json_decref(rows);
        return rc;
    }
    fprintf(out, "\nadaptive refinement along %s:\n",
            json_string_value(json_object_get(json_array_get(rows, 0), "axis")));
    fprintf(out, "  %-20s %-30s %6s %-10s %-12s %-10s %s\n", "metric", "series", "levels",
            "finest", "GCI fine", "state", "why");
    size_t i;
    json_t *r;
    json_array_foreach(rows, i, r)
    {
        char series[SA_LABEL_MAX], finest[64], gci[32];
        sa_params_label(json_object_get(r, "series"), series, sizeof series);
        const json_t *fv = json_object_get(r, "finest");
        if (json_is_number(fv)) {
            snprintf(finest, sizeof finest, "%.6g", json_number_value(fv));
        } else {
            char *f = json_dumps(fv, JSON_COMPACT | JSON_ENCODE_ANY);
            snprintf(finest, sizeof finest, "%s", f ? f : "?");
            free(f);
        }
        json_t *g = json_object_get(r, "gci_fine");
        if (json_is_number(g))
            snprintf(gci, sizeof gci, "%#.4g %%", 100 * json_number_value(g));
        else
            snprintf(gci, sizeof gci, "—");
        fprintf(out, "  %-20s %-30s %6lld %-10s %-12s %-10s %s\n",
                json_string_value(json_object_get(r, "metric")), series,
                (long long)json_integer_value(json_object_get(r, "levels")), finest, gci,
                json_string_value(json_object_get(r, "state")),
                json_string_value(json_object_get(r, "reason")));
    }
    json_decref(rows);
    return 0;
}
