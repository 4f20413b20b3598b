/* refine_run: adaptive refinement along the resolution axis (see refine_run.h). */
#include "refine_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "conv_store.h"
#include "db.h"
#include "rdata.h"
#include "refine_state.h"
#include "study_analysis.h"
#include "util/canon.h"
#include "util/mem.h"

struct level_cost {
    double h, wall;           /* per job, mean over the level's jobs */
    int njobs;
};

struct series {
    char key[SA_LABEL_MAX];   /* canonical JSON of the other swept values */
    int kref;                 /* levels added beyond the start levels */
    const char *state;
    char reason[512];
    double next_core_s;
};

struct refine {
    const struct study *s;
    const struct refine_spec *r;
    int ax, grp;              /* the axis and its factor */
    int nstart;
    int nref;                 /* levels added to the axis values (the most any series has) */
    json_t **added;           /* [naxes]: values appended to each axis of the factor */
    struct series *ser;
    int nser, cap;
    double cores;             /* per job */
    struct study t;           /* the study with the extended values (axes and group_len owned) */
};

static struct series *series_get(struct refine *f, const char *key, int add)
{
    for (int i = 0; i < f->nser; i++)
        if (strcmp(f->ser[i].key, key) == 0)
            return &f->ser[i];
    if (!add)
        return NULL;
    if (f->nser == f->cap) {
        int cap = f->cap ? 2 * f->cap : 16;
        struct series *g = mem_realloc(f->ser, (size_t)cap * sizeof *g);
        if (!g)
            return NULL;
        f->ser = g;
        f->cap = cap;
    }
    struct series *s = &f->ser[f->nser++];
    memset(s, 0, sizeof *s);
    snprintf(s->key, sizeof s->key, "%s", key);
    s->state = "refining";
    return s;
}

/* The values of the swept keys outside the axis's factor and the repeats,
 * as canonical JSON: the series a job belongs to (as the report groups). */
static void series_key(const struct study *s, int grp, const json_t *params, char *out, size_t len)
{
    json_t *o = json_object();
    for (int i = 0; i < s->naxes; i++) {
        json_t *v = json_object_get(params, s->axes[i].path);
        if (v && s->axes[i].kind != AXIS_REPEAT && s->axes[i].group != grp &&
            strcmp(s->axes[i].path, "seed") != 0)
            json_object_set(o, s->axes[i].path, v);
    }
    char *t = canon_json(o);
    snprintf(out, len, "%s", t ? t : "{}");
    free(t);
    json_decref(o);
}

/* --- the study with the added levels ---------------------------------------- */

static void extended_free(struct refine *f)
{
    if (f->t.axes) {
        for (int i = 0; i < f->s->naxes; i++)
            json_decref(f->t.axes[i].values);
        free(f->t.axes);
    }
    free(f->t.group_len);
    memset(&f->t, 0, sizeof f->t);
}

static int extended_build(struct refine *f, struct err *e)
{
    extended_free(f);
    const struct study *s = f->s;
    f->t = *s;
    f->t.axes = mem_calloc((size_t)s->naxes, sizeof *f->t.axes);
    f->t.group_len = mem_calloc((size_t)s->ngroups, sizeof *f->t.group_len);
    if (!f->t.axes || !f->t.group_len) {
        free(f->t.axes);
        free(f->t.group_len);
        memset(&f->t, 0, sizeof f->t);
        return err_nomem(e, "refinement");
    }
    for (int i = 0; i < s->naxes; i++) {
        f->t.axes[i] = s->axes[i];
        if (s->axes[i].group == f->grp) {
            json_t *v = json_copy(s->axes[i].values);
            json_array_extend(v, f->added[i]);
            f->t.axes[i].values = v;
        } else {
            f->t.axes[i].values = json_incref(s->axes[i].values);
        }
    }
    long n = 1;
    for (int g = 0; g < s->ngroups; g++) {
        f->t.group_len[g] = s->group_len[g] + (g == f->grp ? f->nref : 0);
        n *= f->t.group_len[g];
    }
    f->t.njobs = n;
    return 0;
}

/* plan_filter: keep the levels each series has been given. */
static int keep_levels(void *ctx, struct plan *p, struct err *e)
{
    struct refine *f = ctx;
    long *idx = mem_alloc((size_t)(f->t.ngroups ? f->t.ngroups : 1) * sizeof *idx);
    if (!idx)
        return err_nomem(e, "refinement");
    long k = 0;
    for (long j = 0; j < p->njobs; j++) {
        struct plan_job *pj = &p->jobs[j];
        int keep = 1;
        if (pj->sweep >= 0) {
            study_job_indices(&f->t, pj->sweep, idx);
            json_t *params = json_loads(pj->params_json, 0, NULL);
            char key[SA_LABEL_MAX];
            series_key(f->s, f->grp, params, key, sizeof key);
            json_decref(params);
            const struct series *ser = series_get(f, key, 0);
            keep = idx[f->grp] < f->nstart + (ser ? ser->kref : 0);
        }
        if (keep) {
            p->jobs[k++] = *pj;
        } else {
            free(pj->case_json);
            free(pj->params_json);
            free(pj->deps);
        }
    }
    p->njobs = k;
    free(idx);
    return 0;
}

/* --- the next level ------------------------------------------------------- */

/* x * factor, an integer when x is one and the product is whole. */
static json_t *scaled(const json_t *v, double factor, int *ok)
{
    double x = res_number(v);
    if (!isfinite(x)) {
        *ok = 0;
        return json_null();
    }
    double y = x * factor;
    int wrap = json_is_array(v);
    json_t *out;
    if (json_is_integer(wrap ? json_array_get(v, 0) : v)) {
        if (fabs(y - round(y)) > 1e-9 * fabs(y) || fabs(y) > 9e15) {
            *ok = 0;
            return json_null();
        }
        out = json_integer((json_int_t)llround(y));
    } else {
        out = json_real(y);
    }
    return wrap ? json_pack("[o]", out) : out;
}

/* The axis value one level finer than v, for the report's mapping to h. */
static json_t *finer(const json_t *v, const struct resolution *res, double ratio, int *ok)
{
    *ok = 1;
    if (res->hmap == HMAP_VALUE)
        return scaled(v, 1.0 / ratio, ok);
    if (res->hmap == HMAP_INVERSE)
        return scaled(v, ratio, ok);
    /* cells: every entry of a list times the ratio, or a count times ratio^dim */
    if (json_is_array(v) && json_array_size(v) > 1) {
        json_t *out = json_array();
        size_t i;
        json_t *x;
        json_array_foreach(v, i, x) json_array_append_new(out, scaled(x, ratio, ok));
        return out;
    }
    return scaled(v, pow(ratio, (double)(res->dim ? res->dim : 1)), ok);
}

static json_t *follow(const json_t *v, enum refine_follow how, double ratio, int *ok)
{
    *ok = 1;
    if (how == FOLLOW_SAME)
        return json_deep_copy(v);
    return scaled(v, how == FOLLOW_INVERSE ? ratio : 1.0 / ratio, ok);
}

/* Append one level to the axis and the keys that follow it. */
static int add_level(struct refine *f, const struct resolution *res, struct err *e)
{
    const struct study *s = f->s;
    const json_t *axv = s->axes[f->ax].values;
    /* the finest level so far: the last added, or the finest start value */
    long from = -1;
    if (f->nref == 0) {
        double hmin = INFINITY;
        for (size_t i = 0; i < json_array_size(axv); i++) {
            double h = resolution_h(res, json_array_get(axv, i));
            if (h < hmin) {
                hmin = h;
                from = (long)i;
            }
        }
    }
    for (int i = 0; i < s->naxes; i++) {
        if (s->axes[i].group != f->grp)
            continue;
        const json_t *last = f->nref ? json_array_get(f->added[i], (size_t)f->nref - 1)
                                     : json_array_get(s->axes[i].values, (size_t)from);
        int ok;
        json_t *next;
        if (i == f->ax) {
            next = finer(last, res, f->r->ratio, &ok);
        } else {
            enum refine_follow how = FOLLOW_SAME;
            for (int k = 0; k < f->r->nfollow; k++)
                if (strcmp(f->r->follow[k].path, s->axes[i].path) == 0)
                    how = f->r->follow[k].how;
            next = follow(last, how, f->r->ratio, &ok);
        }
        if (!ok) {
            char *t = json_dumps(last, JSON_COMPACT | JSON_ENCODE_ANY);
            int rc = err_set(e, ERR_INPUT, "refine: %s = %s times the ratio %g is not a whole "
                                           "number: choose a ratio that keeps it one",
                             s->axes[i].path, t ? t : "?", f->r->ratio);
            free(t);
            json_decref(next);
            return rc;
        }
        json_array_append_new(f->added[i], next);
    }
    f->nref++;
    return 0;
}

/* --- measured cost ------------------------------------------------------- */

struct costs {
    char (*key)[SA_LABEL_MAX];
    struct level_cost *lv;
    int n, cap;
    double spent;             /* core-seconds of the runs of the active jobs */
};

static int cost_add(struct costs *c, const char *key, double h, double wall)
{
    for (int i = 0; i < c->n; i++)
        if (c->lv[i].h == h && strcmp(c->key[i], key) == 0) {
            c->lv[i].wall += wall;
            c->lv[i].njobs++;
            return 0;
        }
    if (c->n == c->cap) {
        int cap = c->cap ? 2 * c->cap : 32;
        char(*k)[SA_LABEL_MAX] = mem_realloc(c->key, (size_t)cap * sizeof *k);
        if (!k)
            return -1;
        c->key = k;
        struct level_cost *l = mem_realloc(c->lv, (size_t)cap * sizeof *l);
        if (!l)
            return -1;
        c->lv = l;
        c->cap = cap;
    }
    snprintf(c->key[c->n], SA_LABEL_MAX, "%s", key);
    c->lv[c->n++] = (struct level_cost){h, wall, 1};
    return 0;
}

static int costs_load(struct refine *f, sqlite3 *db, long long study_id,
                      const struct resolution *res, struct costs *c, struct err *e)
{
    memset(c, 0, sizeof *c);
    sqlite3_stmt *st;
    int rc = db_prepare(db,
                        "SELECT j.params, r.wall_s FROM jobs j JOIN runs r ON r.job_id = j.id AND "
                        "r.status = 'done' AND r.attempt = (SELECT max(x.attempt) FROM runs x "
                        "WHERE x.job_id = j.id AND x.status = 'done') WHERE j.study_id = ?1 AND "
                        "j.active = 1 AND j.kind = 'sweep' AND r.wall_s IS NOT NULL",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        json_t *params = json_loads((const char *)sqlite3_column_text(st, 0), 0, NULL);
        char key[SA_LABEL_MAX];
        series_key(f->s, f->grp, params, key, sizeof key);
        double h = resolution_h(res, json_object_get(params, f->s->axes[f->ax].path));
        json_decref(params);
        if (isfinite(h) && cost_add(c, key, h, sqlite3_column_double(st, 1)))
            rc = err_nomem(e, "costs");
    }
    sqlite3_finalize(st);
    if (rc || (rc = db_prepare(db, "SELECT coalesce(sum(r.wall_s), 0) FROM runs r JOIN jobs j ON "
                                   "j.id = r.job_id WHERE j.study_id = ?1 AND j.active = 1",
                               &st, e)))
        return rc;
    sqlite3_bind_int64(st, 1, study_id);
    if (sqlite3_step(st) == SQLITE_ROW)
        c->spent = sqlite3_column_double(st, 0) * f->cores;
    sqlite3_finalize(st);
    return 0;
}

static void costs_free(struct costs *c)
{
    free(c->key);
    free(c->lv);
}

/* Predicted core-seconds of a series' next level at h_next (NaN: no data). */
static double predict(const struct refine *f, const struct costs *c, const char *key,
                      double h_next)
{
    const struct level_cost *a = NULL, *b = NULL;   /* finest, next finest */
    for (int i = 0; i < c->n; i++) {
        if (strcmp(c->key[i], key) != 0)
            continue;
        const struct level_cost *l = &c->lv[i];
        if (!a || l->h < a->h) {
            b = a;
            a = l;
        } else if (!b || l->h < b->h) {
            b = l;
        }
    }
    if (!a)
        return NAN;
    double t1 = a->wall / a->njobs, k = 0;
    if (b && t1 > 0 && b->wall > 0) {
        double t2 = b->wall / b->njobs;
        k = log(t1 / t2) / log(b->h / a->h);
        k = k < 0 ? 0 : k > 6 ? 6 : k;
    }
    return t1 * pow(a->h / h_next, k) * a->njobs * f->cores;
}

/* --- one round's decisions -------------------------------------------------- */

static void fmt_pct(double x, char *out, size_t len)
{
    snprintf(out, len, "%#.4g %%", 100 * x);
}

/* What one metric says about a series: 1 met, 0 wants a finer level, -1
 * stop (why in `why`). */
/* Advance a write position by what snprintf reported, never past the end. */
static size_t advance(size_t used, int w, size_t len)
{
    if (w < 0)
        return used;
    used += (size_t)w;
    return used < len ? used : len - 1;
}

static int judge(const struct refine *f, const struct study_analysis *a, const struct sa_conv *c,
                 const char *metric, char *why, size_t len)
{
    const struct sa_group *gr = &a->groups[c->group];
    if (c->npts < gr->npts) {
        snprintf(why, len, "%s: %d of %d levels have no value (a job failed)", metric,
                 gr->npts - c->npts, gr->npts);
        return -1;
    }
    if (c->status == SA_FEW) {
        snprintf(why, len, "%s: %s", metric, c->note);
        return -1;
    }
    if (c->status == SA_ERROR) {
        snprintf(why, len, "%s: no order: %s", metric, c->note);
        return -1;
    }
    const struct conv_result *r = &c->c;
    if (r->kind == CONV_DIVERGENT || r->kind == CONV_OSCILLATORY) {
        snprintf(why, len, "%s: %s (R = eps21/eps32 = %.4g)", metric, conv_kind_names[r->kind],
                 r->ratio);
        return -1;
    }
    if (r->kind == CONV_INDETERMINATE) {
        if (r->phi[0] == r->phi[1]) {
            snprintf(why, len, "%s: equal values on the two finest levels", metric);
            return 1;
        }
        snprintf(why, len, "%s: indeterminate (equal values on the two coarser levels)", metric);
        return -1;
    }
    char g[32], t[32];
    int met = 1;
    size_t used = 0;
    why[0] = '\0';
    if (isfinite(f->r->gci)) {
        fmt_pct(r->gci_fine, g, sizeof g);
        fmt_pct(f->r->gci, t, sizeof t);
        if (c->limit_near_zero) {
            snprintf(why, len, "%s: limit near 0, the relative GCI cannot meet %s (use "
                               "until.band)",
                     metric, t);
            return -1;
        }
        int ok = r->gci_fine <= f->r->gci;
        met &= ok;
        used = advance(used, snprintf(why + used, len - used, "%s: GCI %s %s %s", metric, g,
                                      ok ? "<=" : ">", t),
                       len);
    }
    if (isfinite(f->r->band)) {
        int ok = c->abs_unc <= f->r->band;
        met &= ok;
        used = advance(used, snprintf(why + used, len - used, "%s%s: band %#.4g %s %g",
                                      used ? ", " : "", metric, c->abs_unc, ok ? "<=" : ">",
                                      f->r->band),
                       len);
    }
    if (isfinite(f->r->asymptotic)) {
        int ok = isfinite(r->asymptotic) && fabs(r->asymptotic - 1) <= f->r->asymptotic;
        met &= ok;
        snprintf(why + used, len - used, ", asymptotic ratio %#.4g %s", r->asymptotic,
                 ok ? "in range" : "outside the range");
    }
    return met;
}

static int analyse_round(struct refine *f, const struct study_run_opts *o, int *refining,
                         FILE *log, struct err *e)
{
    *refining = 0;
    const struct study *s = f->s;
    sqlite3 *db = NULL;
    struct rdata d;
    struct study_analysis a;
    struct report_spec rs = s->report;   /* shallow: the report's settings, the axis forced */
    rs.res_mode = RES_AXIS;
    snprintf(rs.res_axis, sizeof rs.res_axis, "%s", f->r->axis);
    rs.metrics = NULL;
    rs.nmetrics = 0;
    rs.fits = NULL;
    rs.nfits = 0;
    int rc = db_open_readonly(o->db_path, &db, e);
    if (!rc)
        rc = rdata_load(db, s->name, &d, e);
    if (rc) {
        db_close(&db);
        return rc;
    }
    rc = sa_build(&a, &d, &rs, e);
    struct costs c = {0};
    if (!rc)
        rc = costs_load(f, db, d.study_id, &a.res, &c, e);
    db_close(&db);
    struct refine_row *rows = NULL;
    int nrows = 0;
    if (!rc) {
        rows = mem_calloc((size_t)(a.ngroups * f->r->nmetrics + 1), sizeof *rows);
        if (!rows)
            rc = err_nomem(e, "refinement");
    }
    /* h of the next level, the same for every series */
    double h_next = NAN;
    if (!rc) {
        struct refine probe = *f;
        json_t **added = mem_calloc((size_t)s->naxes, sizeof *added);
        if (!added) {
            rc = err_nomem(e, "refinement");
        } else {
            for (int i = 0; i < s->naxes; i++)
                added[i] = json_copy(f->added[i]);
            probe.added = added;
            rc = add_level(&probe, &a.res, e);
            if (!rc)
                h_next = resolution_h(&a.res, json_array_get(added[f->ax], (size_t)f->nref));
            for (int i = 0; i < s->naxes; i++)
                json_decref(added[i]);
            free(added);
        }
    }
    double committed = c.spent;
    int want_level = 0;
    for (int g = 0; !rc && g < a.ngroups; g++) {
        struct series *ser = series_get(f, a.groups[g].key, 1);
        if (!ser) {
            rc = err_nomem(e, "refinement");
            break;
        }
        int verdict = 1;   /* 1 all met, 0 some wants more, -1 stopped */
        char why[512] = "", one[512];
        for (int k = 0; k < f->r->nmetrics; k++) {
            int m = rdata_metric(&d, f->r->metrics[k]), slot = -1;
            for (int q = 0; q < a.nmetrics; q++)
                if (a.metrics[q] == m)
                    slot = q;
            int v;
            if (slot < 0) {
                snprintf(one, sizeof one, "%s: no values", f->r->metrics[k]);
                v = -1;
            } else {
                v = judge(f, &a, sa_conv_at(&a, slot, g), f->r->metrics[k], one, sizeof one);
            }
            if (v < verdict || (v == verdict && v <= 0 && !why[0]))
                snprintf(why, sizeof why, "%s", one);
            else if (v == verdict && v == 1)
                snprintf(why + strlen(why), sizeof why - strlen(why), "%s%s", why[0] ? "; " : "",
                         one);
            if (v < verdict)
                verdict = v;
        }
        int levels = f->nstart + ser->kref;
        ser->next_core_s = NAN;
        if (verdict == 1) {
            ser->state = "converged";
            snprintf(ser->reason, sizeof ser->reason, "%s", why);
        } else if (verdict < 0) {
            ser->state = "stopped";
            snprintf(ser->reason, sizeof ser->reason, "%s", why);
        } else if (levels >= f->r->max_levels) {
            ser->state = "stopped";
            snprintf(ser->reason, sizeof ser->reason, "max_levels %ld reached (%s)",
                     f->r->max_levels, why);
        } else {
            double next = predict(f, &c, ser->key, h_next);
            ser->next_core_s = next;
            if (isfinite(f->r->budget_core_s) && isfinite(next) &&
                committed + next > f->r->budget_core_s) {
                ser->state = "stopped";
                snprintf(ser->reason, sizeof ser->reason,
                         "budget: the next level (h = %.6g) is predicted to take %.4g core-s; "
                         "%.4g of %.4g core-s committed (%s)",
                         h_next, next, committed, f->r->budget_core_s, why);
            } else {
                ser->state = "refining";
                if (isfinite(next))
                    snprintf(ser->reason, sizeof ser->reason, "%s; next level h = %.6g, predicted "
                                                              "%.4g core-s",
                             why, h_next, next);
                else
                    snprintf(ser->reason, sizeof ser->reason, "%s", why);
                committed += isfinite(next) ? next : 0;
                ser->kref++;
                want_level |= ser->kref > f->nref;
                (*refining)++;
            }
        }
        /* one row per metric of the series */
        for (int k = 0; k < f->r->nmetrics; k++) {
            struct refine_row *row = &rows[nrows++];
            int m = rdata_metric(&d, f->r->metrics[k]), slot = -1;
            for (int q = 0; q < a.nmetrics; q++)
                if (a.metrics[q] == m)
                    slot = q;
            const struct sa_conv *cv = slot >= 0 ? sa_conv_at(&a, slot, g) : NULL;
            snprintf(row->metric, sizeof row->metric, "%s", f->r->metrics[k]);
            snprintf(row->series, sizeof row->series, "%s", ser->key);
            snprintf(row->axis, sizeof row->axis, "%s", f->r->axis);
            row->levels = cv ? cv->npts : 0;
            row->value = row->phi_ext = row->gci = row->band = row->asymptotic = NAN;
            snprintf(row->finest, sizeof row->finest, "null");
            if (cv && cv->npts > 0) {
                const struct sa_point *pt = &a.pts[cv->pts[0]];
                row->value = pt->mean[m];
                char *t = canon_json(json_object_get(pt->params, f->r->axis));
                snprintf(row->finest, sizeof row->finest, "%s", t ? t : "null");
                free(t);
            }
            if (cv && cv->status == SA_OK) {
                row->phi_ext = cv->c.phi_ext;
                row->gci = cv->limit_near_zero ? NAN : cv->c.gci_fine;
                row->band = cv->abs_unc;
                row->asymptotic = cv->c.asymptotic;
            }
            row->state = ser->state;
            snprintf(row->reason, sizeof row->reason, "%s", ser->reason);
            row->spent_core_s = c.spent;
            row->next_core_s = ser->next_core_s;
        }
        char label[SA_LABEL_MAX];
        sa_params_label(a.groups[g].params, label, sizeof label);
        fprintf(log, "refine %s [%s]: %d levels, %s: %s\n", s->name, label, levels, ser->state,
                ser->reason);
    }
    if (!rc) {
        sqlite3 *w = NULL;
        int nconv = 0;
        rc = db_open(o->db_path, &w, e);
        if (!rc)
            rc = refine_state_write(w, d.study_id, rows, nrows, e);
        if (!rc)
            rc = conv_store_write(w, &a, "campaign", &nconv, e);
        db_close(&w);
    }
    if (!rc && want_level)
        rc = add_level(f, &a.res, e);
    free(rows);
    costs_free(&c);
    sa_free(&a);
    rdata_free(&d);
    return rc;
}

int refine_run(const struct study *s, const struct study_run_opts *o, struct runner_summary *sum,
               FILE *log, struct err *e)
{
    struct refine f;
    memset(&f, 0, sizeof f);
    f.s = s;
    f.r = &s->refine;
    f.ax = -1;
    for (int i = 0; i < s->naxes; i++)
        if (strcmp(s->axes[i].path, f.r->axis) == 0)
            f.ax = i;
    if (f.ax < 0)
        return err_set(e, ERR_INPUT, "refine.axis: '%s' is not swept", f.r->axis);
    f.grp = s->axes[f.ax].group;
    f.nstart = (int)json_array_size(s->axes[f.ax].values);
    f.cores = (double)s->threads * (s->mpirun_np ? s->mpirun_np : 1);
    f.added = mem_calloc((size_t)s->naxes, sizeof *f.added);
    if (!f.added)
        return err_nomem(e, "refinement");
    for (int i = 0; i < s->naxes; i++)
        f.added[i] = json_array();
    struct study_run_opts ro = *o;
    ro.plan_filter = keep_levels;
    ro.filter_ctx = &f;
    int rc = 0;
    for (int round = 1;; round++) {
        if ((rc = extended_build(&f, e)))
            break;
        rc = study_run(&f.t, &ro, sum, e);
        if (rc || sum->interrupted)
            break;
        int refining;
        if ((rc = analyse_round(&f, o, &refining, log, e)))
            break;
        if (!refining) {
            fprintf(log, "refine %s: done after %d round%s\n", s->name, round,
                    round == 1 ? "" : "s");
            break;
        }
    }
    extended_free(&f);
    for (int i = 0; i < s->naxes; i++)
        json_decref(f.added[i]);
    free(f.added);
    free(f.ser);
    return rc;
}

int study_run_any(const struct study *s, const struct study_run_opts *o,
                  struct runner_summary *sum, struct err *e)
{
    if (s->refine.on)
        return refine_run(s, o, sum, stderr, e);
    return study_run(s, o, sum, e);
}
