/* report_spec: the `report` and `regress` sections of a study (see report_spec.h). */
#include "report_spec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/mem.h"
#include "util/yamldoc.h"

const char *const hmap_names[] = {"value", "inverse", "cells", NULL};
const char *const fit_model_names[] = {"linear", "power", NULL};

void report_spec_init(struct report_spec *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->res_mode = RES_INFER;
    rs->hmap = HMAP_INFER;
    rs->volume = 1.0;
    rs->order_default = NAN;
    rs->safety = 1.25;   /* Celik et al. 2008, Eq. (8): Fs = 1.25 with three or more grids */
    rs->tol_default.abs = 0;
    rs->tol_default.rel = 1e-9;
    rs->tol_default.order = NAN;
    rs->order_tol = 0.05;
}

void report_spec_free(struct report_spec *rs)
{
    for (int i = 0; i < rs->nmetrics; i++)
        free(rs->metrics[i]);
    free(rs->metrics);
    free(rs->orders);
    free(rs->axes);
    free(rs->fits);
    free(rs->tols);
    report_spec_init(rs);
}

/* A child object of a mapping whose keys are names (not schema keys). */
static int open_named(struct cfg_obj *parent, const char *key, json_t *node, struct cfg_obj *child)
{
    memset(child, 0, sizeof *child);
    child->cfg = parent->cfg;
    child->node = node;
    snprintf(child->path, sizeof child->path, "%s.%s", parent->path, key);
    if (!json_is_object(node))
        return cfg_error_at(parent->cfg, child->path, "must be a mapping");
    return 0;
}

static int copy_name(struct cfg *c, const char *path, const char *s, char *out, size_t len)
{
    if (!s[0] || strlen(s) >= len)
        return cfg_error_at(c, path, "must be a name of 1 to %zu characters", len - 1);
    snprintf(out, len, "%s", s);
    return 0;
}

static int read_resolution(struct cfg_obj *rep, struct report_spec *rs)
{
    struct cfg *c = rep->cfg;
    cfg_allow(rep, "resolution");
    json_t *v = json_object_get(rep->node, "resolution");
    if (!v || json_is_null(v))
        return 0;
    char path[CFG_PATH_MAX];
    snprintf(path, sizeof path, "%s.resolution", rep->path);
    if (json_is_string(v)) {
        const char *s = json_string_value(v);
        if (strcmp(s, "none") == 0) {
            rs->res_mode = RES_NONE;
            return 0;
        }
        if (!docpath_valid(s))
            return cfg_error_at(c, path, "'%s' is not a swept case key (like md.timestep) or 'none'",
                                s);
        rs->res_mode = RES_AXIS;
        return copy_name(c, path, s, rs->res_axis, sizeof rs->res_axis);
    }
    struct cfg_obj r;
    int rc = cfg_section(rep, "resolution", &r);
    if (rc)
        return rc;
    const char *axis, *label;
    int hm, have_label;
    int h_given = json_object_get(r.node, "h") != NULL;
    if ((rc = cfg_string(&r, "axis", NULL, &axis)) ||
        (rc = cfg_enum(&r, "h", "value", hmap_names, &hm)) ||
        (rc = cfg_int(&r, "dim", 0, CFG_RANGE(0, 3), &rs->dim)) ||
        (rc = cfg_real(&r, "volume", 1.0, CFG_GT(0), &rs->volume)) ||
        (rc = cfg_string_opt(&r, "label", &label, &have_label)))
        return rc;
    rs->hmap = h_given ? (enum hmap)hm : HMAP_INFER;   /* absent: inferred from the values */
    if (have_label && (rc = copy_name(c, "report.resolution.label", label, rs->res_label,
                                      sizeof rs->res_label)))
        return rc;
    if (strcmp(axis, "none") == 0) {
        rs->res_mode = RES_NONE;
    } else {
        if (!docpath_valid(axis))
            return cfg_error_at(c, "report.resolution.axis",
                                "'%s' is not a swept case key (like md.timestep) or 'none'", axis);
        rs->res_mode = RES_AXIS;
        snprintf(rs->res_axis, sizeof rs->res_axis, "%s", axis);
    }
    return cfg_close(&r);
}

static int read_order(struct cfg_obj *rep, struct report_spec *rs)
{
    cfg_allow(rep, "order");
    json_t *v = json_object_get(rep->node, "order");
    if (!v || json_is_null(v))
        return 0;
    if (json_is_number(v))
        return cfg_real(rep, "order", NAN, CFG_GT(0), &rs->order_default);
    struct cfg_obj o;
    int rc = cfg_section(rep, "order", &o);
    if (rc)
        return rc;
    rs->orders = mem_calloc(json_object_size(o.node) + 1, sizeof *rs->orders);
    if (!rs->orders)
        return err_nomem(o.cfg->err, "orders");
    const char *key;
    json_t *val;
    json_object_foreach(o.node, key, val)
    {
        double p;
        if (json_is_null(val)) {   /* cfg_real would delete it, key and all, mid-iteration */
            char kp[CFG_PATH_MAX];
            snprintf(kp, sizeof kp, "%s.%s", o.path, key);
            return cfg_error_at(o.cfg, kp, "must be a number, found null");
        }
        if ((rc = cfg_real(&o, key, NAN, CFG_GT(0), &p)))
            return rc;
        if (strcmp(key, "default") == 0) {
            rs->order_default = p;
        } else {
            struct rspec_order *ro = &rs->orders[rs->norders++];
            if ((rc = copy_name(o.cfg, o.path, key, ro->metric, sizeof ro->metric)))
                return rc;
            ro->order = p;
        }
    }
    return 0;
}

static int read_metrics(struct cfg_obj *rep, struct report_spec *rs)
{
    const char *names[256];
    int n, rc = cfg_strings(rep, "metrics", 0, names, 256, &n);
    if (rc || n == 0)
        return rc;
    rs->metrics = mem_calloc((size_t)n, sizeof *rs->metrics);
    if (!rs->metrics)
        return err_nomem(rep->cfg->err, "report metrics");
    for (int i = 0; i < n; i++) {
        if (!(rs->metrics[i] = mem_strdup(names[i])))
            return err_nomem(rep->cfg->err, "report metrics");
        rs->nmetrics++;
    }
    return 0;
}

static int read_axes(struct cfg_obj *rep, struct report_spec *rs)
{
    struct cfg_obj ax;
    int present, rc = cfg_section_opt(rep, "axes", &ax, &present);
    if (rc || !present)
        return rc;
    rs->axes = mem_calloc(json_object_size(ax.node) + 1, sizeof *rs->axes);
    if (!rs->axes)
        return err_nomem(ax.cfg->err, "report axes");
    const char *key;
    json_t *val;
    json_object_foreach(ax.node, key, val)
    {
        cfg_allow(&ax, key);
        struct cfg_obj one;
        if ((rc = open_named(&ax, key, val, &one)))
            return rc;
        struct rspec_axis *a = &rs->axes[rs->naxes++];
        if (!docpath_valid(key))
            return cfg_error_at(ax.cfg, one.path, "'%s' is not a case key path", key);
        snprintf(a->path, sizeof a->path, "%s", key);
        const char *label;
        int have, log;
        json_t *lv = json_object_get(one.node, "log");
        if ((rc = cfg_string_opt(&one, "label", &label, &have)) ||
            (rc = cfg_bool(&one, "log", 0, &log)) || (rc = cfg_close(&one)))
            return rc;
        a->log = lv && json_is_boolean(lv) ? log : -1;
        if (have && (rc = copy_name(ax.cfg, one.path, label, a->label, sizeof a->label)))
            return rc;
    }
    return cfg_close(&ax);
}

static int read_fits(struct cfg_obj *rep, struct report_spec *rs)
{
    size_t n;
    int rc = cfg_list(rep, "fits", 0, &n);
    if (rc || n == 0)
        return rc;
    rs->fits = mem_calloc(n, sizeof *rs->fits);
    if (!rs->fits)
        return err_nomem(rep->cfg->err, "fits");
    for (size_t i = 0; i < n; i++) {
        struct cfg_obj f;
        if ((rc = cfg_list_item(rep, "fits", i, &f)))
            return rc;
        struct rspec_fit *ft = &rs->fits[rs->nfits++];
        snprintf(ft->where, sizeof ft->where, "report.fits[%zu]", i);
        const char *metric, *against, *along, *names[2];
        int model, nn, have_along;
        if ((rc = cfg_string(&f, "metric", NULL, &metric)) ||
            (rc = cfg_string(&f, "against", NULL, &against)) ||
            (rc = cfg_string_opt(&f, "along", &along, &have_along)) ||
            (rc = cfg_enum(&f, "model", "linear", fit_model_names, &model)) ||
            (rc = cfg_strings(&f, "names", 0, names, 2, &nn)) ||
            (rc = cfg_bool(&f, "extrapolated", 0, &ft->extrapolated)))
            return rc;
        ft->has_range = json_object_get(f.node, "range") != NULL;
        if (ft->has_range) {
            if ((rc = cfg_reals(&f, "range", 2, NULL, CFG_ANY, ft->range)))
                return rc;
            if (!(ft->range[0] < ft->range[1])) {
                char p[CFG_PATH_MAX + 8];
                snprintf(p, sizeof p, "%s.range", f.path);
                return cfg_error_at(f.cfg, p, "give [low, high] with low < high, not [%g, %g]",
                                    ft->range[0], ft->range[1]);
            }
        }
        if ((rc = cfg_close(&f)))
            return rc;
        if ((rc = copy_name(f.cfg, f.path, metric, ft->metric, sizeof ft->metric)) ||
            (rc = copy_name(f.cfg, f.path, against, ft->against, sizeof ft->against)) ||
            (have_along && (rc = copy_name(f.cfg, f.path, along, ft->along, sizeof ft->along))))
            return rc;
        ft->model = (enum fit_model)model;
        if (nn != 0 && nn != 2) {
            char p[CFG_PATH_MAX + 8];
            snprintf(p, sizeof p, "%s.names", f.path);
            return cfg_error_at(f.cfg, p, "give two parameter names (like [c0, s]), not %d", nn);
        }
        const char *def0 = model == FIT_LINEAR ? "a" : "A", *def1 = model == FIT_LINEAR ? "b" : "k";
        snprintf(ft->names[0], sizeof ft->names[0], "%s", nn == 2 ? names[0] : def0);
        snprintf(ft->names[1], sizeof ft->names[1], "%s", nn == 2 ? names[1] : def1);
    }
    return 0;
}

static int read_tol(struct cfg_obj *o, struct rspec_tol *t, const struct rspec_tol *def)
{
    int present, rc;
    if ((rc = cfg_real(o, "abs", def ? def->abs : 0.0, CFG_GE(0), &t->abs)) ||
        (rc = cfg_real(o, "rel", def ? def->rel : 0.0, CFG_GE(0), &t->rel)) ||
        (rc = cfg_real_opt(o, "order", CFG_GE(0), &t->order, &present)) || (rc = cfg_close(o)))
        return rc;
    if (!present)
        t->order = NAN;
    return 0;
}

static int read_regress(struct cfg_obj *root, struct report_spec *rs)
{
    struct cfg_obj rg;
    int present, rc = cfg_section_opt(root, "regress", &rg, &present);
    if (rc || !present)
        return rc;
    const char *baseline;
    int have;
    if ((rc = cfg_string_opt(&rg, "baseline", &baseline, &have)) ||
        (rc = cfg_real(&rg, "order", rs->order_tol, CFG_GE(0), &rs->order_tol)))
        return rc;
    if (have && (rc = copy_name(rg.cfg, "regress.baseline", baseline, rs->baseline,
                                sizeof rs->baseline)))
        return rc;
    struct cfg_obj tl;
    if ((rc = cfg_section_opt(&rg, "tolerances", &tl, &present)))
        return rc;
    if (present) {
        json_t *dv = json_object_get(tl.node, "default");
        if (dv) {
            cfg_allow(&tl, "default");
            struct cfg_obj one;
            if ((rc = open_named(&tl, "default", dv, &one)) ||
                (rc = read_tol(&one, &rs->tol_default, NULL)))
                return rc;
        }
        rs->tols = mem_calloc(json_object_size(tl.node) + 1, sizeof *rs->tols);
        if (!rs->tols)
            return err_nomem(tl.cfg->err, "tolerances");
        const char *key;
        json_t *val;
        json_object_foreach(tl.node, key, val)
        {
            if (strcmp(key, "default") == 0)
                continue;
            cfg_allow(&tl, key);
            struct cfg_obj one;
            struct rspec_tol *t = &rs->tols[rs->ntols++];
            if ((rc = open_named(&tl, key, val, &one)) ||
                (rc = copy_name(tl.cfg, one.path, key, t->metric, sizeof t->metric)) ||
                (rc = read_tol(&one, t, &rs->tol_default)))
                return rc;
        }
        if ((rc = cfg_close(&tl)))
            return rc;
    }
    return cfg_close(&rg);
}

int report_spec_read(struct cfg_obj *root, struct report_spec *rs)
{
    report_spec_init(rs);
    struct cfg_obj rep;
    int present, rc = cfg_section_opt(root, "report", &rep, &present);
    if (!rc && present) {
        if ((rc = read_resolution(&rep, rs)) || (rc = read_order(&rep, rs)) ||
            (rc = cfg_real(&rep, "safety", 1.25, CFG_RANGE(1, 10), &rs->safety)) ||
            (rc = read_metrics(&rep, rs)) || (rc = read_axes(&rep, rs)) ||
            (rc = read_fits(&rep, rs)) || (rc = cfg_close(&rep)))
            return rc;
    }
    if (!rc)
        rc = read_regress(root, rs);
    return rc;
}

int report_spec_from_text(const char *text, size_t len, const char *name, struct report_spec *rs,
                          struct err *e)
{
    json_t *doc = NULL;
    struct locmap *locs = NULL;
    report_spec_init(rs);
    int rc = yamldoc_load_string(text, len, name, &doc, &locs, e);
    if (!rc) {
        struct cfg c = {name, locs, e, ".", 1};
        struct cfg_obj root;
        rc = cfg_root(&c, doc, &root);
        if (!rc)
            rc = report_spec_read(&root, rs);
    }
    json_decref(doc);
    locmap_destroy(&locs);
    if (rc)
        report_spec_free(rs);
    return rc;
}

double report_spec_order(const struct report_spec *rs, const char *metric)
{
    for (int i = 0; i < rs->norders; i++)
        if (strcmp(rs->orders[i].metric, metric) == 0)
            return rs->orders[i].order;
    return rs->order_default;
}

const struct rspec_axis *report_spec_axis(const struct report_spec *rs, const char *path)
{
    for (int i = 0; i < rs->naxes; i++)
        if (strcmp(rs->axes[i].path, path) == 0)
            return &rs->axes[i];
    return NULL;
}

void report_spec_tol(const struct report_spec *rs, const char *metric, double *abs, double *rel,
                     double *order)
{
    const struct rspec_tol *t = &rs->tol_default;
    for (int i = 0; i < rs->ntols; i++)
        if (strcmp(rs->tols[i].metric, metric) == 0)
            t = &rs->tols[i];
    *abs = t->abs;
    *rel = t->rel;
    *order = isnan(t->order) ? (isnan(rs->tol_default.order) ? rs->order_tol : rs->tol_default.order)
                             : t->order;
}

int report_spec_wants(const struct report_spec *rs, const char *metric)
{
    if (!rs->metrics)
        return 1;
    for (int i = 0; i < rs->nmetrics; i++)
        if (strcmp(rs->metrics[i], metric) == 0)
            return 1;
    return 0;
}
