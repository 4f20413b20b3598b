/* refine_spec: the `refine:` section of a study (see refine_spec.h). */
#include "refine_spec.h"

#include <math.h>
#include <string.h>

const char *const refine_follow_names[] = {"inverse", "value", "same", NULL};

void refine_spec_init(struct refine_spec *r)
{
    memset(r, 0, sizeof *r);
    r->ratio = 2;
    r->gci = r->band = r->asymptotic = NAN;
    r->max_levels = 6;
    r->budget_core_s = INFINITY;
}

static int read_until(struct cfg_obj *ref, struct refine_spec *r)
{
    struct cfg_obj u;
    int rc = cfg_section_required(ref, "until", &u);
    if (rc)
        return rc;
    int have_gci, have_band;
    if ((rc = cfg_real_opt(&u, "gci", CFG_GT(0), &r->gci, &have_gci)) ||
        (rc = cfg_real_opt(&u, "band", CFG_GT(0), &r->band, &have_band)))
        return rc;
    if (!have_gci)
        r->gci = NAN;
    if (!have_band)
        r->band = NAN;
    json_t *a = json_object_get(u.node, "asymptotic");
    if (json_is_boolean(a)) {
        int on;
        if ((rc = cfg_bool(&u, "asymptotic", 0, &on)))
            return rc;
        r->asymptotic = on ? 0.1 : NAN;   /* the report's 10 % criterion */
    } else if (a) {
        if ((rc = cfg_real(&u, "asymptotic", 0.1, CFG_GT(0), &r->asymptotic)))
            return rc;
    }
    if (!have_gci && !have_band)
        return cfg_error_at(u.cfg, u.path, "give gci (a fraction, 0.01 = 1 %%) or band (in the "
                                           "metric's unit), or both");
    return cfg_close(&u);
}

static int read_budget(struct cfg_obj *ref, struct refine_spec *r)
{
    struct cfg_obj b;
    int present, rc = cfg_section_opt(ref, "budget", &b, &present);
    if (rc || !present)
        return rc;
    double h, s;
    int have_h, have_s;
    if ((rc = cfg_real_opt(&b, "core_hours", CFG_GT(0), &h, &have_h)) ||
        (rc = cfg_real_opt(&b, "core_seconds", CFG_GT(0), &s, &have_s)))
        return rc;
    if (have_h == have_s)
        return cfg_error_at(b.cfg, b.path, "give one of core_hours and core_seconds");
    r->budget_core_s = have_h ? 3600 * h : s;
    return cfg_close(&b);
}

static int read_follow(struct cfg_obj *ref, struct refine_spec *r)
{
    cfg_allow(ref, "follow");
    json_t *f = json_object_get(ref->node, "follow");
    if (!f || json_is_null(f))
        return 0;
    char path[CFG_PATH_MAX];
    snprintf(path, sizeof path, "%s.follow", ref->path);
    if (!json_is_object(f))
        return cfg_error_at(ref->cfg, path, "must be a mapping {key: inverse | value | same}");
    const char *k;
    json_t *v;
    json_object_foreach(f, k, v)
    {
        char kp[CFG_PATH_MAX + DOCPATH_MAX];
        snprintf(kp, sizeof kp, "%s.%s", path, k);
        if (r->nfollow == REFINE_MAX_FOLLOW)
            return cfg_error_at(ref->cfg, kp, "at most %d keys follow the axis", REFINE_MAX_FOLLOW);
        if (!docpath_valid(k) || strlen(k) >= DOCPATH_MAX)
            return cfg_error_at(ref->cfg, kp, "'%s' is not a case key path", k);
        int how = -1;
        for (int i = 0; json_is_string(v) && refine_follow_names[i]; i++)
            if (strcmp(json_string_value(v), refine_follow_names[i]) == 0)
                how = i;
        if (how < 0)
            return cfg_error_at(ref->cfg, kp, "must be inverse (x ratio per level), value (/ "
                                              "ratio) or same");
        snprintf(r->follow[r->nfollow].path, DOCPATH_MAX, "%s", k);
        r->follow[r->nfollow++].how = (enum refine_follow)how;
    }
    return 0;
}

int refine_spec_read(struct cfg_obj *root, struct refine_spec *r)
{
    refine_spec_init(r);
    struct cfg_obj ref;
    int present, rc = cfg_section_opt(root, "refine", &ref, &present);
    if (rc || !present)
        return rc;
    r->on = 1;
    const char *axis, *metric;
    int have_axis, have_metric, nm = 0;
    const char *names[REFINE_MAX_METRICS];
    if ((rc = cfg_string_opt(&ref, "axis", &axis, &have_axis)) ||
        (rc = cfg_string_opt(&ref, "metric", &metric, &have_metric)) ||
        (rc = cfg_strings(&ref, "metrics", 0, names, REFINE_MAX_METRICS, &nm)) ||
        (rc = cfg_real(&ref, "ratio", 2.0, CFG_GT(1), &r->ratio)) ||
        (rc = cfg_int(&ref, "max_levels", 6, CFG_RANGE(3, 30), &r->max_levels)) ||
        (rc = read_until(&ref, r)) || (rc = read_budget(&ref, r)) || (rc = read_follow(&ref, r)))
        return rc;
    if (have_axis) {
        if (!docpath_valid(axis) || strlen(axis) >= DOCPATH_MAX)
            return cfg_error_at(ref.cfg, "refine.axis", "'%s' is not a case key path", axis);
        snprintf(r->axis, sizeof r->axis, "%s", axis);
    }
    if (have_metric == (nm > 0))
        return cfg_error_at(ref.cfg, ref.path, "give the metric to converge: metric: NAME or "
                                               "metrics: [NAME, ...]");
    if (have_metric)
        names[nm++] = metric;
    for (int i = 0; i < nm; i++) {
        if (!names[i][0] || strlen(names[i]) >= sizeof r->metrics[0])
            return cfg_error_at(ref.cfg, ref.path, "a metric name of 1 to 127 characters");
        snprintf(r->metrics[r->nmetrics++], sizeof r->metrics[0], "%s", names[i]);
    }
    return cfg_close(&ref);
}
