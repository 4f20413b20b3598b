/* import_store: reference rows checked and written (see import_store.h). */
#include "import_store.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "sysinfo.h"
#include "util/canon.h"
#include "util/sha256.h"
#include "util/yamldoc.h"
#include "util/mem.h"

/* What the database knows of the study. */
struct known {
    long long id;             /* 0: no such study */
    long sweep_jobs;          /* campaign jobs: 0 for a references-only study */
    json_t *axes;             /* {name: kind} */
    json_t *units;            /* {metric: unit} of recorded metrics */
    json_t *listed;           /* the study file's `metrics:` list, or NULL */
};

static void known_free(struct known *k)
{
    json_decref(k->axes);
    json_decref(k->units);
    json_decref(k->listed);
}

static int load_known(sqlite3 *db, const char *name, struct known *k, struct err *e)
{
    memset(k, 0, sizeof *k);
    k->axes = json_object();
    k->units = json_object();
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT id, spec_text FROM studies WHERE name = ?1", &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    if (sqlite3_step(st) == SQLITE_ROW) {
        k->id = sqlite3_column_int64(st, 0);
        const char *text = (const char *)sqlite3_column_text(st, 1);
        json_t *doc = NULL;
        struct locmap *locs = NULL;
        struct err ye = {0};
        if (text && yamldoc_load_string(text, strlen(text), "study", &doc, &locs, &ye) == 0) {
            json_t *m = json_object_get(doc, "metrics");
            if (json_is_array(m))
                k->listed = json_incref(m);
        }
        json_decref(doc);
        locmap_destroy(&locs);
    }
    sqlite3_finalize(st);
    if (!k->id)
        return 0;
    if ((rc = db_prepare(db, "SELECT name, kind FROM study_axes WHERE study_id = ?1", &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, k->id);
    while (sqlite3_step(st) == SQLITE_ROW)
        json_object_set_new(k->axes, (const char *)sqlite3_column_text(st, 0),
                            json_string((const char *)sqlite3_column_text(st, 1)));
    sqlite3_finalize(st);
    if ((rc = db_prepare(db, "SELECT count(*) FROM jobs WHERE study_id = ?1 AND kind = 'sweep'",
                         &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, k->id);
    if (sqlite3_step(st) == SQLITE_ROW)
        k->sweep_jobs = (long)sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    if ((rc = db_prepare(db, "SELECT DISTINCT m.name, m.unit FROM metrics m JOIN runs r ON r.id = "
                             "m.run_id JOIN jobs j ON j.id = r.job_id WHERE j.study_id = ?1",
                         &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, k->id);
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *m = (const char *)sqlite3_column_text(st, 0);
        if (!json_object_get(k->units, m))
            json_object_set_new(k->units, m, json_string((const char *)sqlite3_column_text(st, 1)));
    }
    sqlite3_finalize(st);
    return 0;
}

static int listed(const struct known *k, const char *metric)
{
    size_t i;
    json_t *v;
    json_array_foreach(k->listed, i, v)
    {
        if (json_is_string(v) && strcmp(json_string_value(v), metric) == 0)
            return 1;
    }
    return 0;
}

static int valid_name(const char *s)
{
    if (!s[0] || strlen(s) >= 128)
        return 0;
    for (; *s; s++)
        if (!isalnum((unsigned char)*s) && *s != '_' && *s != '-' && *s != '.')
            return 0;
    return 1;
}

/* Names in a JSON object's keys joined with ", " (for messages). */
static void key_list(const json_t *obj, int skip_repeat, char *out, size_t len)
{
    out[0] = '\0';
    const char *k;
    json_t *v;
    size_t used = 0;
    json_object_foreach((json_t *)obj, k, v)
    {
        if (skip_repeat && json_is_string(v) && strcmp(json_string_value(v), "repeat") == 0)
            continue;
        int w = snprintf(out + used, len - used, "%s%s", used ? ", " : "", k);
        if (w < 0 || (size_t)w >= len - used)
            break;
        used += (size_t)w;
    }
    if (!out[0])
        snprintf(out, len, "none");
}

static int check_rows(const struct import_set *s, const struct known *k, struct err *e)
{
    int campaign = k->id && k->sweep_jobs > 0;
    int refs_only = k->id && !campaign && json_object_size(k->axes) > 0;
    char where[4200], names[1024];
    json_t *seen = json_object();
    int rc = 0;
    for (int i = 0; i < s->nrows && !rc; i++) {
        const struct import_row *r = &s->rows[i];
        import_where(s, i, where, sizeof where);
        const char *name;
        json_t *v;
        if (campaign || refs_only) {
            json_object_foreach(r->params, name, v)
            {
                json_t *kind = json_object_get(k->axes, name);
                if (!kind || strcmp(json_string_value(kind), "repeat") == 0) {
                    key_list(k->axes, 1, names, sizeof names);
                    rc = err_set(e, ERR_INPUT, "%s: %s: unknown parameter: study %s sweeps %s",
                                 where, name, campaign ? "the campaign" : "the references of this",
                                 names);
                    break;
                }
            }
            json_object_foreach(k->axes, name, v)
            {
                if (rc || strcmp(json_string_value(v), "repeat") == 0)
                    continue;
                if (!json_object_get(r->params, name))
                    rc = err_set(e, ERR_INPUT, "%s: %s: missing parameter (every row gives each "
                                               "swept key)",
                                 where, name);
            }
        }
        json_object_foreach(r->metrics, name, v)
        {
            if (rc)
                break;
            const char *unit = json_string_value(json_object_get(v, "unit"));
            json_t *known_unit = json_object_get(k->units, name);
            if (campaign && !known_unit && !listed(k, name) &&
                (json_object_size(k->units) || k->listed)) {
                key_list(k->units, 0, names, sizeof names);
                rc = err_set(e, ERR_INPUT, "%s: %s: unknown metric: the study records %s", where,
                             name, names);
            } else if (known_unit && strcmp(json_string_value(known_unit), unit) != 0) {
                rc = err_set(e, ERR_INPUT, "%s: %s: unit '%s' is not the study's '%s'", where,
                             name, unit, json_string_value(known_unit));
            } else if (!valid_name(name)) {
                rc = err_set(e, ERR_INPUT, "%s: '%s': a metric name is letters, digits, '_', '-' "
                                           "and '.'",
                             where, name);
            }
        }
        if (rc)
            break;
        if (!json_object_size(r->params)) {
            rc = err_set(e, ERR_INPUT, "%s: a row needs at least one parameter", where);
            break;
        }
        char *key = canon_json(r->params);
        json_t *prev = json_object_get(seen, key ? key : "");
        if (prev)
            rc = err_set(e, ERR_INPUT, "%s: duplicate row: the same parameters as line %lld", where,
                         (long long)json_integer_value(prev));
        else
            json_object_set_new(seen, key ? key : "", json_integer(r->line));
        free(key);
    }
    json_decref(seen);
    return rc;
}

static int step(sqlite3 *db, sqlite3_stmt *st, const char *what, struct err *e)
{
    int r = sqlite3_step(st);
    sqlite3_reset(st);
    return r == SQLITE_DONE || r == SQLITE_ROW ? 0 : db_fail(db, e, what);
}

/* The settings text of a references-only study. */
static char *spec_text(const char *name, const char *file, const struct import_opts *o)
{
    char *t = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&t, &n);
    if (!f)
        return NULL;
    fprintf(f, "# written by cascade import: a study holding reference values only\n");
    fprintf(f, "name: %s\ndescription: \"reference values imported from %s\"\n", name, file);
    if (o->resolution) {
        fprintf(f, "report:\n  resolution: {axis: \"%s\"", o->resolution);
        if (o->hmap)
            fprintf(f, ", h: %s", o->hmap);
        if (o->dim)
            fprintf(f, ", dim: %ld", o->dim);
        if (o->volume > 0)
            fprintf(f, ", volume: %.17g", o->volume);
        fprintf(f, "}\n");
    }
    fclose(f);
    return t;
}

static int create_or_update_study(sqlite3 *db, const struct import_set *s,
                                  const struct import_opts *o, struct known *k, struct err *e)
{
    char abs[4096];
    if (!realpath(s->file, abs))
        snprintf(abs, sizeof abs, "%s", s->file);
    char *text = spec_text(o->study, abs, o);
    if (!text)
        return err_nomem(e, "study settings");
    char hash[65], now[40];
    sha256_hex(text, strlen(text), hash);
    sys_iso_time(sys_now(), now, sizeof now);
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "INSERT INTO studies (name, description, spec_path, spec_text, spec_hash, "
                        "created, updated) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?6) ON CONFLICT (name) "
                        "DO UPDATE SET spec_text = excluded.spec_text, spec_hash = "
                        "excluded.spec_hash, updated = excluded.updated RETURNING id",
                        &st, e);
    if (!rc) {
        char desc[4200];
        snprintf(desc, sizeof desc, "reference values imported from %s", abs);
        sqlite3_bind_text(st, 1, o->study, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 2, desc, -1, SQLITE_TRANSIENT);
        sqlite3_bind_text(st, 3, abs, -1, SQLITE_TRANSIENT);
        sqlite3_bind_text(st, 4, text, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 5, hash, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 6, now, -1, SQLITE_STATIC);
        if (sqlite3_step(st) == SQLITE_ROW)
            k->id = sqlite3_column_int64(st, 0);
        else
            rc = db_fail(db, e, "creating the study");
        sqlite3_finalize(st);
    }
    free(text);
    return rc;
}

static int cmp_values(const void *a, const void *b)
{
    const json_t *x = *(json_t *const *)a, *y = *(json_t *const *)b;
    if (json_is_number(x) && json_is_number(y)) {
        double p = json_number_value(x), q = json_number_value(y);
        return p < q ? -1 : p > q;
    }
    char *s = canon_json(x), *t = canon_json(y);
    int c = strcmp(s ? s : "", t ? t : "");
    free(s);
    free(t);
    return c;
}

/* The axes of a references-only study: every imported parameter with its
 * distinct values, in ascending order. */
static int rebuild_axes(sqlite3 *db, long long study_id, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT r.params FROM import_rows r JOIN imports i ON i.id = "
                            "r.import_id WHERE i.study_id = ?1 ORDER BY r.id",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    json_t *axes = json_object();   /* name: {canon: value} */
    json_t *order = json_array();
    while (sqlite3_step(st) == SQLITE_ROW) {
        json_t *p = json_loads((const char *)sqlite3_column_text(st, 0), 0, NULL);
        const char *k;
        json_t *v;
        json_object_foreach(p, k, v)
        {
            json_t *set = json_object_get(axes, k);
            if (!set) {
                set = json_object();
                json_object_set_new(axes, k, set);
                json_array_append_new(order, json_string(k));
            }
            char *c = canon_json(v);
            json_object_set(set, c ? c : "", v);
            free(c);
        }
        json_decref(p);
    }
    sqlite3_finalize(st);
    char sql[160];
    snprintf(sql, sizeof sql, "DELETE FROM study_axes WHERE study_id = %lld", study_id);
    rc = db_exec(db, sql, e);
    st = NULL;
    if (!rc)
        rc = db_prepare(db, "INSERT INTO study_axes (study_id, name, position, grp, kind, nvalues, "
                            "vals) VALUES (?1, ?2, ?3, ?3, 'grid', ?4, ?5)",
                        &st, e);
    size_t i;
    json_t *name;
    json_array_foreach(order, i, name)
    {
        if (rc)
            break;
        json_t *set = json_object_get(axes, json_string_value(name));
        size_t n = json_object_size(set), q = 0;
        json_t **vals = mem_alloc((n ? n : 1) * sizeof *vals);
        if (!vals) {
            rc = err_nomem(e, "axes");
            break;
        }
        const char *k;
        json_t *v;
        json_object_foreach(set, k, v) vals[q++] = v;
        qsort(vals, n, sizeof *vals, cmp_values);
        json_t *list = json_array();
        for (q = 0; q < n; q++)
            json_array_append(list, vals[q]);
        free(vals);
        char *text = json_dumps(list, JSON_COMPACT | JSON_REAL_PRECISION(17));
        json_decref(list);
        sqlite3_bind_int64(st, 1, study_id);
        sqlite3_bind_text(st, 2, json_string_value(name), -1, SQLITE_STATIC);
        sqlite3_bind_int(st, 3, (int)i);
        sqlite3_bind_int64(st, 4, (sqlite3_int64)n);
        sqlite3_bind_text(st, 5, text ? text : "[]", -1, SQLITE_TRANSIENT);
        free(text);
        rc = step(db, st, "writing the axes", e);
    }
    sqlite3_finalize(st);
    json_decref(axes);
    json_decref(order);
    return rc;
}

static int write_rows(sqlite3 *db, const struct import_set *s, long long import_id,
                      struct import_result *res, struct err *e)
{
    sqlite3_stmt *row = NULL, *par = NULL, *val = NULL;
    int rc = db_prepare(db, "INSERT INTO import_rows (import_id, line, params) VALUES (?1, ?2, ?3) "
                            "RETURNING id",
                        &row, e);
    if (!rc)
        rc = db_prepare(db, "INSERT INTO import_params (row_id, name, value) VALUES (?1, ?2, ?3)",
                        &par, e);
    if (!rc)
        rc = db_prepare(db, "INSERT INTO import_values (row_id, metric, value, unit) VALUES (?1, "
                            "?2, ?3, ?4)",
                        &val, e);
    for (int i = 0; i < s->nrows && !rc; i++) {
        const struct import_row *r = &s->rows[i];
        char *params = canon_json(r->params);
        sqlite3_bind_int64(row, 1, import_id);
        sqlite3_bind_int(row, 2, r->line);
        sqlite3_bind_text(row, 3, params ? params : "{}", -1, SQLITE_TRANSIENT);
        free(params);
        if (sqlite3_step(row) != SQLITE_ROW) {
            rc = db_fail(db, e, "writing an imported row");
            break;
        }
        long long row_id = sqlite3_column_int64(row, 0);
        sqlite3_reset(row);
        const char *k;
        json_t *v;
        json_object_foreach(r->params, k, v)
        {
            if (rc)
                break;
            sqlite3_bind_int64(par, 1, row_id);
            sqlite3_bind_text(par, 2, k, -1, SQLITE_STATIC);
            db_bind_json_value(par, 3, v);
            rc = step(db, par, "writing imported parameters", e);
        }
        json_object_foreach(r->metrics, k, v)
        {
            if (rc)
                break;
            json_t *x = json_object_get(v, "value");
            sqlite3_bind_int64(val, 1, row_id);
            sqlite3_bind_text(val, 2, k, -1, SQLITE_STATIC);
            if (json_is_number(x))
                sqlite3_bind_double(val, 3, json_number_value(x));
            else
                sqlite3_bind_null(val, 3);
            sqlite3_bind_text(val, 4, json_string_value(json_object_get(v, "unit")), -1,
                              SQLITE_STATIC);
            rc = step(db, val, "writing imported values", e);
            res->nvalues++;
        }
        res->nrows++;
    }
    sqlite3_finalize(row);
    sqlite3_finalize(par);
    sqlite3_finalize(val);
    return rc;
}

static int read_hash(const char *path, char hash[65], struct err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(e, ERR_INPUT, "%s: cannot read", path);
    char *buf = NULL;
    size_t n = 0;
    FILE *m = open_memstream(&buf, &n);
    char chunk[8192];
    size_t got;
    while (m && (got = fread(chunk, 1, sizeof chunk, f)) > 0)
        fwrite(chunk, 1, got, m);
    fclose(f);
    if (!m)
        return err_nomem(e, "file");
    fclose(m);
    sha256_hex(buf, n, hash);
    free(buf);
    return 0;
}

int import_store(sqlite3 *db, const struct import_set *s, const struct import_opts *o,
                 struct import_result *res, struct err *e)
{
    memset(res, 0, sizeof *res);
    if (!valid_name(o->study))
        return err_set(e, ERR_INPUT, "'%s': a study name is letters, digits, '_', '-' and '.'",
                       o->study);
    const char *source = o->source && o->source[0] ? o->source : s->source;
    if (!source[0])
        return err_set(e, ERR_INPUT, "%s: say which source the values come from: --source NAME, or "
                                     "a line '# source: NAME' (CSV) or 'source: NAME' (JSON)",
                       s->file);
    snprintf(res->source, sizeof res->source, "%s", source);
    if (strcmp(source, "campaign") == 0)
        return err_set(e, ERR_INPUT, "%s: 'campaign' names the study's own runs; give the "
                                     "source another name",
                       s->file);
    char hash[65];
    int rc = read_hash(s->file, hash, e);
    if (rc)
        return rc;
    struct known k;
    rc = load_known(db, o->study, &k, e);
    if (!rc && k.sweep_jobs > 0 && (o->resolution || o->hmap || o->dim || o->volume > 0))
        rc = err_set(e, ERR_INPUT, "--resolution, --h, --dim and --volume set up a study that "
                                   "holds references only; study %s is run by the campaign (its "
                                   "report: section says how to analyse it)",
                     o->study);
    if (!rc)
        rc = check_rows(s, &k, e);
    if (rc) {
        known_free(&k);
        return rc;
    }
    int refs_only = k.sweep_jobs == 0;
    /* every check has passed: write all of it or nothing */
    rc = db_begin(db, e);
    if (!rc && refs_only && (!k.id || o->resolution)) {
        res->created = !k.id;
        rc = create_or_update_study(db, s, o, &k, e);
    }
    res->study_id = k.id;
    sqlite3_stmt *st = NULL;
    long long import_id = 0;
    if (!rc) {
        char sql[200];
        snprintf(sql, sizeof sql, "SELECT count(*) FROM imports WHERE study_id = %lld AND source = ?1",
                 k.id);
        rc = db_prepare(db, sql, &st, e);
        if (!rc) {
            sqlite3_bind_text(st, 1, source, -1, SQLITE_STATIC);
            if (sqlite3_step(st) == SQLITE_ROW)
                res->replaced = sqlite3_column_int(st, 0) > 0;
            sqlite3_finalize(st);
        }
    }
    if (!rc)
        rc = db_prepare(db, "DELETE FROM imports WHERE study_id = ?1 AND source = ?2", &st, e);
    if (!rc) {
        sqlite3_bind_int64(st, 1, k.id);
        sqlite3_bind_text(st, 2, source, -1, SQLITE_STATIC);
        rc = step(db, st, "replacing the earlier import", e);
        sqlite3_finalize(st);
    }
    if (!rc)
        rc = db_prepare(db, "INSERT INTO imports (study_id, source, file, sha256, imported, nrows) "
                            "VALUES (?1, ?2, ?3, ?4, ?5, ?6) RETURNING id",
                        &st, e);
    if (!rc) {
        char abs[4096], now[40];
        if (!realpath(s->file, abs))
            snprintf(abs, sizeof abs, "%s", s->file);
        sys_iso_time(sys_now(), now, sizeof now);
        sqlite3_bind_int64(st, 1, k.id);
        sqlite3_bind_text(st, 2, source, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 3, abs, -1, SQLITE_TRANSIENT);
        sqlite3_bind_text(st, 4, hash, -1, SQLITE_STATIC);
        sqlite3_bind_text(st, 5, now, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int(st, 6, s->nrows);
        if (sqlite3_step(st) == SQLITE_ROW)
            import_id = sqlite3_column_int64(st, 0);
        else
            rc = db_fail(db, e, "recording the import");
        sqlite3_finalize(st);
    }
    if (!rc)
        rc = write_rows(db, s, import_id, res, e);
    if (!rc && refs_only)
        rc = rebuild_axes(db, k.id, e);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    known_free(&k);
    return rc;
}
