/* baseline_conv: converged value and level in a baseline (see baseline_conv.h). */
#include "baseline_conv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "resolution.h"

void baseline_conv_add(json_t *b, const struct study_analysis *a)
{
    if (json_array_size(a->refine) == 0)
        return;
    json_t *list = json_array();
    size_t i;
    json_t *row;
    json_array_foreach((json_t *)a->refine, i, row)
    {
        json_t *o = json_object();
        json_object_set(o, "metric", json_object_get(row, "metric"));
        json_object_set(o, "group", json_object_get(row, "series"));
        json_object_set(o, "state", json_object_get(row, "state"));
        json_object_set(o, "levels", json_object_get(row, "levels"));
        json_object_set(o, "finest", json_object_get(row, "finest"));
        json_object_set(o, "value", json_object_get(row, "value"));
        json_array_append_new(list, o);
    }
    json_object_set_new(b, "converged", list);
}

const char *baseline_conv_check(const json_t *b)
{
    const json_t *list = json_object_get(b, "converged");
    if (!list)
        return NULL;
    if (!json_is_array(list))
        return "\"converged\" must be a list";
    size_t i;
    json_t *v;
    json_array_foreach((json_t *)list, i, v)
    {
        if (!json_is_string(json_object_get(v, "metric")) ||
            !json_is_object(json_object_get(v, "group")) ||
            !json_is_string(json_object_get(v, "state")) ||
            !json_is_integer(json_object_get(v, "levels")) || !json_object_get(v, "finest"))
            return "each entry of \"converged\" needs \"metric\", \"group\", \"state\", an integer "
                   "\"levels\" and \"finest\"";
    }
    return NULL;
}

static const json_t *row_of(const json_t *refine, const char *metric, const json_t *group)
{
    size_t i;
    json_t *row;
    json_array_foreach((json_t *)refine, i, row)
    {
        if (strcmp(json_string_value(json_object_get(row, "metric")), metric) == 0 &&
            json_equal(json_object_get(row, "series"), (json_t *)group))
            return row;
    }
    return NULL;
}

/* Equal axis values: numbers by value, the rest as JSON. */
static int same(const json_t *a, const json_t *b)
{
    double x = res_number(a), y = res_number(b);
    if (isfinite(x) || isfinite(y))
        return x == y;
    return json_equal((json_t *)a, (json_t *)b);
}

static void text_of(const json_t *v, char *out, size_t len)
{
    double x = res_number(v);
    if (isfinite(x)) {
        snprintf(out, len, "%.10g", x);
        return;
    }
    char *t = json_dumps(v, JSON_COMPACT | JSON_ENCODE_ANY);
    snprintf(out, len, "%s", t ? t : "?");
    free(t);
}

void baseline_conv_compare(const json_t *b, const struct study_analysis *a,
                           const struct report_spec *rs, struct cmp_report *r)
{
    const json_t *list = json_object_get(b, "converged");
    size_t i;
    json_t *v;
    json_array_foreach((json_t *)list, i, v)
    {
        const char *metric = json_string_value(json_object_get(v, "metric"));
        const json_t *group = json_object_get(v, "group");
        char where[SA_LABEL_MAX];
        sa_params_label(group, where, sizeof where);
        const json_t *row = row_of(a->refine, metric, group);
        r->compared++;
        if (!row) {
            struct cmp_item *it = cmp_add_item(r, CMP_MISSING, metric, "level", where);
            if (it)
                snprintf(it->note, sizeof it->note, "no refinement state now (run the study)");
            continue;
        }
        /* the level: the same number of levels ending at the same axis value, same state */
        long lb = (long)json_integer_value(json_object_get(v, "levels"));
        long ln = (long)json_integer_value(json_object_get(row, "levels"));
        const char *sb = json_string_value(json_object_get(v, "state"));
        const char *sn = json_string_value(json_object_get(row, "state"));
        int level_ok = lb == ln && same(json_object_get(v, "finest"), json_object_get(row, "finest")) &&
                       strcmp(sb, sn) == 0;
        struct cmp_item *it = cmp_add_item(r, level_ok ? CMP_OK : CMP_REGRESSED, metric, "level",
                                           where);
        if (it) {
            char fb[64], fn[64];
            text_of(json_object_get(v, "finest"), fb, sizeof fb);
            text_of(json_object_get(row, "finest"), fn, sizeof fn);
            it->base = (double)lb;
            it->now = (double)ln;
            it->tol = 0;
            snprintf(it->note, sizeof it->note, "%s at %s (%ld levels); baseline %s at %s (%ld)", sn,
                     fn, ln, sb, fb, lb);
        }
        /* the value at that level */
        const json_t *bv = json_object_get(v, "value"), *nv = json_object_get(row, "value");
        if (!json_is_number(bv))
            continue;
        r->compared++;
        double base = json_number_value(bv), now = json_is_number(nv) ? json_number_value(nv) : NAN;
        double abs, rel, otol;
        report_spec_tol(rs, metric, &abs, &rel, &otol);
        double tol = abs + rel * fabs(base);
        enum cmp_verdict verdict = !isfinite(now)              ? CMP_MISSING
                                   : fabs(now - base) <= tol ? CMP_OK
                                                              : CMP_REGRESSED;
        it = cmp_add_item(r, verdict, metric, "converged", where);
        if (it) {
            it->base = base;
            it->now = now;
            it->tol = tol;
            snprintf(it->note, sizeof it->note, "the value at the finest level");
        }
    }
    /* series the baseline does not know */
    json_array_foreach((json_t *)a->refine, i, v)
    {
        const char *metric = json_string_value(json_object_get(v, "metric"));
        const json_t *series = json_object_get(v, "series");
        int known = 0;
        size_t k;
        json_t *e;
        json_array_foreach((json_t *)list, k, e)
        {
            known |= strcmp(json_string_value(json_object_get(e, "metric")), metric) == 0 &&
                     json_equal(json_object_get(e, "group"), (json_t *)series);
        }
        if (known)
            continue;
        char where[SA_LABEL_MAX];
        sa_params_label(series, where, sizeof where);
        struct cmp_item *it = cmp_add_item(r, CMP_NEW, metric, "level", where);
        if (it) {
            it->now = (double)json_integer_value(json_object_get(v, "levels"));
            snprintf(it->note, sizeof it->note, "not in the baseline");
        }
    }
}
