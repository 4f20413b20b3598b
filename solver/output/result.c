/* result: building and atomically writing result.json. */
#include "output/result.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "util/wfile.h"

int result_init(struct result *r)
{
    r->root = json_object();
    r->metrics = json_object();
    r->series = json_object();
    if (!r->root || !r->metrics || !r->series)
        return ERR_RUNTIME;
    json_object_set_new(r->root, "status", json_string("ok"));
    json_object_set_new(r->root, "metrics", r->metrics);
    json_object_set_new(r->root, "series", r->series);
    return 0;
}

void result_free(struct result *r)
{
    json_decref(r->root);
    r->root = r->metrics = r->series = NULL;
}

void result_metric(struct result *r, const char *name, double value, const char *unit)
{
    /* JSON has no NaN: a missing value is null */
    json_t *v = isfinite(value) ? json_real(value) : json_null();
    json_object_set_new(r->metrics, name, json_pack("{s:o, s:s}", "value", v, "unit", unit));
}

void result_metric_source(struct result *r, const char *name, const char *source)
{
    json_t *m = json_object_get(r->metrics, name);
    if (m)
        json_object_set_new(m, "source", json_string(source));
}

void result_series(struct result *r, const char *name, const double *values, int n,
                   const char *unit)
{
    json_t *arr = json_array();
    for (int i = 0; i < n; i++)
        json_array_append_new(arr, isfinite(values[i]) ? json_real(values[i]) : json_null());
    json_object_set_new(r->series, name, json_pack("{s:s, s:o}", "unit", unit, "values", arr));
}

void result_artifact(struct result *r, const char *name, const char *file)
{
    json_t *a = json_object_get(r->root, "artifacts");
    if (!a) {
        a = json_object();
        json_object_set_new(r->root, "artifacts", a);
    }
    json_object_set_new(a, name, json_string(file));
}

void result_set_status(struct result *r, const char *status, const char *message)
{
    json_object_set_new(r->root, "status", json_string(status));
    if (message)
        json_object_set_new(r->root, "message", json_string(message));
}

int result_write(const struct result *r, const char *path, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    if (json_dumpf(r->root, w.f, JSON_INDENT(2) | JSON_SORT_KEYS | JSON_REAL_PRECISION(12)) != 0) {
        wfile_discard(&w);
        return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory", path);
    }
    return wfile_commit(&w, e);
}
