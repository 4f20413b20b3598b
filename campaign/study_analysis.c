/* study_analysis: points, groups, convergence and series of a report (see study_analysis.h). */
#include "study_analysis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/canon.h"
#include "util/mem.h"

/* Flag thresholds (documented in docs/reports.md). */
#define SA_FORMAL_TOL 0.25     /* |p - formal| > 25 % of the formal order */
#define SA_LOCAL_TOL 0.25      /* local orders of the two finest triples differ by > 25 % */
#define SA_ASYMPTOTIC_TOL 0.1  /* Celik's ratio further than 10 % from 1 */
#define SA_LOGX_SPAN 20.0      /* an axis spanning 20x or more is plotted on a log scale */

/* A value for people: strings bare, numbers shortest, lists and mappings in
 * YAML flow style ({style: eam/alloy, file: x}) in the keys' canonical order. */
static void value_text(const json_t *v, char *out, size_t len)
{
    if (len == 0)
        return;
    out[0] = '\0';
    if (json_is_string(v)) {
        snprintf(out, len, "%s", json_string_value(v));
    } else if (json_is_integer(v)) {
        snprintf(out, len, "%lld", (long long)json_integer_value(v));
    } else if (json_is_real(v)) {
        canon_real(json_real_value(v), out, len);
    } else if (json_is_array(v)) {
        size_t used = snprintf(out, len, "[");
        for (size_t i = 0; i < json_array_size(v) && used < len; i++) {
            char one[SA_LABEL_MAX];
            value_text(json_array_get(v, i), one, sizeof one);
            used += snprintf(out + used, len - used, "%s%s", i ? ", " : "", one);
        }
        if (used < len)
            snprintf(out + used, len - used, "]");
    } else if (json_is_object(v)) {
        /* canonical (sorted) key order, so equal mappings print alike */
        char *canon = canon_json(v);
        json_t *sorted = canon ? json_loads(canon, 0, NULL) : NULL;
        free(canon);
        size_t used = snprintf(out, len, "{");
        const char *k;
        json_t *x;
        int first = 1;
        json_object_foreach(sorted, k, x)
        {
            if (used >= len)
                break;
            char one[SA_LABEL_MAX];
            value_text(x, one, sizeof one);
            used += snprintf(out + used, len - used, "%s%s: %s", first ? "" : ", ", k, one);
            first = 0;
        }
        if (used < len)
            snprintf(out + used, len - used, "}");
        json_decref(sorted);
    } else if (json_is_boolean(v)) {
        snprintf(out, len, "%s", json_is_true(v) ? "true" : "false");
    } else {
        snprintf(out, len, "null");
    }
}

void sa_params_label(const json_t *params, char *out, size_t len)
{
    out[0] = '\0';
    const char *k;
    json_t *v;
    size_t used = 0;
    json_object_foreach((json_t *)params, k, v)
    {
        char val[SA_LABEL_MAX];
        value_text(v, val, sizeof val);
        int w = snprintf(out + used, len - used, "%s%s=%s", used ? " " : "", k, val);
        if (w < 0 || (size_t)w >= len - used)
            break;
        used += (size_t)w;
    }
    if (!out[0])
        snprintf(out, len, "all jobs");
}

void sa_job_label(const struct rdata *d, const json_t *params, char *out, size_t len)
{
    json_t *ordered = json_object();
    for (int i = 0; i < d->naxes; i++) {
        json_t *v = json_object_get(params, d->axes[i].name);
        if (v)
            json_object_set(ordered, d->axes[i].name, v);
    }
    sa_params_label(json_object_size(ordered) ? ordered : params, out, len);
    json_decref(ordered);
}

/* The grouping key of a parameter set: 0, or -1 when out of memory (a
 * stand-in key would merge points that differ). */
static int key_of(const json_t *obj, char *out, size_t len)
{
    char *t = obj ? canon_json(obj) : NULL;
    if (!t)
        return -1;
    snprintf(out, len, "%s", t);
    free(t);
    return 0;
}

/* The swept values of a job restricted to axes for which keep(axis) holds,
 * in the study's axis order. */
static json_t *restrict_params(const struct rdata *d, const json_t *params,
                               int (*keep)(const struct study_analysis *, int, int),
                               const struct study_analysis *a, int extra)
{
    json_t *out = json_object();
    for (int i = 0; i < d->naxes; i++) {
        json_t *v = json_object_get(params, d->axes[i].name);
        if (v && keep(a, i, extra))
            json_object_set(out, d->axes[i].name, v);
    }
    return out;
}

static int keep_point(const struct study_analysis *a, int i, int extra)
{
    (void)extra;
    return !a->d->axes[i].repeat;
}

static int keep_group(const struct study_analysis *a, int i, int extra)
{
    (void)extra;
    return !a->d->axes[i].repeat && a->d->axes[i].grp != a->res.grp;
}

/* the group's values without factor `extra` (a factor index, or -1 for all) */
static int keep_rest(const struct study_analysis *a, int i, int extra)
{
    return keep_group(a, i, 0) && extra >= 0 && a->d->axes[i].grp != extra;
}

/* Index of `key` in dict, adding `next` when absent. */
static int dict_index(json_t *dict, const char *key, int next, int *added)
{
    json_t *v = json_object_get(dict, key);
    *added = v == NULL;
    if (v)
        return (int)json_integer_value(v);
    json_object_set_new(dict, key, json_integer(next));
    return next;
}

/* Room for element n of arrays that double at powers of two. */
static int grow_long(long **arr, int n)
{
    if (n & (n - 1))
        return 0;
    long *g = mem_realloc(*arr, (size_t)(n ? 2 * n : 1) * sizeof *g);
    if (!g)
        return -1;
    *arr = g;
    return 0;
}

static int grow_double(double **arr, int n)
{
    if (n & (n - 1))
        return 0;
    double *g = mem_realloc(*arr, (size_t)(n ? 2 * n : 1) * sizeof *g);
    if (!g)
        return -1;
    *arr = g;
    return 0;
}

static int grow_int(int **arr, int n)
{
    if (n & (n - 1))
        return 0;
    int *g = mem_realloc(*arr, (size_t)(n ? 2 * n : 1) * sizeof *g);
    if (!g)
        return -1;
    *arr = g;
    return 0;
}

static int build_points(struct study_analysis *a, struct err *e)
{
    const struct rdata *d = a->d;
    json_t *pdict = json_object(), *gdict = json_object();
    int rc = 0;
    a->pts = mem_calloc((size_t)(d->njobs ? d->njobs : 1), sizeof *a->pts);
    a->groups = mem_calloc((size_t)(d->njobs ? d->njobs : 1), sizeof *a->groups);
    if (!a->pts || !a->groups || !pdict || !gdict)
        rc = err_nomem(e, "points");
    for (long j = 0; !rc && j < d->njobs; j++) {
        const struct rd_job *job = &d->jobs[j];
        if (job->prep)
            continue;
        a->nsweep++;
        a->ndone += job->solver != NULL;
        json_t *pp = restrict_params(d, job->params, keep_point, a, 0);
        char key[SA_LABEL_MAX];
        if (key_of(pp, key, sizeof key) != 0) {
            json_decref(pp);
            rc = err_nomem(e, "points");
            break;
        }
        int added, p = dict_index(pdict, key, a->npts, &added);
        struct sa_point *pt = &a->pts[p];
        if (added) {
            a->npts++;
            pt->params = pp;
            snprintf(pt->key, sizeof pt->key, "%s", key);
            sa_params_label(pp, pt->label, sizeof pt->label);
            pt->h = a->res.axis >= 0
                        ? resolution_h(&a->res, json_object_get(pp, d->axes[a->res.axis].name))
                        : NAN;
            json_t *gp = restrict_params(d, job->params, keep_group, a, 0);
            char gkey[SA_LABEL_MAX];
            if (key_of(gp, gkey, sizeof gkey) != 0) {
                json_decref(gp);
                rc = err_nomem(e, "points");
                break;
            }
            int gadded, g = dict_index(gdict, gkey, a->ngroups, &gadded);
            struct sa_group *gr = &a->groups[g];
            if (gadded) {
                a->ngroups++;
                gr->params = gp;
                snprintf(gr->key, sizeof gr->key, "%s", gkey);
                sa_params_label(gp, gr->label, sizeof gr->label);
            } else {
                json_decref(gp);
            }
            if (grow_int(&gr->pts, gr->npts)) {
                rc = err_nomem(e, "points");
                break;
            }
            pt->group = g;
            gr->pts[gr->npts++] = p;
        } else {
            json_decref(pp);
        }
        if (grow_long(&pt->jobs, pt->njobs)) {
            rc = err_nomem(e, "points");
            break;
        }
        pt->jobs[pt->njobs++] = j;
    }
    json_decref(pdict);
    json_decref(gdict);
    if (rc)
        return rc;
    /* each group's points in ascending h (insertion sort: groups are short) */
    for (int g = 0; g < a->ngroups; g++) {
        struct sa_group *gr = &a->groups[g];
        for (int i = 1; i < gr->npts; i++) {
            int p = gr->pts[i], k = i;
            double h = a->pts[p].h;
            while (k > 0 && a->pts[gr->pts[k - 1]].h > h) {
                gr->pts[k] = gr->pts[k - 1];
                k--;
            }
            gr->pts[k] = p;
        }
    }
    /* mean and standard deviation over repeats */
    for (int p = 0; p < a->npts; p++) {
        struct sa_point *pt = &a->pts[p];
        size_t nm = (size_t)(d->nmetrics ? d->nmetrics : 1);
        pt->mean = mem_calloc(nm, sizeof *pt->mean);
        pt->sd = mem_calloc(nm, sizeof *pt->sd);
        pt->n = mem_calloc(nm, sizeof *pt->n);
        if (!pt->mean || !pt->sd || !pt->n)
            return err_nomem(e, "point statistics");
        for (int m = 0; m < d->nmetrics; m++) {
            double s = 0, s2 = 0;
            int n = 0;
            for (int k = 0; k < pt->njobs; k++) {
                double v = d->jobs[pt->jobs[k]].val[m];
                if (isfinite(v)) {
                    s += v;
                    n++;
                }
            }
            double mean = n ? s / n : NAN;
            for (int k = 0; k < pt->njobs; k++) {
                double v = d->jobs[pt->jobs[k]].val[m];
                if (isfinite(v))
                    s2 += (v - mean) * (v - mean);
            }
            pt->mean[m] = mean;
            pt->n[m] = n;
            pt->sd[m] = n > 1 ? sqrt(s2 / (n - 1)) : NAN;
        }
    }
    return 0;
}

static void add_flag(struct sa_conv *c, const char *text, int serious)
{
    size_t used = strlen(c->flags);
    snprintf(c->flags + used, sizeof c->flags - used, "%s%s", used ? "; " : "", text);
    if (serious)
        c->flagged = 1;
}

static int analyse_one(struct study_analysis *a, int k, int g, struct err *e)
{
    const struct rdata *d = a->d;
    struct sa_conv *c = sa_conv_at(a, k, g);
    const struct sa_group *gr = &a->groups[g];
    int m = a->metrics[k];
    c->metric = m;
    c->group = g;
    c->formal = report_spec_order(a->rs, d->metric[m]);
    c->pts = mem_alloc((size_t)(gr->npts ? gr->npts : 1) * sizeof *c->pts);
    c->local_p = mem_alloc((size_t)(gr->npts ? gr->npts : 1) * sizeof *c->local_p);
    c->local_kind = mem_alloc((size_t)(gr->npts ? gr->npts : 1) * sizeof *c->local_kind);
    if (!c->pts || !c->local_p || !c->local_kind)
        return err_nomem(e, "convergence");
    for (int i = 0; i < gr->npts; i++) {
        const struct sa_point *pt = &a->pts[gr->pts[i]];
        if (isfinite(pt->mean[m]) && isfinite(pt->h))
            c->pts[c->npts++] = gr->pts[i];
        else if (c->npts == 0)
            c->finest_missing = 1;
    }
    for (int i = 0; i < c->npts; i++) {
        c->local_p[i] = NAN;
        c->local_kind[i] = -1;
    }
    /* local orders: every three consecutive grids with a value */
    for (int i = 0; i + 2 < c->npts; i++) {
        double h[3], phi[3];
        for (int q = 0; q < 3; q++) {
            h[q] = a->pts[c->pts[i + q]].h;
            phi[q] = a->pts[c->pts[i + q]].mean[m];
        }
        struct conv_result r;
        struct err le = {0};
        if (conv_three_grid(h, phi, a->rs->safety, &r, &le) == 0) {
            c->local_p[i] = r.p;
            c->local_kind[i] = (int)r.kind;
        }
    }
    if (c->npts < 3) {
        c->status = SA_FEW;
        snprintf(c->note, sizeof c->note, "%d grid%s with a value: the observed order needs three",
                 c->npts, c->npts == 1 ? "" : "s");
        add_flag(c, "fewer than three grids", 1);
        return 0;
    }
    double h[3], phi[3];
    for (int q = 0; q < 3; q++) {
        h[q] = a->pts[c->pts[q]].h;
        phi[q] = a->pts[c->pts[q]].mean[m];
    }
    struct err ce = {0};
    if (conv_three_grid(h, phi, a->rs->safety, &c->c, &ce) != 0) {
        c->status = SA_ERROR;
        snprintf(c->note, sizeof c->note, "%s", ce.msg);
        add_flag(c, "no order", 1);
        return 0;
    }
    c->status = SA_OK;
    const struct conv_result *r = &c->c;
    if (r->kind == CONV_OSCILLATORY)
        add_flag(c, "oscillatory", 1);
    else if (r->kind == CONV_DIVERGENT)
        add_flag(c, "divergent", 1);
    else if (r->kind == CONV_INDETERMINATE)
        add_flag(c, "indeterminate: equal values on two grids", 0);
    if (c->finest_missing)
        add_flag(c, "finest grid has no value", 1);
    if (isfinite(r->phi_ext)) {
        /* the GCI in the metric's unit: Fs |eps21| / (r21^p - 1) */
        c->abs_unc = a->rs->safety * fabs(r->phi[1] - r->phi[0]) / (pow(r->r21, r->p) - 1);
        c->limit_near_zero = fabs(r->phi_ext) < fabs(r->phi[0] - r->phi_ext);
    } else {
        c->abs_unc = NAN;
    }
    if (isfinite(r->p) && isfinite(c->formal) && fabs(r->p - c->formal) > SA_FORMAL_TOL * c->formal) {
        char t[96];
        snprintf(t, sizeof t, "p far from the formal order %g", c->formal);
        add_flag(c, t, 1);
    }
    if (c->limit_near_zero)
        add_flag(c, "limit near 0: relative GCI meaningless, use the band", 0);
    else if (isfinite(r->asymptotic) && fabs(r->asymptotic - 1) > SA_ASYMPTOTIC_TOL)
        add_flag(c, "not in the asymptotic range", 1);
    if (c->npts >= 4 && isfinite(c->local_p[0]) && isfinite(c->local_p[1]) &&
        fabs(c->local_p[1] - c->local_p[0]) > SA_LOCAL_TOL * fabs(c->local_p[0]))
        add_flag(c, "order changes with h", 1);
    return 0;
}

/* The finest point of group g with a finite value of metric m, or -1. */
static int finest_point(const struct study_analysis *a, int g, int m)
{
    const struct sa_group *gr = &a->groups[g];
    for (int i = 0; i < gr->npts; i++)
        if (isfinite(a->pts[gr->pts[i]].mean[m]))
            return gr->pts[i];
    return -1;
}

static double extrapolated(const struct study_analysis *a, int m, int g)
{
    if (!a->conv)
        return NAN;
    for (int k = 0; k < a->nmetrics; k++)
        if (a->metrics[k] == m) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            return c->status == SA_OK ? c->c.phi_ext : NAN;
        }
    return NAN;
}

static int find_fit(const struct study_analysis *a, const char *metric, const char *against)
{
    for (int f = 0; f < a->rs->nfits; f++)
        if (strcmp(a->rs->fits[f].metric, metric) == 0 &&
            strcmp(a->rs->fits[f].against, against) == 0)
            return f;
    return -1;
}

static int grow_xs(struct study_analysis *a, int *cap, struct err *e)
{
    if (a->nxs < *cap)
        return 0;
    *cap = *cap ? 2 * *cap : 16;
    struct sa_xseries *g = mem_realloc(a->xs, (size_t)*cap * sizeof *g);
    if (!g)
        return err_nomem(e, "series");
    a->xs = g;
    return 0;
}

static int add_xplot(struct study_analysis *a, const struct sa_xplot *p, struct err *e)
{
    struct sa_xplot *g = mem_realloc(a->xplots, (size_t)(a->nxplots + 1) * sizeof *g);
    if (!g)
        return err_nomem(e, "plots");
    a->xplots = g;
    a->xplots[a->nxplots++] = *p;
    return 0;
}

/* Series of metric m against axis xa (factor xg) or metric xm, keyed by the
 * values of the axes outside factor `rest_out` (-1: one series). */
static int build_series(struct study_analysis *a, int m, int xa, int xm, int rest_out, int fit,
                        int use_ext, int *cap, struct err *e)
{
    const struct rdata *d = a->d;
    json_t *dict = json_object();
    int first = a->nxs, rc = 0;
    for (int g = 0; g < a->ngroups && !rc; g++) {
        int p = finest_point(a, g, m);
        double x, y, yext = extrapolated(a, m, g), ysd = NAN;
        if (xa >= 0) {
            x = res_number(json_object_get(a->groups[g].params, d->axes[xa].name));
            y = p >= 0 ? a->pts[p].mean[m] : NAN;
            ysd = p >= 0 ? a->pts[p].sd[m] : NAN;
        } else {
            /* the finest grid with both values */
            const struct sa_group *gr = &a->groups[g];
            x = y = NAN;
            for (int i = 0; i < gr->npts; i++) {
                const struct sa_point *pt = &a->pts[gr->pts[i]];
                if (isfinite(pt->mean[m]) && isfinite(pt->mean[xm])) {
                    x = pt->mean[xm];
                    y = pt->mean[m];
                    ysd = pt->sd[m];
                    break;
                }
            }
            if (use_ext)
                x = extrapolated(a, xm, g);
        }
        if (!isfinite(x))
            continue;
        json_t *rest = rest_out >= 0
                           ? restrict_params(d, a->groups[g].params, keep_rest, a, rest_out)
                           : json_object();
        char key[SA_LABEL_MAX];
        if (key_of(rest, key, sizeof key) != 0) {
            json_decref(rest);
            rc = err_nomem(e, "series");
            break;
        }
        int added, s = dict_index(dict, key, a->nxs - first, &added);
        if (added) {
            if ((rc = grow_xs(a, cap, e))) {
                json_decref(rest);
                break;
            }
            struct sa_xseries *xs = &a->xs[a->nxs++];
            memset(xs, 0, sizeof *xs);
            xs->metric = m;
            xs->xaxis = xa;
            xs->xmetric = xm;
            xs->fit = fit;
            sa_params_label(rest, xs->label, sizeof xs->label);
            if (!json_object_size(rest))
                snprintf(xs->label, sizeof xs->label, "all");
        }
        json_decref(rest);
        if (rc)
            break;
        struct sa_xseries *xs = &a->xs[first + s];
        if (grow_double(&xs->x, xs->n) || grow_double(&xs->y, xs->n) ||
            grow_double(&xs->yext, xs->n) || grow_double(&xs->ysd, xs->n)) {
            rc = err_nomem(e, "series");
            break;
        }
        /* insertion by x */
        int i = xs->n++;
        while (i > 0 && xs->x[i - 1] > x) {
            xs->x[i] = xs->x[i - 1];
            xs->y[i] = xs->y[i - 1];
            xs->yext[i] = xs->yext[i - 1];
            xs->ysd[i] = xs->ysd[i - 1];
            i--;
        }
        xs->x[i] = x;
        xs->y[i] = y;
        xs->yext[i] = yext;
        xs->ysd[i] = ysd;
    }
    json_decref(dict);
    if (rc)
        return rc;
    for (int s = first; s < a->nxs; s++) {
        struct sa_xseries *xs = &a->xs[s];
        if (fit >= 0) {
            const struct rspec_fit *f = &a->rs->fits[fit];
            const double *yy = f->extrapolated && xa >= 0 ? xs->yext : xs->y;
            if (f->has_range) {
                /* the points inside the range only (x is sorted: a slice) */
                int i0 = 0, i1 = xs->n;
                while (i0 < xs->n && !(xs->x[i0] >= f->range[0]))
                    i0++;
                while (i1 > i0 && !(xs->x[i1 - 1] <= f->range[1]))
                    i1--;
                xs->fit_ok = fit_points(f->model, xs->x + i0, yy + i0, i1 - i0, &xs->fr) == 0;
            } else {
                xs->fit_ok = fit_points(f->model, xs->x, yy, xs->n, &xs->fr) == 0;
            }
        }
    }
    if (a->nxs == first)
        return 0;
    struct sa_xplot pl = {m, xa, xm, fit, first, a->nxs - first, 0};
    double lo = INFINITY, hi = -INFINITY;
    for (int s = first; s < a->nxs; s++)
        for (int i = 0; i < a->xs[s].n; i++) {
            lo = fmin(lo, a->xs[s].x[i]);
            hi = fmax(hi, a->xs[s].x[i]);
        }
    const struct rspec_axis *opt = xa >= 0 ? report_spec_axis(a->rs, d->axes[xa].name) : NULL;
    if (opt && opt->log >= 0)
        pl.logx = opt->log;
    else
        pl.logx = lo > 0 && hi / lo >= SA_LOGX_SPAN;
    if (fit >= 0 && a->rs->fits[fit].model == FIT_POWER)
        pl.logx = 1;
    return add_xplot(a, &pl, e);
}

/* The axis plotted for a factor: its first axis with numeric values, at
 * least two of them distinct. */
static int factor_axis(const struct study_analysis *a, int grp)
{
    const struct rdata *d = a->d;
    for (int i = 0; i < d->naxes; i++) {
        if (d->axes[i].grp != grp || d->axes[i].repeat)
            continue;
        size_t k;
        json_t *v;
        double first = NAN;
        int numeric = 1, distinct = 0;
        json_array_foreach(d->axes[i].values, k, v)
        {
            double x = res_number(v);
            if (!isfinite(x))
                numeric = 0;
            else if (isnan(first))
                first = x;
            else if (x != first)
                distinct = 1;
        }
        if (numeric && distinct)
            return i;
    }
    return -1;
}

static int build_xseries(struct study_analysis *a, struct err *e)
{
    const struct rdata *d = a->d;
    int cap = 0, rc = 0;
    for (int k = 0; k < a->nmetrics && !rc; k++) {
        int m = a->metrics[k];
        int seen_grp[256] = {0};
        for (int i = 0; i < d->naxes && !rc; i++) {
            int grp = d->axes[i].grp;
            if (d->axes[i].repeat || grp == a->res.grp || grp < 0 || grp >= 256 || seen_grp[grp])
                continue;
            seen_grp[grp] = 1;
            int xa = factor_axis(a, grp);
            if (xa < 0)
                continue;
            int fit = find_fit(a, d->metric[m], d->axes[xa].name);
            rc = build_series(a, m, xa, -1, grp, fit, 0, &cap, e);
        }
    }
    /* metric against metric */
    for (int f = 0; f < a->rs->nfits && !rc; f++) {
        const struct rspec_fit *ft = &a->rs->fits[f];
        if (rdata_axis(d, ft->against) >= 0)
            continue;
        int m = rdata_metric(d, ft->metric), xm = rdata_metric(d, ft->against);
        if (m < 0 || xm < 0)
            continue;   /* reported as missing by the report */
        int along = ft->along[0] ? rdata_axis(d, ft->along) : -1;
        rc = build_series(a, m, -1, xm, along >= 0 ? d->axes[along].grp : -1, f,
                          ft->extrapolated, &cap, e);
    }
    return rc;
}

static int choose_metrics(struct study_analysis *a, struct err *e)
{
    const struct rdata *d = a->d;
    a->metrics = mem_alloc((size_t)(d->nmetrics ? d->nmetrics : 1) * sizeof *a->metrics);
    if (!a->metrics)
        return err_nomem(e, "metrics");
    for (int m = 0; m < d->nmetrics; m++)
        if (report_spec_wants(a->rs, d->metric[m]))
            a->metrics[a->nmetrics++] = m;
    return 0;
}

int sa_build(struct study_analysis *a, const struct rdata *d, const struct report_spec *rs,
             struct err *e)
{
    memset(a, 0, sizeof *a);
    a->d = d;
    a->rs = rs;
    struct res_axis_info *ai = mem_calloc((size_t)(d->naxes ? d->naxes : 1), sizeof *ai);
    if (!ai)
        return err_nomem(e, "axes");
    for (int i = 0; i < d->naxes; i++)
        ai[i] = (struct res_axis_info){d->axes[i].name, d->axes[i].grp, d->axes[i].repeat,
                                       d->axes[i].values};
    int rc = resolution_choose(rs, ai, d->naxes, &a->res, e);
    free(ai);
    for (int f = 0; !rc && f < rs->nfits; f++) {
        const struct rspec_fit *ft = &rs->fits[f];
        if (ft->along[0] && rdata_axis(d, ft->along) < 0)
            rc = err_set(e, ERR_INPUT, "%s.along: '%s' is not a swept axis of the study", ft->where,
                         ft->along);
    }
    if (!rc)
        rc = choose_metrics(a, e);
    if (!rc)
        rc = build_points(a, e);
    if (!rc && a->res.axis >= 0 && a->nmetrics > 0 && a->ngroups > 0) {
        a->conv = mem_calloc((size_t)a->nmetrics * (size_t)a->ngroups, sizeof *a->conv);
        if (!a->conv)
            rc = err_nomem(e, "convergence");
        for (int k = 0; !rc && k < a->nmetrics; k++)
            for (int g = 0; !rc && g < a->ngroups; g++)
                rc = analyse_one(a, k, g, e);
    }
    if (!rc)
        rc = build_xseries(a, e);
    if (rc)
        sa_free(a);
    return rc;
}

struct sa_conv *sa_conv_at(const struct study_analysis *a, int k, int g)
{
    return a->conv ? &a->conv[(size_t)k * (size_t)a->ngroups + (size_t)g] : NULL;
}

void sa_free(struct study_analysis *a)
{
    for (int p = 0; p < a->npts; p++) {
        json_decref(a->pts[p].params);
        free(a->pts[p].jobs);
        free(a->pts[p].mean);
        free(a->pts[p].sd);
        free(a->pts[p].n);
    }
    free(a->pts);
    for (int g = 0; g < a->ngroups; g++) {
        json_decref(a->groups[g].params);
        free(a->groups[g].pts);
    }
    free(a->groups);
    if (a->conv)
        for (int i = 0; i < a->nmetrics * a->ngroups; i++) {
            free(a->conv[i].pts);
            free(a->conv[i].local_p);
            free(a->conv[i].local_kind);
        }
    free(a->conv);
    for (int s = 0; s < a->nxs; s++) {
        free(a->xs[s].x);
        free(a->xs[s].y);
        free(a->xs[s].yext);
        free(a->xs[s].ysd);
    }
    free(a->xs);
    free(a->xplots);
    free(a->metrics);
    memset(a, 0, sizeof *a);
}
