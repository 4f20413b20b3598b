/* export_ref: imported reference rows in cascade export (see export_ref.h). */
#include "export_ref.h"

#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "rdata_ref.h"
#include "table.h"
#include "util/mem.h"

int export_ref_metrics(sqlite3 *db, long long study_id, char ***names, char ***units, int *n,
                       struct err *e)
{
    if (!rdata_has_table(db, "imports"))
        return 0;
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT DISTINCT v.metric, v.unit FROM import_values v JOIN "
                            "import_rows r ON r.id = v.row_id JOIN imports i ON i.id = r.import_id "
                            "WHERE i.study_id = ?1 ORDER BY v.metric",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        const char *m = (const char *)sqlite3_column_text(st, 0);
        int have = 0;
        for (int k = 0; k < *n; k++)
            have |= strcmp((*names)[k], m) == 0;
        if (have)
            continue;
        char **gn = mem_realloc(*names, (size_t)(*n + 1) * sizeof *gn);
        if (gn)
            *names = gn;
        char **gu = gn ? mem_realloc(*units, (size_t)(*n + 1) * sizeof *gu) : NULL;
        if (gu)
            *units = gu;
        if (!gn || !gu) {
            rc = err_nomem(e, "metrics");
            break;
        }
        (*names)[*n] = mem_strdup(m);
        (*units)[*n] = mem_strdup((const char *)sqlite3_column_text(st, 1));
        (*n)++;
    }
    sqlite3_finalize(st);
    return rc;
}

int export_ref_rows(sqlite3 *db, long long study_id, char *const *axes, int naxes,
                    char *const *metrics, int nm, FILE *out, struct err *e)
{
    if (!rdata_has_table(db, "imports"))
        return 0;
    sqlite3_stmt *st = NULL, *ps = NULL, *vs = NULL;
    int rc = db_prepare(db, "SELECT r.id, i.source, r.line FROM import_rows r JOIN imports i ON "
                            "i.id = r.import_id WHERE i.study_id = ?1 ORDER BY i.source, r.id",
                        &st, e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM import_params WHERE row_id = ?1 AND name = ?2", &ps,
                        e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM import_values WHERE row_id = ?1 AND metric = ?2",
                        &vs, e);
    if (!rc) {
        sqlite3_bind_int64(st, 1, study_id);
        char cell[4096];
        while (sqlite3_step(st) == SQLITE_ROW) {
            long long row = sqlite3_column_int64(st, 0);
            /* key,kind,name,state,attempt,solver_version,solver_git,wall_s */
            fputs(",reference,", out);
            table_csv_field(out, (const char *)sqlite3_column_text(st, 1));
            fprintf(out, ",reference,%d,,,", sqlite3_column_int(st, 2));
            for (int a = 0; a < naxes; a++) {
                sqlite3_reset(ps);
                sqlite3_bind_int64(ps, 1, row);
                sqlite3_bind_text(ps, 2, axes[a], -1, SQLITE_STATIC);
                cell[0] = '\0';
                if (sqlite3_step(ps) == SQLITE_ROW)
                    table_cell(ps, 0, cell, sizeof cell);
                fputc(',', out);
                table_csv_field(out, cell);
            }
            for (int m = 0; m < nm; m++) {
                sqlite3_reset(vs);
                sqlite3_bind_int64(vs, 1, row);
                sqlite3_bind_text(vs, 2, metrics[m], -1, SQLITE_STATIC);
                cell[0] = '\0';
                if (sqlite3_step(vs) == SQLITE_ROW)
                    table_cell(vs, 0, cell, sizeof cell);
                fputc(',', out);
                table_csv_field(out, cell);
            }
            fputc('\n', out);
        }
    }
    sqlite3_finalize(st);
    sqlite3_finalize(ps);
    sqlite3_finalize(vs);
    return rc;
}
