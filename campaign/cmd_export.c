/* cascade export: a study as one row per job, CSV or JSON lines. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "export_ref.h"
#include "rdata_ref.h"
#include "table.h"
#include "util/canon.h"
#include "util/mem.h"
#include "util/wfile.h"

static const char *usage =
    "usage: cascade export STUDY [--format csv|jsonl] [--db FILE] [--out FILE]\n"
    "\n"
    "Writes one row per job of the study: key, kind, name, state, attempt,\n"
    "solver version and git hash, wall seconds, then one column per swept\n"
    "parameter (in the study's order) and one per metric, named 'metric [unit]',\n"
    "from each job's latest successful run (empty when it has none).  Reference\n"
    "values imported with cascade import follow as rows of kind 'reference' (name:\n"
    "the source; attempt: the line of the imported file).\n"
    "\n"
    "  --format csv     RFC 4180 CSV with a header line (the default; --csv says the same)\n"
    "  --format jsonl   JSON lines: one object per job with the same names as the CSV\n"
    "                   header; numbers stay numbers, a missing value is null, a\n"
    "                   swept list or mapping is JSON (pandas.read_json(f, lines=True))\n"
    "  --out FILE       write there instead of to standard output\n"
    "\n"
    "Reals print in the shortest form that reads back to the same double.\n";

/* One output row being written: CSV fields or the members of one JSON
 * object, in column order. */
struct row_sink {
    FILE *out;
    int jsonl;
    int first;
};

static void row_begin(struct row_sink *k)
{
    k->first = 1;
    if (k->jsonl)
        fputc('{', k->out);
}

static void row_end(struct row_sink *k)
{
    fputs(k->jsonl ? "}\n" : "\n", k->out);
}

/* A JSON string literal of s (minimal escapes). */
static void json_text(FILE *out, const char *s)
{
    json_t *j = json_string(s);
    char *t = j ? canon_json(j) : NULL;
    fputs(t ? t : "\"\"", out);
    free(t);
    json_decref(j);
}

/* Column `name`, value from column `col` of `st` (st NULL: no value).
 * `structured`: a text value that holds a JSON list or mapping (a swept
 * list) goes into JSON lines as JSON, not as a string. */
static void row_cell(struct row_sink *k, const char *name, sqlite3_stmt *st, int col,
                     int structured)
{
    if (!k->jsonl) {
        char cell[4096] = "";
        if (st)
            table_cell(st, col, cell, sizeof cell);
        if (!k->first)
            fputc(',', k->out);
        table_csv_field(k->out, cell);
        k->first = 0;
        return;
    }
    if (!k->first)
        fputc(',', k->out);
    k->first = 0;
    json_text(k->out, name);
    fputc(':', k->out);
    int type = st ? sqlite3_column_type(st, col) : SQLITE_NULL;
    if (type == SQLITE_INTEGER) {
        fprintf(k->out, "%lld", (long long)sqlite3_column_int64(st, col));
    } else if (type == SQLITE_FLOAT) {
        double x = sqlite3_column_double(st, col);
        char num[64];
        canon_real(x, num, sizeof num);
        fputs(isfinite(x) ? num : "null", k->out);   /* JSON has no inf */
    } else if (type == SQLITE_NULL) {
        fputs("null", k->out);
    } else {
        const char *t = (const char *)sqlite3_column_text(st, col);
        json_t *v = structured && t && (t[0] == '[' || t[0] == '{') ? json_loads(t, 0, NULL) : NULL;
        char *c = v ? canon_json(v) : NULL;
        if (c)
            fputs(c, k->out);
        else
            json_text(k->out, t ? t : "");
        free(c);
        json_decref(v);
    }
}

struct metric_col {
    char *name;
    char *unit;
};

/* The reference rows of `cascade import` as JSON lines (export_ref_rows
 * writes them as CSV): kind and state 'reference', name the source,
 * attempt the line of the imported file. */
static int ref_rows_jsonl(sqlite3 *db, long long sid, char *const *axes, int naxes,
                          char *const *metrics, int nm, char *const *heads, struct row_sink *k,
                          struct err *e)
{
    if (!rdata_has_table(db, "imports"))
        return 0;
    sqlite3_stmt *st = NULL, *ps = NULL, *vs = NULL;
    int rc = db_prepare(db, "SELECT '', 'reference', i.source, 'reference', r.line, NULL, NULL, "
                            "NULL, r.id FROM import_rows r JOIN imports i ON i.id = r.import_id "
                            "WHERE i.study_id = ?1 ORDER BY i.source, r.id",
                        &st, e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM import_params WHERE row_id = ?1 AND name = ?2", &ps,
                        e);
    if (!rc)
        rc = db_prepare(db, "SELECT value FROM import_values WHERE row_id = ?1 AND metric = ?2",
                        &vs, e);
    if (!rc) {
        sqlite3_bind_int64(st, 1, sid);
        while (sqlite3_step(st) == SQLITE_ROW) {
            long long row = sqlite3_column_int64(st, 8);
            row_begin(k);
            for (int c = 0; c < 8; c++)
                row_cell(k, heads[c], st, c, 0);
            for (int a = 0; a < naxes; a++) {
                sqlite3_reset(ps);
                sqlite3_bind_int64(ps, 1, row);
                sqlite3_bind_text(ps, 2, axes[a], -1, SQLITE_STATIC);
                int have = sqlite3_step(ps) == SQLITE_ROW;
                row_cell(k, heads[8 + a], have ? ps : NULL, 0, 1);
            }
            for (int m = 0; m < nm; m++) {
                sqlite3_reset(vs);
                sqlite3_bind_int64(vs, 1, row);
                sqlite3_bind_text(vs, 2, metrics[m], -1, SQLITE_STATIC);
                int have = sqlite3_step(vs) == SQLITE_ROW;
                row_cell(k, heads[8 + naxes + m], have ? vs : NULL, 0, 0);
            }
            row_end(k);
        }
    }
    sqlite3_finalize(st);
    sqlite3_finalize(ps);
    sqlite3_finalize(vs);
    return rc;
}

int cmd_export(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL, *out_path = NULL;
    const char *format = "csv";
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "--out", &out_path)) ||
            (m = cli_opt(argc, argv, &i, "--format", &format))) {
            if (m < 0)
                return 2;
        } else if (strcmp(argv[i], "--csv") == 0) {
            format = "csv";
        } else if (argv[i][0] != '-' && !study) {
            study = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!study)
        return cli_usage_error(usage, "give a study name");
    int jsonl = strcmp(format, "jsonl") == 0 || strcmp(format, "json") == 0;
    if (!jsonl && strcmp(format, "csv") != 0)
        return cli_usage_error(usage, "--format: give csv or jsonl, not '%s'", format);
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
    char **heads = NULL;   /* the column names, CSV header and JSON member names */
    int nhead = 8 + naxes + nr;
    if (!rc && !(heads = mem_calloc((size_t)nhead, sizeof *heads)))
        rc = err_nomem(&e, "export columns");
    if (!rc) {
        static const char *const fixed[8] = {"key",    "kind",           "name",       "state",
                                             "attempt", "solver_version", "solver_git", "wall_s"};
        for (int c = 0; c < 8; c++)
            heads[c] = mem_strdup(fixed[c]);
        for (int a = 0; a < naxes; a++)
            heads[8 + a] = mem_strdup(axes[a]);
        for (int m = 0; m < nr; m++) {
            char h[512];
            snprintf(h, sizeof h, "%s [%s]", rnames[m], runits[m]);
            heads[8 + naxes + m] = mem_strdup(h);
        }
        for (int c = 0; c < nhead && !rc; c++)
            if (!heads[c])
                rc = err_nomem(&e, "export columns");
    }
    if (!rc) {
        struct row_sink k = {out, jsonl, 1};
        if (!jsonl) {
            for (int c = 0; c < nhead; c++) {
                if (c)
                    fputc(',', out);
                table_csv_field(out, heads[c]);
            }
            fputc('\n', out);
        }
        sqlite3_bind_int64(st, 1, sid);
        while (sqlite3_step(st) == SQLITE_ROW) {
            long long jid = sqlite3_column_int64(st, 0);
            long long run = sqlite3_column_int64(st, 5);
            row_begin(&k);
            for (int c = 1, h = 0; c <= 9; c++)
                if (c != 5)
                    row_cell(&k, heads[h++], st, c, 0);
            for (int a = 0; a < naxes; a++) {
                sqlite3_reset(ps);
                sqlite3_bind_int64(ps, 1, jid);
                sqlite3_bind_text(ps, 2, axes[a], -1, SQLITE_STATIC);
                int have = sqlite3_step(ps) == SQLITE_ROW;
                row_cell(&k, heads[8 + a], have ? ps : NULL, 0, 1);
            }
            for (int m = 0; m < nr; m++) {
                int have = 0;
                if (run) {
                    sqlite3_reset(ms);
                    sqlite3_bind_int64(ms, 1, run);
                    sqlite3_bind_text(ms, 2, rnames[m], -1, SQLITE_STATIC);
                    have = sqlite3_step(ms) == SQLITE_ROW;
                }
                row_cell(&k, heads[8 + naxes + m], have ? ms : NULL, 0, 0);
            }
            row_end(&k);
        }
        rc = jsonl ? ref_rows_jsonl(db, sid, axes, naxes, rnames, nr, heads, &k, &e)
                   : export_ref_rows(db, sid, axes, naxes, rnames, nr, out, &e);
        if (!rc && (ferror(out) || fflush(out) != 0))
            rc = err_set(&e, ERR_RUNTIME, "writing %s: %s", out_path ? out_path : "standard output",
                         strerror(errno));
    }
    for (int c = 0; heads && c < nhead; c++)
        free(heads[c]);
    free(heads);
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
