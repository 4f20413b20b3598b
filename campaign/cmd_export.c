/* cascade export: a study as one CSV row per job. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "export_ref.h"
#include "table.h"
#include "util/mem.h"
#include "util/wfile.h"

static const char *usage =
    "usage: cascade export STUDY --csv [--db FILE] [--out FILE]\n"
    "\n"
    "Writes one CSV row per job of the study: key, kind, name, state, attempt,\n"
    "solver version and git hash, wall seconds, then one column per swept\n"
    "parameter (in the study's order) and one per metric, named 'metric [unit]',\n"
    "from each job's latest successful run (empty when it has none).  Reference\n"
    "values imported with cascade import follow as rows of kind 'reference' (name:\n"
    "the source; attempt: the line of the imported file).\n";

struct metric_col {
    char *name;
    char *unit;
};

int cmd_export(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL, *out_path = NULL;
    int csv = 0;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "--out", &out_path))) {
            if (m < 0)
                return 2;
        } else if (strcmp(argv[i], "--csv") == 0) {
            csv = 1;
        } else if (argv[i][0] != '-' && !study) {
            study = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!study)
        return cli_usage_error(usage, "give a study name");
    if (!csv)
        return cli_usage_error(usage, "give the format: --csv");
    struct err e = {0};
    sqlite3 *db = NULL;
    int rc = db_open_readonly(db_path, &db, &e);
    sqlite3_stmt *st = NULL, *ps = NULL, *ms = NULL;
    long long sid = 0;
    char **axes = NULL;
    int naxes = 0;
    struct metric_col *mc = NULL;
    int nm = 0;
    FILE *out = stdout;
    struct wfile wf = {0};   /* --out: written to FILE.tmp, renamed when complete */
    if (!rc)
        rc = db_prepare(db, "SELECT id FROM studies WHERE name = ?1", &st, &e);
    if (!rc) {
        sqlite3_bind_text(st, 1, study, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW)
            sid = sqlite3_column_int64(st, 0);
        else
            rc = err_set(&e, ERR_INPUT, "no study named '%s' in %s", study, db_path);
        sqlite3_finalize(st);
        st = NULL;
    }
    if (!rc)
        rc = db_prepare(db, "SELECT name FROM study_axes WHERE study_id = ?1 ORDER BY position",
                        &st, &e);
    if (!rc) {
        sqlite3_bind_int64(st, 1, sid);
        while (!rc && sqlite3_step(st) == SQLITE_ROW) {
            char **g = mem_realloc(axes, (size_t)(naxes + 1) * sizeof *g);
            if (g)
                axes = g;
            const char *name = (const char *)sqlite3_column_text(st, 0);
            if (!g || !(axes[naxes] = mem_strdup(name ? name : "")))
                rc = err_nomem(&e, "the parameter columns");
            else
                naxes++;
        }
        sqlite3_finalize(st);
        st = NULL;
        if (!rc)
            rc = db_prepare(db,
                        "SELECT DISTINCT metric, unit FROM results WHERE study = ?1 "
                        "ORDER BY metric",
                        &st, &e);
    }
    if (!rc) {
        sqlite3_bind_text(st, 1, study, -1, SQLITE_STATIC);
        while (!rc && sqlite3_step(st) == SQLITE_ROW) {
            struct metric_col *g = mem_realloc(mc, (size_t)(nm + 1) * sizeof *g);
            if (!g) {
                rc = err_nomem(&e, "the metric columns");
                break;
            }
            mc = g;
            const char *mname = (const char *)sqlite3_column_text(st, 0);
            const char *munit = (const char *)sqlite3_column_text(st, 1);
            mc[nm].name = mem_strdup(mname ? mname : "");
            mc[nm].unit = mem_strdup(munit ? munit : "");
            nm++;
            if (!mc[nm - 1].name || !mc[nm - 1].unit)
                rc = err_nomem(&e, "the metric columns");
        }
        sqlite3_finalize(st);
        st = NULL;
    }
    char **rnames = NULL, **runits = NULL;   /* the metric columns, with the imported ones */
    int nr = 0;
    for (int m = 0; !rc && m < nm; m++) {
        char **gn = mem_realloc(rnames, (size_t)(nr + 1) * sizeof *gn);
        char **gu = gn ? mem_realloc(runits, (size_t)(nr + 1) * sizeof *gu) : NULL;
        if (gn)
            rnames = gn;
        if (gu)
            runits = gu;
        if (!gn || !gu) {
            rc = err_nomem(&e, "metrics");
            break;
        }
        rnames[nr] = mem_strdup(mc[m].name);
        runits[nr++] = mem_strdup(mc[m].unit);
        if (!rnames[nr - 1] || !runits[nr - 1])
            rc = err_nomem(&e, "metrics");
    }
    if (!rc)
        rc = export_ref_metrics(db, sid, &rnames, &runits, &nr, &e);
    if (!rc && out_path) {
        /* a --out that names no place to write is the user's argument (exit
         * 2); a full disk is not */
        if (wfile_open(&wf, out_path, &e) != 0) {
            int bad_path = errno == ENOENT || errno == ENOTDIR || errno == EACCES ||
                           errno == EISDIR || errno == EROFS || errno == ENAMETOOLONG;
            rc = e.code = bad_path ? ERR_INPUT : ERR_RUNTIME;
        }
        out = wf.f;
    }
    if (!rc)
        rc = db_prepare(db,
                        "SELECT j.id, j.key, j.kind, coalesce(j.name, ''), j.state, d.id, "
                        "d.attempt, d.solver_version, d.solver_git, d.wall_s FROM jobs j "
                        "LEFT JOIN runs d ON d.job_id = j.id AND d.status = 'done' AND d.attempt = "
                        "(SELECT max(x.attempt) FROM runs x WHERE x.job_id = j.id AND "
                        "x.status = 'done') WHERE j.study_id = ?1 AND j.active = 1 ORDER BY j.seq",
                        &st, &e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM job_params WHERE job_id = ?1 AND name = ?2", &ps, &e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM metrics WHERE run_id = ?1 AND name = ?2", &ms, &e);
    if (!rc) {
        fputs("key,kind,name,state,attempt,solver_version,solver_git,wall_s", out);
        for (int a = 0; a < naxes; a++) {
            fputc(',', out);
            table_csv_field(out, axes[a]);
        }
        for (int m = 0; m < nr; m++) {
            char h[512];
            snprintf(h, sizeof h, "%s [%s]", rnames[m], runits[m]);
            fputc(',', out);
            table_csv_field(out, h);
        }
        fputc('\n', out);
        sqlite3_bind_int64(st, 1, sid);
        char cell[4096];
        while (sqlite3_step(st) == SQLITE_ROW) {
            long long jid = sqlite3_column_int64(st, 0);
            long long run = sqlite3_column_int64(st, 5);
            for (int c = 1; c <= 9; c++) {
                if (c == 5)
                    continue;
                table_cell(st, c, cell, sizeof cell);
                if (c > 1)
                    fputc(',', out);
                table_csv_field(out, cell);
            }
            for (int a = 0; a < naxes; a++) {
                sqlite3_reset(ps);
                sqlite3_bind_int64(ps, 1, jid);
                sqlite3_bind_text(ps, 2, axes[a], -1, SQLITE_STATIC);
                cell[0] = '\0';
                if (sqlite3_step(ps) == SQLITE_ROW)
                    table_cell(ps, 0, cell, sizeof cell);
                fputc(',', out);
                table_csv_field(out, cell);
            }
            for (int m = 0; m < nr; m++) {
                cell[0] = '\0';
                if (run) {
                    sqlite3_reset(ms);
                    sqlite3_bind_int64(ms, 1, run);
                    sqlite3_bind_text(ms, 2, rnames[m], -1, SQLITE_STATIC);
                    if (sqlite3_step(ms) == SQLITE_ROW)
                        table_cell(ms, 0, cell, sizeof cell);
                }
                fputc(',', out);
                table_csv_field(out, cell);
            }
            fputc('\n', out);
        }
        rc = export_ref_rows(db, sid, axes, naxes, rnames, nr, out, &e);
    }
    sqlite3_finalize(st);
    sqlite3_finalize(ps);
    sqlite3_finalize(ms);
    if (!rc && out_path)
        rc = wfile_commit(&wf, &e);
    wfile_discard(&wf);   /* an error before the commit: no half-written CSV */
    if (!rc && !out_path && (fflush(stdout) != 0 || ferror(stdout)))
        rc = err_set(&e, ERR_RUNTIME, "cannot write the CSV to standard output: %s",
                     strerror(errno));
    for (int a = 0; a < naxes; a++)
        free(axes[a]);
    free(axes);
    for (int m = 0; m < nm; m++) {
        free(mc[m].name);
        free(mc[m].unit);
    }
    free(mc);
    for (int m = 0; m < nr; m++) {
        free(rnames[m]);
        free(runits[m]);
    }
    free(rnames);
    free(runits);
    db_close(&db);
    if (rc)
        fprintf(stderr, "error: %s\n", e.msg);
    return cli_exit_code(rc);
}
