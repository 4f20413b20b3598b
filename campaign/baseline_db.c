/* baseline_db: recording baselines and checks (see baseline_db.h). */
#include "baseline_db.h"

#include <stdlib.h>
#include <string.h>

#include "build_info.h"
#include "db.h"
#include "sysinfo.h"
#include "util/canon.h"
#include "util/sha256.h"

static int insert_values(sqlite3 *db, long long id, const json_t *b, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "INSERT OR REPLACE INTO baseline_values (baseline_id, metric, quantity, "
                            "params, value, unit) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                        &st, e);
    if (rc)
        return rc;
    static const char *const lists[2] = {"values", "orders"};
    for (int l = 0; l < 2 && !rc; l++) {
        size_t i;
        json_t *v;
        json_array_foreach(json_object_get(b, lists[l]), i, v)
        {
            char *params = canon_json(json_object_get(v, l ? "group" : "params"));
            const char *unit = l ? "1" : json_string_value(json_object_get(v, "unit"));
            sqlite3_reset(st);
            sqlite3_bind_int64(st, 1, id);
            sqlite3_bind_text(st, 2, json_string_value(json_object_get(v, "metric")), -1,
                              SQLITE_TRANSIENT);
            sqlite3_bind_text(st, 3, l ? "order" : "value", -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 4, params ? params : "{}", -1, SQLITE_TRANSIENT);
            sqlite3_bind_double(st, 5, json_number_value(json_object_get(v, l ? "p" : "value")));
            sqlite3_bind_text(st, 6, unit ? unit : "1", -1, SQLITE_TRANSIENT);
            free(params);
            if (sqlite3_step(st) != SQLITE_DONE) {
                rc = db_fail(db, e, "recording baseline values");
                break;
            }
        }
    }
    sqlite3_finalize(st);
    return rc;
}

int baseline_db_record(sqlite3 *db, long long study_id, const char *path, const char *text,
                       const json_t *b, long long *id, struct err *e)
{
    char hash[65], now[40];
    sha256_hex(text, strlen(text), hash);
    sys_iso_time(sys_now(), now, sizeof now);
    const json_t *sv = json_object_get(b, "solver");
    const char *ver = json_string_value(json_object_get(sv, "version"));
    const char *git = json_string_value(json_object_get(sv, "git"));
    const char *created = json_string_value(json_object_get(b, "created"));
    int rc = db_begin(db, e);
    if (rc)
        return rc;
    sqlite3_stmt *st = NULL;
    rc = db_prepare(db, "SELECT id FROM baselines WHERE study_id = ?1 AND sha256 = ?2", &st, e);
    int found = 0;
    if (!rc) {
        sqlite3_bind_int64(st, 1, study_id);
        sqlite3_bind_text(st, 2, hash, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW) {
            *id = sqlite3_column_int64(st, 0);
            found = 1;
        }
        sqlite3_finalize(st);
    }
    if (!rc && found) {
        rc = db_prepare(db, "UPDATE baselines SET path = ?2 WHERE id = ?1", &st, e);
        if (!rc) {
            sqlite3_bind_int64(st, 1, *id);
            sqlite3_bind_text(st, 2, path, -1, SQLITE_STATIC);
            if (sqlite3_step(st) != SQLITE_DONE)
                rc = db_fail(db, e, "updating a baseline");
            sqlite3_finalize(st);
        }
    } else if (!rc) {
        rc = db_prepare(db, "INSERT INTO baselines (study_id, path, sha256, content, solver_version, "
                            "solver_git, created, recorded) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
                        &st, e);
        if (!rc) {
            sqlite3_bind_int64(st, 1, study_id);
            sqlite3_bind_text(st, 2, path, -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 3, hash, -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 4, text, -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 5, ver ? ver : "unknown", -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 6, git ? git : "unknown", -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 7, created ? created : now, -1, SQLITE_STATIC);
            sqlite3_bind_text(st, 8, now, -1, SQLITE_STATIC);
            if (sqlite3_step(st) != SQLITE_DONE)
                rc = db_fail(db, e, "recording a baseline");
            *id = sqlite3_last_insert_rowid(db);
            sqlite3_finalize(st);
        }
        if (!rc)
            rc = insert_values(db, *id, b, e);
    }
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

int baseline_db_check(sqlite3 *db, long long baseline_id, const char *solver,
                      const struct cmp_report *r, struct err *e)
{
    char now[40], ver[128], git[128];
    sys_iso_time(sys_now(), now, sizeof now);
    baseline_split_solver(solver, ver, sizeof ver, git, sizeof git);
    json_t *diff = cmp_failures_json(r);
    char *text = canon_json(diff);
    json_decref(diff);
    sqlite3_stmt *st;
    int rc = db_prepare(db, "INSERT INTO regress_checks (baseline_id, checked, solver_version, "
                            "solver_git, cascade, compared, regressed, passed, diff) "
                            "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                        &st, e);
    if (!rc) {
        sqlite3_bind_int64(st, 1, baseline_id);
        sqlite3_bind_text(st, 2, now, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, ver, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 4, git, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 5, CASCADE_VERSION " (" CASCADE_GIT_HASH ")", -1, SQLITE_STATIC);
        sqlite3_bind_int(st, 6, r->compared);
        sqlite3_bind_int(st, 7, r->regressed);
        sqlite3_bind_int(st, 8, r->regressed == 0);
        sqlite3_bind_text(st, 9, text ? text : "[]", -1, SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE)
            rc = db_fail(db, e, "recording a regression check");
        sqlite3_finalize(st);
    }
    free(text);
    return rc;
}
