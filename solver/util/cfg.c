/* cfg: typed getters with defaults, bounds, locations and near-miss hints. */
#include "util/cfg.h"

#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "util/mem.h"

static void child_path(const struct cfg_obj *o, const char *key, char *out, size_t len)
{
    snprintf(out, len, "%s%s%s", o->path, o->path[0] ? "." : "", key);
}

static int vfail(struct cfg *c, const char *path, int use_key, const char *fmt, va_list ap)
{
    char what[ERR_MSG_MAX / 2];
    vsnprintf(what, sizeof what, fmt, ap);
    const struct loc *l = c->locs ? locmap_get(c->locs, path) : NULL;
    /* For a missing key, fall back to the nearest ancestor that exists. */
    char up[CFG_PATH_MAX];
    snprintf(up, sizeof up, "%s", path);
    while (!l && c->locs && up[0]) {
        char *dot = strrchr(up, '.');
        char *br = strrchr(up, '[');
        char *cut = dot > br ? dot : br;
        if (cut)
            *cut = '\0';
        else
            up[0] = '\0';
        l = locmap_get(c->locs, up);
    }
    const char *shown = path[0] ? path : "(top level)";
    if (l) {
        int line = use_key && l->key_line ? l->key_line : l->val_line;
        int col = use_key && l->key_line ? l->key_col : l->val_col;
        return err_set(c->err, ERR_INPUT, "%s:%d:%d: %s: %s", c->file, line, col, shown, what);
    }
    return err_set(c->err, ERR_INPUT, "%s: %s: %s", c->file, shown, what);
}

static int fail(struct cfg *c, const char *path, int use_key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail(struct cfg *c, const char *path, int use_key, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = vfail(c, path, use_key, fmt, ap);
    va_end(ap);
    return rc;
}

int cfg_error_at(struct cfg *c, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = vfail(c, path, 0, fmt, ap);
    va_end(ap);
    return rc;
}

void cfg_allow(struct cfg_obj *o, const char *key)
{
    for (int i = 0; i < o->nknown; i++)
        if (strcmp(o->known[i], key) == 0)
            return;
    if (o->nknown < CFG_KEYS_MAX)
        o->known[o->nknown++] = key;
}

/* A required key that is absent: an error, or, when only the keys are being
 * listed (describe), the mark in the tree (returns 0; the caller then
 * makes up a value within the bounds). */
static int missing_key(struct cfg_obj *o, const char *key);

/* A key marked required by an earlier describe read counts as absent. */
static int is_mark(const struct cfg_obj *o, const json_t *v)
{
    return (o->cfg->shallow == CFG_DESCRIBE) && json_is_string(v) &&
           strcmp(json_string_value(v), CFG_REQUIRED_MARK) == 0;
}

/* A stand-in value within bounds b (describe only). */
static double stand_in(struct cfg_bound b)
{
    if (isfinite(b.lo) && isfinite(b.hi))
        return 0.5 * (b.lo + b.hi);
    if (isfinite(b.lo))
        return b.lo + 1;
    if (isfinite(b.hi))
        return b.hi - 1;
    return 1.0;
}

/* An integer stand-in: small (a count or a size of 2, not the middle of a
 * range up to millions, which a check of the total would refuse). */
static long stand_in_int(struct cfg_bound b)
{
    if (isfinite(b.lo) && b.lo + 1 <= b.hi)
        return (long)b.lo + 1;
    return (long)ceil(stand_in(b));
}

static const char *type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "a mapping";
    case JSON_ARRAY: return "a list";
    case JSON_STRING: return "a string";
    case JSON_INTEGER: return "an integer";
    case JSON_REAL: return "a real number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    case JSON_NULL: return "null";
    }
    return "?";
}

static int missing_key(struct cfg_obj *o, const char *key)
{
    if (!(o->cfg->shallow == CFG_DESCRIBE))
        return fail(o->cfg, o->path, 1, "missing required key '%s'", key);
    json_object_set_new(o->node, key, json_string(CFG_REQUIRED_MARK));
    return 0;
}

int cfg_root(struct cfg *c, json_t *doc, struct cfg_obj *root)
{
    memset(root, 0, sizeof *root);
    root->cfg = c;
    root->node = doc;
    if (!json_is_object(doc))
        return fail(c, "", 0, "the document must be a mapping of keys to values, found %s",
                    type_name(doc));
    return 0;
}

static int open_child(struct cfg_obj *o, const char *key, struct cfg_obj *child, json_t *node,
                      const char *path)
{
    memset(child, 0, sizeof *child);
    child->cfg = o->cfg;
    child->node = node;
    snprintf(child->path, sizeof child->path, "%s", path);
    if (!json_is_object(node))
        return fail(o->cfg, path, 0, "must be a mapping of keys to values, found %s",
                    type_name(node));
    return 0;
}

int cfg_section_opt(struct cfg_obj *o, const char *key, struct cfg_obj *child, int *present)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *present = v != NULL && !json_is_null(v);
    if (!*present) {
        memset(child, 0, sizeof *child);
        child->cfg = o->cfg;
        snprintf(child->path, sizeof child->path, "%s", path);
        if (v)
            json_object_del(o->node, key);
        return 0;
    }
    return open_child(o, key, child, v, path);
}

int cfg_section(struct cfg_obj *o, const char *key, struct cfg_obj *child)
{
    int present;
    int rc = cfg_section_opt(o, key, child, &present);
    if (rc || present)
        return rc;
    json_t *fresh = json_object();
    json_object_set_new(o->node, key, fresh);
    child->node = fresh;
    return 0;
}

int cfg_section_listed(struct cfg_obj *o, const char *key, struct cfg_obj *child, int *present)
{
    if (o->cfg->shallow != CFG_DESCRIBE)
        return cfg_section_opt(o, key, child, present);
    *present = 1;
    return cfg_section(o, key, child);
}

int cfg_section_required(struct cfg_obj *o, const char *key, struct cfg_obj *child)
{
    int present;
    int rc = cfg_section_opt(o, key, child, &present);
    if (rc)
        return rc;
    if (!present && (o->cfg->shallow == CFG_DESCRIBE))
        return cfg_section(o, key, child);   /* its keys are what is asked for */
    if (!present)
        return fail(o->cfg, o->path, 1, "missing required section '%s'", key);
    return 0;
}

static int check_bound(struct cfg *c, const char *path, double x, struct cfg_bound b)
{
    int lo_bad = b.lo_open ? !(x > b.lo) : !(x >= b.lo);
    int hi_bad = b.hi_open ? !(x < b.hi) : !(x <= b.hi);
    if (!lo_bad && !hi_bad)
        return 0;
    char want[128];
    if (isinf(b.hi))
        snprintf(want, sizeof want, "must be %s %g", b.lo_open ? ">" : ">=", b.lo);
    else if (isinf(b.lo))
        snprintf(want, sizeof want, "must be %s %g", b.hi_open ? "<" : "<=", b.hi);
    else
        snprintf(want, sizeof want, "must be in %s%g, %g%s", b.lo_open ? "(" : "[", b.lo, b.hi,
                 b.hi_open ? ")" : "]");
    return fail(c, path, 0, "%s (got %g)", want, x);
}

static int get_number(struct cfg_obj *o, const char *key, json_t *v, const char *path, double *x)
{
    if (json_is_integer(v))
        *x = (double)json_integer_value(v);
    else if (json_is_real(v))
        *x = json_real_value(v);
    else
        return fail(o->cfg, path, 0, "must be a number, found %s", type_name(v));
    return 0;
}

int cfg_real_opt(struct cfg_obj *o, const char *key, struct cfg_bound b, double *out, int *present)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *present = v && !json_is_null(v) && !is_mark(o, v);
    if (!*present) {
        if (v)
            json_object_del(o->node, key);
        return 0;
    }
    double x = 0;
    int rc = get_number(o, key, v, path, &x);
    if (rc)
        return rc;
    if ((rc = check_bound(o->cfg, path, x, b)))
        return rc;
    if (!json_is_real(v))
        json_object_set_new(o->node, key, json_real(x));
    *out = x;
    return 0;
}

int cfg_real(struct cfg_obj *o, const char *key, double def, struct cfg_bound b, double *out)
{
    int present;
    int rc = cfg_real_opt(o, key, b, out, &present);
    if (rc || present)
        return rc;
    if (isnan(def)) {
        *out = stand_in(b);
        return missing_key(o, key);
    }
    *out = def;
    json_object_set_new(o->node, key, json_real(def));
    return 0;
}

int cfg_int_opt(struct cfg_obj *o, const char *key, struct cfg_bound b, long *out, int *present)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *present = v && !json_is_null(v) && !is_mark(o, v);
    if (!*present) {
        if (v)
            json_object_del(o->node, key);
        return 0;
    }
    long x;
    double r = json_is_real(v) ? json_real_value(v) : 0;
    if (json_is_integer(v)) {
        x = (long)json_integer_value(v);
    } else if (json_is_real(v) && fabs(r) < 9.0e18 && r == (double)(long)r) {
        /* the range test first: (long) of a real beyond it is undefined */
        x = (long)r;
        json_object_set_new(o->node, key, json_integer(x));
    } else {
        return fail(o->cfg, path, 0, "must be an integer, found %s", type_name(v));
    }
    int rc = check_bound(o->cfg, path, (double)x, b);
    if (rc)
        return rc;
    *out = x;
    return 0;
}

int cfg_int(struct cfg_obj *o, const char *key, long def, struct cfg_bound b, long *out)
{
    int present;
    int rc = cfg_int_opt(o, key, b, out, &present);
    if (rc || present)
        return rc;
    if (def == CFG_REQUIRED_INT) {
        *out = stand_in_int(b);
        return missing_key(o, key);
    }
    *out = def;
    json_object_set_new(o->node, key, json_integer(def));
    return 0;
}

int cfg_bool(struct cfg_obj *o, const char *key, int def, int *out)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (def < 0) {
            *out = 0;
            return missing_key(o, key);
        }
        *out = def;
        json_object_set_new(o->node, key, json_boolean(def));
        return 0;
    }
    if (!json_is_boolean(v))
        return fail(o->cfg, path, 0, "must be true or false, found %s", type_name(v));
    *out = json_is_true(v);
    return 0;
}

int cfg_string_opt(struct cfg_obj *o, const char *key, const char **out, int *present)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *present = v && !json_is_null(v) && !is_mark(o, v);
    if (!*present) {
        if (v)
            json_object_del(o->node, key);
        return 0;
    }
    if (!json_is_string(v))
        return fail(o->cfg, path, 0, "must be a string, found %s", type_name(v));
    *out = json_string_value(v);
    return 0;
}

int cfg_string(struct cfg_obj *o, const char *key, const char *def, const char **out)
{
    int present;
    int rc = cfg_string_opt(o, key, out, &present);
    if (rc || present)
        return rc;
    if (!def) {
        rc = missing_key(o, key);
        *out = CFG_REQUIRED_MARK;
        return rc;
    }
    json_object_set_new(o->node, key, json_string(def));
    *out = json_string_value(json_object_get(o->node, key));
    return 0;
}

static const char *nearest(const char *word, const char *const *cands, int n)
{
    const char *best = NULL;
    int bestd = INT_MAX;
    for (int i = 0; i < n; i++) {
        int d = cfg_edit_distance(word, cands[i]);
        if (d < bestd) {
            bestd = d;
            best = cands[i];
        }
    }
    int len = (int)strlen(word);
    int limit = len <= 4 ? 1 : len <= 8 ? 2 : 3;
    return bestd <= limit ? best : NULL;
}

int cfg_enum(struct cfg_obj *o, const char *key, const char *def, const char *const *choices,
             int *out)
{
    const char *s;
    int rc = cfg_string(o, key, def, &s);
    if (rc)
        return rc;
    if (is_mark(o, json_object_get(o->node, key))) {
        *out = 0;   /* describe: the first choice stands in */
        return 0;
    }
    int n = 0;
    for (; choices[n]; n++)
        if (strcmp(choices[n], s) == 0) {
            *out = n;
            return 0;
        }
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    char list[512] = "";
    for (int i = 0; i < n; i++) {
        strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
        strncat(list, choices[i], sizeof list - strlen(list) - 1);
    }
    const char *hint = nearest(s, choices, n);
    if (hint)
        return fail(o->cfg, path, 0, "unknown value '%s'; did you mean '%s'? (one of: %s)", s, hint,
                    list);
    return fail(o->cfg, path, 0, "unknown value '%s' (one of: %s)", s, list);
}

static int array_of_numbers(struct cfg_obj *o, const char *key, json_t *v, const char *path, int n,
                            struct cfg_bound b, double *vals)
{
    if (!json_is_array(v))
        return fail(o->cfg, path, 0, "must be a list of %d numbers, found %s", n, type_name(v));
    if (n > 0 && (int)json_array_size(v) != n)
        return fail(o->cfg, path, 0, "must be a list of %d numbers, found %zu", n,
                    json_array_size(v));
    for (size_t i = 0; i < json_array_size(v); i++) {
        char ipath[CFG_PATH_MAX];
        snprintf(ipath, sizeof ipath, "%s[%zu]", path, i);
        int rc = get_number(o, key, json_array_get(v, i), ipath, &vals[i]);
        if (!rc)
            rc = check_bound(o->cfg, ipath, vals[i], b);
        if (rc)
            return rc;
    }
    return 0;
}

int cfg_reals(struct cfg_obj *o, const char *key, int n, const double *def, struct cfg_bound b,
              double *out)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (!def) {
            for (int i = 0; i < n; i++)   /* increasing: a [lo, hi) range is valid */
                out[i] = stand_in(b) + i;
            return missing_key(o, key);
        }
        json_t *arr = json_array();
        for (int i = 0; i < n; i++) {
            out[i] = def[i];
            json_array_append_new(arr, json_real(def[i]));
        }
        json_object_set_new(o->node, key, arr);
        return 0;
    }
    int rc = array_of_numbers(o, key, v, path, n, b, out);
    if (rc)
        return rc;
    json_t *arr = json_array();
    for (int i = 0; i < n; i++)
        json_array_append_new(arr, json_real(out[i]));
    json_object_set_new(o->node, key, arr);
    return 0;
}

int cfg_ints(struct cfg_obj *o, const char *key, int n, const long *def, struct cfg_bound b,
             long *out)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (!def) {
            for (int i = 0; i < n; i++)
                out[i] = stand_in_int(b);
            return missing_key(o, key);
        }
        json_t *arr = json_array();
        for (int i = 0; i < n; i++) {
            out[i] = def[i];
            json_array_append_new(arr, json_integer(def[i]));
        }
        json_object_set_new(o->node, key, arr);
        return 0;
    }
    double vals[64];
    if (n > 64)
        return fail(o->cfg, path, 0, "list too long");
    int rc = array_of_numbers(o, key, v, path, n, b, vals);
    if (rc)
        return rc;
    json_t *arr = json_array();
    for (int i = 0; i < n; i++) {
        /* the range test first: (long) of a real beyond it is undefined */
        if (!(fabs(vals[i]) < 9.0e18) || vals[i] != (double)(long)vals[i]) {
            json_decref(arr);
            char ipath[CFG_PATH_MAX];
            snprintf(ipath, sizeof ipath, "%s[%d]", path, i);
            return fail(o->cfg, ipath, 0, "must be an integer (got %g)", vals[i]);
        }
        out[i] = (long)vals[i];
        json_array_append_new(arr, json_integer(out[i]));
    }
    json_object_set_new(o->node, key, arr);
    return 0;
}

int cfg_real_list(struct cfg_obj *o, const char *key, int required, struct cfg_bound b,
                  double **out, size_t *n)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *out = NULL;
    *n = 0;
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (required)
            return missing_key(o, key);
        return 0;
    }
    if (json_is_number(v)) {   /* one value may be given without brackets */
        json_t *arr = json_array();
        json_array_append(arr, v);
        json_object_set_new(o->node, key, arr);
        v = arr;
    }
    if (!json_is_array(v))
        return fail(o->cfg, path, 0, "must be a list of numbers, found %s", type_name(v));
    size_t len = json_array_size(v);
    double *vals = mem_alloc((len ? len : 1) * sizeof *vals);
    if (!vals)
        return err_nomem(o->cfg->err, "list");
    int rc = array_of_numbers(o, key, v, path, 0, b, vals);
    if (rc) {
        free(vals);
        return rc;
    }
    json_t *arr = json_array();
    for (size_t i = 0; i < len; i++)
        json_array_append_new(arr, json_real(vals[i]));
    json_object_set_new(o->node, key, arr);
    *out = vals;
    *n = len;
    return 0;
}

int cfg_list(struct cfg_obj *o, const char *key, int required, size_t *n)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *n = 0;
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (required)
            return missing_key(o, key);
        return 0;
    }
    if (!json_is_array(v))
        return fail(o->cfg, path, 0, "must be a list, found %s", type_name(v));
    *n = json_array_size(v);
    if (required && *n == 0)
        return fail(o->cfg, path, 0, "must not be empty");
    return 0;
}

int cfg_list_item(struct cfg_obj *o, const char *key, size_t i, struct cfg_obj *child)
{
    char path[CFG_PATH_MAX];
    char base[CFG_PATH_MAX];
    child_path(o, key, base, sizeof base);
    snprintf(path, sizeof path, "%s[%zu]", base, i);
    json_t *arr = json_object_get(o->node, key);
    return open_child(o, key, child, json_array_get(arr, i), path);
}

int cfg_close(struct cfg_obj *o)
{
    if (!o->node)
        return 0;
    const char *key;
    json_t *val;
    json_object_foreach(o->node, key, val)
    {
        int ok = 0;
        for (int i = 0; i < o->nknown && !ok; i++)
            ok = strcmp(o->known[i], key) == 0;
        if (ok)
            continue;
        char path[CFG_PATH_MAX];
        child_path(o, key, path, sizeof path);
        const char *hint = nearest(key, o->known, o->nknown);
        char list[1024] = "";
        for (int i = 0; i < o->nknown; i++) {
            strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
            strncat(list, o->known[i], sizeof list - strlen(list) - 1);
        }
        if (hint)
            return fail(o->cfg, path, 1, "unknown key; did you mean '%s'?", hint);
        return fail(o->cfg, path, 1, "unknown key (known here: %s)", list);
    }
    return 0;
}

int cfg_edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 64 || lb > 64)
        return INT_MAX / 2;
    int d[65][65];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++)
        d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++)
        for (size_t j = 1; j <= lb; j++) {
            int cost = a[i - 1] != b[j - 1];
            int best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best)
                best = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < best)
                best = d[i - 1][j - 1] + cost;
            /* adjacent transposition counts as one edit */
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    return d[la][lb];
}

int cfg_strings(struct cfg_obj *o, const char *key, int required, const char **out, int max,
                int *n)
{
    cfg_allow(o, key);
    char path[CFG_PATH_MAX];
    child_path(o, key, path, sizeof path);
    json_t *v = json_object_get(o->node, key);
    *n = 0;
    if (!v || json_is_null(v) || is_mark(o, v)) {
        if (required)
            return missing_key(o, key);
        return 0;
    }
    if (json_is_string(v)) {   /* a single name may be given without brackets */
        json_t *arr = json_array();
        json_array_append(arr, v);
        json_object_set_new(o->node, key, arr);
        v = arr;
    }
    if (!json_is_array(v))
        return fail(o->cfg, path, 0, "must be a list of names, found %s", type_name(v));
    if ((int)json_array_size(v) > max)
        return fail(o->cfg, path, 0, "at most %d names are allowed, found %zu", max,
                    json_array_size(v));
    if (required && json_array_size(v) == 0)
        return fail(o->cfg, path, 0, "must not be empty");
    for (size_t i = 0; i < json_array_size(v); i++) {
        json_t *s = json_array_get(v, i);
        if (!json_is_string(s)) {
            char ipath[CFG_PATH_MAX];
            snprintf(ipath, sizeof ipath, "%s[%zu]", path, i);
            return fail(o->cfg, ipath, 0, "must be a name (string), found %s", type_name(s));
        }
        out[i] = json_string_value(s);
    }
    *n = (int)json_array_size(v);
    return 0;
}

int cfg_find_file(const struct cfg *c, const char *name, char *out, size_t len)
{
    snprintf(out, len, "%s", name);
    if (name[0] == '/' || access(name, R_OK) == 0)
        return access(out, R_OK) == 0 ? 0 : -1;
    if (c->base_dir && c->base_dir[0]) {
        snprintf(out, len, "%s/%s", c->base_dir, name);
        if (access(out, R_OK) == 0)
            return 0;
    }
    snprintf(out, len, "%s", name);
    return -1;
}
