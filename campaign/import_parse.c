/* import_parse: reference rows from CSV or JSON (see import_parse.h). */
#include "import_parse.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/yamldoc.h"
#include "util/mem.h"

#define MAX_COLS 256

void import_set_free(struct import_set *s)
{
    for (int i = 0; i < s->nrows; i++) {
        json_decref(s->rows[i].params);
        json_decref(s->rows[i].metrics);
    }
    free(s->rows);
    s->rows = NULL;
    s->nrows = 0;
}

void import_where(const struct import_set *s, int i, char *out, size_t len)
{
    if (s->rows[i].col > 0)
        snprintf(out, len, "%s:%d:%d", s->file, s->rows[i].line, s->rows[i].col);
    else
        snprintf(out, len, "%s:%d", s->file, s->rows[i].line);
}

static int add_row(struct import_set *s, int line, int col, struct err *e)
{
    if ((s->nrows & (s->nrows - 1)) == 0) {
        struct import_row *g = mem_realloc(s->rows, (size_t)(s->nrows ? 2 * s->nrows : 1) * sizeof *g);
        if (!g)
            return err_nomem(e, "import rows");
        s->rows = g;
    }
    struct import_row *r = &s->rows[s->nrows++];
    r->line = line;
    r->col = col;
    r->params = json_object();
    r->metrics = json_object();
    return r->params && r->metrics ? 0 : err_nomem(e, "import rows");
}

/* --- CSV ------------------------------------------------------------------- */

static char *trim(char *t)
{
    while (isspace((unsigned char)*t))
        t++;
    size_t n = strlen(t);
    while (n && isspace((unsigned char)t[n - 1]))
        t[--n] = '\0';
    return t;
}

/* Split one line into fields in place (quotes honoured); returns the count,
 * or -1 for an unterminated quote, -2 for too many fields. */
static int split(char *line, char **f)
{
    int n = 0;
    char *p = line;
    for (;;) {
        if (n == MAX_COLS)
            return -2;
        while (*p == ' ' || *p == '\t')
            p++;
        if (*p == '"') {
            char *w = ++p;
            f[n++] = w;
            for (;;) {
                if (!*p)
                    return -1;
                if (*p == '"' && p[1] == '"') {
                    *w++ = '"';
                    p += 2;
                } else if (*p == '"') {
                    p++;
                    break;
                } else {
                    *w++ = *p++;
                }
            }
            *w = '\0';
            while (*p && *p != ',')
                p++;
        } else {
            f[n++] = p;
            while (*p && *p != ',')
                p++;
        }
        if (!*p)
            break;
        *p++ = '\0';
    }
    for (int i = 0; i < n; i++)
        f[i] = trim(f[i]);
    return n;
}

/* A cell as JSON: an integer, a real, or a string. */
static json_t *cell_value(const char *t)
{
    char *end;
    errno = 0;
    long long i = strtoll(t, &end, 10);
    if (*t && !*end && errno == 0)
        return json_integer(i);
    double x = strtod(t, &end);
    if (*t && !*end && isfinite(x))
        return json_real(x);
    return json_string(t);
}

struct column {
    char name[256];
    char unit[64];
    int metric;
};

static int header(struct import_set *s, char **f, int n, int line, struct column *cols,
                  struct err *e)
{
    for (int i = 0; i < n; i++) {
        struct column *c = &cols[i];
        memset(c, 0, sizeof *c);
        char *open = strchr(f[i], '[');
        if (open) {
            char *close = strchr(open, ']');
            if (!close || close[1])
                return err_set(e, ERR_INPUT, "%s:%d: column %d '%s': write a metric as 'name "
                                             "[unit]'",
                               s->file, line, i + 1, f[i]);
            *close = '\0';
            char *u = trim(open + 1);
            if (!u[0])
                return err_set(e, ERR_INPUT, "%s:%d: column %d '%s]': missing unit (write [1] for "
                                             "a dimensionless metric)",
                               s->file, line, i + 1, f[i]);
            snprintf(c->unit, sizeof c->unit, "%s", u);
            *open = '\0';
            c->metric = 1;
        }
        char *name = trim(f[i]);
        if (!name[0] || strlen(name) >= sizeof c->name)
            return err_set(e, ERR_INPUT, "%s:%d: column %d: empty or overlong name", s->file, line,
                           i + 1);
        snprintf(c->name, sizeof c->name, "%s", name);
        for (int k = 0; k < i; k++)
            if (strcmp(cols[k].name, c->name) == 0)
                return err_set(e, ERR_INPUT, "%s:%d: column %d: '%s' given twice (also column %d)",
                               s->file, line, i + 1, c->name, k + 1);
    }
    return 0;
}

static int parse_csv(struct import_set *s, FILE *fp, struct err *e)
{
    char buf[65536];
    char *f[MAX_COLS];
    struct column *cols = mem_calloc(MAX_COLS, sizeof *cols);
    if (!cols)
        return err_nomem(e, "columns");
    int ncols = 0, line = 0, rc = 0;
    while (!rc && fgets(buf, sizeof buf, fp)) {
        line++;
        size_t len = strlen(buf);
        if (len == sizeof buf - 1 && buf[len - 1] != '\n') {
            rc = err_set(e, ERR_INPUT, "%s:%d: line longer than %zu characters", s->file, line,
                         sizeof buf - 2);
            break;
        }
        char *t = trim(buf);
        if (!t[0])
            continue;
        if (t[0] == '#') {
            char *v = trim(t + 1);
            if (strncmp(v, "source:", 7) == 0)
                snprintf(s->source, sizeof s->source, "%s", trim(v + 7));
            continue;
        }
        int n = split(t, f);
        if (n < 0) {
            rc = err_set(e, ERR_INPUT, "%s:%d: %s", s->file, line,
                         n == -1 ? "unterminated quote" : "too many columns");
            break;
        }
        if (!ncols) {
            s->header_line = line;
            if ((rc = header(s, f, n, line, cols, e)))
                break;
            ncols = n;
            continue;
        }
        if (n != ncols) {
            rc = err_set(e, ERR_INPUT, "%s:%d: %d field%s where the header (line %d) has %d", s->file,
                         line, n, n == 1 ? "" : "s", s->header_line, ncols);
            break;
        }
        if ((rc = add_row(s, line, 0, e)))
            break;
        struct import_row *r = &s->rows[s->nrows - 1];
        for (int i = 0; i < n && !rc; i++) {
            if (cols[i].metric) {
                json_t *v = json_null();
                if (f[i][0]) {
                    v = cell_value(f[i]);
                    if (!json_is_number(v)) {
                        json_decref(v);
                        rc = err_set(e, ERR_INPUT, "%s:%d: %s: '%s' is not a number", s->file,
                                     line, cols[i].name, f[i]);
                        break;
                    }
                }
                json_object_set_new(r->metrics, cols[i].name,
                                    json_pack("{s:o, s:s}", "value", v, "unit", cols[i].unit));
            } else {
                if (!f[i][0]) {
                    rc = err_set(e, ERR_INPUT, "%s:%d: %s: empty parameter value", s->file, line,
                                 cols[i].name);
                    break;
                }
                json_object_set_new(r->params, cols[i].name, cell_value(f[i]));
            }
        }
    }
    if (!rc && ferror(fp))
        rc = err_set(e, ERR_INPUT, "%s: read error", s->file);
    if (!rc && !ncols)
        rc = err_set(e, ERR_INPUT, "%s: no header line (parameters, then metrics as 'name [unit]')",
                     s->file);
    free(cols);
    return rc;
}

/* --- JSON ------------------------------------------------------------------ */

static int at(const struct import_set *s, const struct locmap *locs, const char *path, int *line,
              int *col)
{
    const struct loc *l = locmap_get(locs, path);
    *line = l ? (l->key_line ? l->key_line : l->val_line) : 0;
    *col = l ? (l->key_line ? l->key_col : l->val_col) : 0;
    (void)s;
    return 0;
}

__attribute__((format(printf, 5, 6))) static int fail_path(const struct import_set *s,
                                                           const struct locmap *locs,
                                                           const char *path, struct err *e,
                                                           const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int line, col;
    at(s, locs, path, &line, &col);
    return err_set(e, ERR_INPUT, "%s:%d:%d: %s: %s", s->file, line, col, path[0] ? path : "(top)",
                   msg);
}

static int parse_json(struct import_set *s, struct err *e)
{
    json_t *doc = NULL;
    struct locmap *locs = NULL;
    int rc = yamldoc_load_file(s->file, &doc, &locs, e);
    if (rc)
        return rc;
    const char *k;
    json_t *v;
    if (!json_is_object(doc)) {
        rc = fail_path(s, locs, "", e, "must be a mapping with 'source' and 'rows'");
        goto out;
    }
    json_object_foreach(doc, k, v)
    {
        if (strcmp(k, "source") && strcmp(k, "rows")) {
            rc = fail_path(s, locs, k, e, "unknown key (the keys are source and rows)");
            goto out;
        }
    }
    json_t *src = json_object_get(doc, "source");
    if (src && !json_is_string(src)) {
        rc = fail_path(s, locs, "source", e, "must be a string");
        goto out;
    }
    if (src)
        snprintf(s->source, sizeof s->source, "%s", json_string_value(src));
    json_t *rows = json_object_get(doc, "rows");
    if (!json_is_array(rows)) {
        rc = fail_path(s, locs, "rows", e, "must be a list of {params, metrics}");
        goto out;
    }
    size_t i;
    json_t *row;
    json_array_foreach(rows, i, row)
    {
        char p[128];
        snprintf(p, sizeof p, "rows[%zu]", i);
        int line, col;
        at(s, locs, p, &line, &col);
        if (!json_is_object(row)) {
            rc = fail_path(s, locs, p, e, "must be a mapping {params, metrics}");
            goto out;
        }
        json_object_foreach(row, k, v)
        {
            if (strcmp(k, "params") && strcmp(k, "metrics")) {
                char q[256];
                snprintf(q, sizeof q, "%s.%s", p, k);
                rc = fail_path(s, locs, q, e, "unknown key (the keys are params and metrics)");
                goto out;
            }
        }
        json_t *params = json_object_get(row, "params"), *metrics = json_object_get(row, "metrics");
        if (!json_is_object(params) || !json_is_object(metrics)) {
            rc = fail_path(s, locs, p, e, "needs 'params' and 'metrics', both mappings");
            goto out;
        }
        if ((rc = add_row(s, line, col, e)))
            goto out;
        struct import_row *r = &s->rows[s->nrows - 1];
        json_object_foreach(params, k, v)
        {
            if (json_is_null(v) || json_is_object(v)) {
                char q[256];
                snprintf(q, sizeof q, "%s.params.%s", p, k);
                rc = fail_path(s, locs, q, e, "a parameter value must be a number, a string or a "
                                              "list");
                goto out;
            }
            json_object_set(r->params, k, v);
        }
        json_object_foreach(metrics, k, v)
        {
            char q[256];
            snprintf(q, sizeof q, "%s.metrics.%s", p, k);
            json_t *val = json_object_get(v, "value"), *unit = json_object_get(v, "unit");
            if (!json_is_object(v) || json_object_size(v) != (size_t)(!!val + !!unit)) {
                rc = fail_path(s, locs, q, e, "must be {value: NUMBER, unit: TEXT}");
                goto out;
            }
            if (!json_is_string(unit) || !json_string_value(unit)[0]) {
                rc = fail_path(s, locs, q, e, "missing unit (write unit: '1' for a dimensionless "
                                              "metric)");
                goto out;
            }
            if (val && !json_is_null(val) && !json_is_number(val)) {
                rc = fail_path(s, locs, q, e, "value must be a number or null");
                goto out;
            }
            json_object_set_new(r->metrics, k,
                                json_pack("{s:O, s:O}", "value", val ? val : json_null(), "unit",
                                          unit));
        }
    }
out:
    json_decref(doc);
    locmap_destroy(&locs);
    return rc;
}

int import_parse(const char *path, int json, struct import_set *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    snprintf(out->file, sizeof out->file, "%s", path);
    int rc;
    if (json) {
        rc = parse_json(out, e);
    } else {
        FILE *fp = fopen(path, "r");
        if (!fp)
            return err_set(e, ERR_INPUT, "%s: %s", path, strerror(errno));
        rc = parse_csv(out, fp, e);
        fclose(fp);
    }
    if (!rc && out->nrows == 0)
        rc = err_set(e, ERR_INPUT, "%s: no rows to import", path);
    if (rc)
        import_set_free(out);
    return rc;
}
