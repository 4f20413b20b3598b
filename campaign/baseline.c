/* baseline: regression baselines -- building, files, comparison (see baseline.h). */
#include "baseline.h"
#include "baseline_conv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "build_info.h"
#include "util/canon.h"
#include "util/mem.h"
#include "util/wfile.h"

const char *const cmp_verdict_names[] = {"ok", "REGRESSED", "MISSING", "FAILED", "new", NULL};

void baseline_solver_of(const struct study_analysis *a, char *out, size_t len)
{
    const struct rdata *d = a->d;
    out[0] = '\0';
    long best = 0;
    for (long i = 0; i < d->njobs; i++) {
        const char *s = d->jobs[i].solver;
        if (!s || d->jobs[i].prep)
            continue;
        long n = 0;
        for (long j = 0; j < d->njobs; j++)
            n += d->jobs[j].solver && !d->jobs[j].prep && strcmp(d->jobs[j].solver, s) == 0;
        if (n > best) {
            best = n;
            snprintf(out, len, "%s", s);
        }
    }
}

void baseline_split_solver(const char *s, char *version, size_t vlen, char *git, size_t glen)
{
    const char *open = strstr(s, " (");
    size_t n = strlen(s);
    if (open && n > 0 && s[n - 1] == ')') {
        snprintf(version, vlen, "%.*s", (int)(open - s), s);
        snprintf(git, glen, "%.*s", (int)(s + n - 1 - (open + 2)), open + 2);
    } else {
        snprintf(version, vlen, "%s", s);
        snprintf(git, glen, "unknown");
    }
}

json_t *baseline_build(const struct study_analysis *a, const char *created)
{
    const struct rdata *d = a->d;
    char solver[256], ver[128], git[128];
    baseline_solver_of(a, solver, sizeof solver);
    baseline_split_solver(solver, ver, sizeof ver, git, sizeof git);
    json_t *b = json_pack("{s:s, s:s, s:s, s:{s:s, s:s}}", "format", BASELINE_FORMAT, "study",
                          d->name, "created", created, "solver", "version", ver, "git", git);
    if (!b)
        return NULL;
    json_object_set_new(b, "cascade", json_string(CASCADE_VERSION " (" CASCADE_GIT_HASH ")"));
    if (a->res.axis >= 0)
        json_object_set_new(b, "resolution", json_string(d->axes[a->res.axis].name));
    json_t *values = json_array(), *orders = json_array();
    for (int k = 0; k < a->nmetrics; k++) {
        int m = a->metrics[k];
        for (int p = 0; p < a->npts; p++) {
            const struct sa_point *pt = &a->pts[p];
            if (!isfinite(pt->mean[m]))
                continue;
            json_array_append_new(values, json_pack("{s:s, s:O, s:f, s:s}", "metric", d->metric[m],
                                                    "params", pt->params, "value", pt->mean[m],
                                                    "unit", d->unit[m] ? d->unit[m] : "1"));
        }
        for (int g = 0; a->conv && g < a->ngroups; g++) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            if (c->status != SA_OK || !isfinite(c->c.p))
                continue;
            json_t *o = json_pack("{s:s, s:O, s:f, s:s}", "metric", d->metric[m], "group",
                                  a->groups[g].params, "p", c->c.p, "kind",
                                  conv_kind_names[c->c.kind]);
            if (isfinite(c->c.phi_ext))
                json_object_set_new(o, "extrapolated", json_real(c->c.phi_ext));
            json_array_append_new(orders, o);
        }
    }
    json_object_set_new(b, "values", values);
    json_object_set_new(b, "orders", orders);
    baseline_conv_add(b, a);
    return b;
}

/* One member; 0, or -1 when out of memory (nothing written then). */
static int put_member(FILE *f, const char *key, const json_t *v, int last)
{
    json_t *ks = json_string(key);
    char *k = canon_json(ks);
    json_decref(ks);
    char *t = canon_json(v);
    int ok = k && t;
    if (ok)
        fprintf(f, "  %s: %s%s\n", k, t, last ? "" : ",");
    free(k);
    free(t);
    return ok ? 0 : -1;
}

int baseline_write(const json_t *b, const char *path, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    int oom = 0;
    fputs("{\n", f);
    static const char *const head[] = {"format", "study", "created", "solver", "cascade",
                                       "resolution", NULL};
    for (int i = 0; head[i]; i++) {
        json_t *v = json_object_get(b, head[i]);
        if (v && put_member(f, head[i], v, 0) != 0)
            oom = 1;
    }
    static const char *const lists[] = {"values", "orders", "converged", NULL};
    int nlists = json_object_get(b, "converged") ? 3 : 2;   /* converged: refine studies only */
    for (int l = 0; l < nlists; l++) {
        json_t *arr = json_object_get(b, lists[l]);
        fprintf(f, "  \"%s\": [", lists[l]);
        size_t i;
        json_t *v;
        json_array_foreach(arr, i, v)
        {
            char *t = canon_json(v);
            oom |= !t;
            fprintf(f, "%s\n    %s", i ? "," : "", t ? t : "null");
            free(t);
        }
        fprintf(f, "%s]%s\n", json_array_size(arr) ? "\n  " : "", l + 1 < nlists ? "," : "");
    }
    fputs("}\n", f);
    if (oom) {
        wfile_discard(&w);
        return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory (baseline)", path);
    }
    return wfile_commit(&w, e);
}

int baseline_read(const char *path, const char *study, json_t **out, char **text, struct err *e)
{
    *out = NULL;
    *text = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(e, ERR_INPUT, "%s: cannot read the baseline: %s (create it with "
                                     "--update-baseline)",
                       path, strerror(errno));
    size_t cap = 1 << 16, n = 0, got;
    char *buf = mem_alloc(cap + 1);
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            char *g = mem_realloc(buf, 2 * cap + 1);
            if (!g) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = g;
            cap *= 2;
        }
    }
    fclose(f);
    if (!buf)
        return err_nomem(e, "baseline");
    buf[n] = '\0';
    json_error_t je;
    json_t *b = json_loads(buf, 0, &je);
    if (!b) {
        free(buf);
        return err_set(e, ERR_INPUT, "%s:%d:%d: not valid JSON: %s", path, je.line, je.column,
                       je.text);
    }
    const char *fmt = json_string_value(json_object_get(b, "format"));
    const char *name = json_string_value(json_object_get(b, "study"));
    const char *bad = NULL;
    if (!fmt || strcmp(fmt, BASELINE_FORMAT) != 0)
        bad = "\"format\" must be \"" BASELINE_FORMAT "\"";
    else if (!name)
        bad = "\"study\" is missing";
    else if (!json_is_array(json_object_get(b, "values")) ||
             !json_is_array(json_object_get(b, "orders")))
        bad = "\"values\" and \"orders\" must be lists";
    if (!bad) {
        size_t i;
        json_t *v;
        json_array_foreach(json_object_get(b, "values"), i, v)
        {
            if (!json_is_string(json_object_get(v, "metric")) ||
                !json_is_object(json_object_get(v, "params")) ||
                !json_is_number(json_object_get(v, "value")))
                bad = "each entry of \"values\" needs \"metric\", \"params\" and a numeric "
                      "\"value\"";
        }
        json_array_foreach(json_object_get(b, "orders"), i, v)
        {
            if (!json_is_string(json_object_get(v, "metric")) ||
                !json_is_object(json_object_get(v, "group")) ||
                !json_is_number(json_object_get(v, "p")))
                bad = "each entry of \"orders\" needs \"metric\", \"group\" and a numeric \"p\"";
        }
        if (!bad)
            bad = baseline_conv_check(b);
    }
    if (bad) {
        json_decref(b);
        free(buf);
        return err_set(e, ERR_INPUT, "%s: not a cascade baseline: %s", path, bad);
    }
    if (strcmp(name, study) != 0) {
        int rc = err_set(e, ERR_INPUT, "%s is the baseline of study '%s', not '%s'", path, name,
                         study);
        json_decref(b);
        free(buf);
        return rc;
    }
    *out = b;
    *text = buf;
    return 0;
}

/* --- comparison -------------------------------------------------------------- */

struct cmp_item *cmp_add_item(struct cmp_report *r, enum cmp_verdict v, const char *metric,
                              const char *what, const char *where)
{
    if (r->n == r->cap) {
        int cap = r->cap ? 2 * r->cap : 64;
        struct cmp_item *g = mem_realloc(r->it, (size_t)cap * sizeof *g);
        if (!g)
            return NULL;
        r->it = g;
        r->cap = cap;
    }
    struct cmp_item *it = &r->it[r->n++];
    memset(it, 0, sizeof *it);
    it->verdict = v;
    snprintf(it->metric, sizeof it->metric, "%s", metric);
    snprintf(it->what, sizeof it->what, "%s", what);
    snprintf(it->where, sizeof it->where, "%s", where);
    it->base = it->now = it->tol = NAN;
    if (v == CMP_REGRESSED || v == CMP_MISSING || v == CMP_FAILED)
        r->regressed++;
    else if (v == CMP_NEW)
        r->added++;
    return it;
}

static int analysed_slot(const struct study_analysis *a, const char *metric)
{
    for (int k = 0; k < a->nmetrics; k++)
        if (strcmp(a->d->metric[a->metrics[k]], metric) == 0)
            return k;
    return -1;
}

/* Index of a point or a group by the canonical JSON of its values, through
 * a dictionary built once per comparison. */
static int index_of(const json_t *dict, const json_t *params)
{
    char *key = canon_json(params);
    json_t *v = key ? json_object_get(dict, key) : NULL;
    free(key);
    return v ? (int)json_integer_value(v) : -1;
}

static json_t *point_index(const struct study_analysis *a)
{
    json_t *d = json_object();
    for (int p = 0; p < a->npts; p++)
        json_object_set_new(d, a->pts[p].key, json_integer(p));
    return d;
}

static json_t *group_index(const struct study_analysis *a)
{
    json_t *d = json_object();
    for (int g = 0; g < a->ngroups; g++)
        json_object_set_new(d, a->groups[g].key, json_integer(g));
    return d;
}

static void compare_values(const json_t *b, const struct study_analysis *a,
                           const struct report_spec *rs, struct cmp_report *r, char *seen)
{
    json_t *pidx = point_index(a);
    size_t i;
    json_t *v;
    json_array_foreach(json_object_get(b, "values"), i, v)
    {
        const char *metric = json_string_value(json_object_get(v, "metric"));
        const json_t *params = json_object_get(v, "params");
        double base = json_number_value(json_object_get(v, "value"));
        char where[SA_LABEL_MAX];
        int k = analysed_slot(a, metric), p = index_of(pidx, params);
        if (p >= 0)
            snprintf(where, sizeof where, "%s", a->pts[p].label);
        else
            sa_params_label(params, where, sizeof where);
        r->compared++;
        double now = k >= 0 && p >= 0 ? a->pts[p].mean[a->metrics[k]] : NAN;
        if (k >= 0 && p >= 0)
            seen[(size_t)k * (size_t)a->npts + (size_t)p] = 1;
        double abs, rel, otol;
        report_spec_tol(rs, metric, &abs, &rel, &otol);
        double tol = abs + rel * fabs(base);
        enum cmp_verdict verdict = !isfinite(now)              ? CMP_MISSING
                                   : fabs(now - base) <= tol ? CMP_OK
                                                              : CMP_REGRESSED;
        struct cmp_item *it = cmp_add_item(r, verdict, metric, "value", where);
        if (!it)
            continue;
        it->base = base;
        it->now = now;
        it->tol = tol;
        if (verdict == CMP_MISSING)
            snprintf(it->note, sizeof it->note, "%s",
                     k < 0 ? "metric not recorded now" : p < 0 ? "point no longer in the study"
                                                               : "no value now (job failed?)");
        else if (verdict == CMP_REGRESSED && base != 0)
            snprintf(it->note, sizeof it->note, "relative change %.3g", (now - base) / fabs(base));
    }
    json_decref(pidx);
}

static void compare_orders(const json_t *b, const struct study_analysis *a,
                           const struct report_spec *rs, struct cmp_report *r, char *seen)
{
    json_t *gidx = group_index(a);
    size_t i;
    json_t *v;
    json_array_foreach(json_object_get(b, "orders"), i, v)
    {
        const char *metric = json_string_value(json_object_get(v, "metric"));
        const json_t *group = json_object_get(v, "group");
        double base = json_number_value(json_object_get(v, "p"));
        const char *kind = json_string_value(json_object_get(v, "kind"));
        char where[SA_LABEL_MAX];
        int k = analysed_slot(a, metric), g = index_of(gidx, group);
        if (g >= 0)
            snprintf(where, sizeof where, "%s", a->groups[g].label);
        else
            sa_params_label(group, where, sizeof where);
        r->compared++;
        const struct sa_conv *c = k >= 0 && g >= 0 ? sa_conv_at(a, k, g) : NULL;
        double now = c && c->status == SA_OK ? c->c.p : NAN;
        if (c)
            seen[(size_t)a->nmetrics * (size_t)a->npts + (size_t)k * (size_t)a->ngroups +
                 (size_t)g] = 1;
        double abs, rel, otol;
        report_spec_tol(rs, metric, &abs, &rel, &otol);
        int kind_changed = isfinite(now) && kind && strcmp(kind, conv_kind_names[c->c.kind]) != 0;
        enum cmp_verdict verdict = !isfinite(now) ? CMP_MISSING
                                   : fabs(now - base) <= otol && !kind_changed ? CMP_OK
                                                                              : CMP_REGRESSED;
        struct cmp_item *it = cmp_add_item(r, verdict, metric, "order p", where);
        if (!it)
            continue;
        it->base = base;
        it->now = now;
        it->tol = otol;
        if (verdict == CMP_MISSING)
            snprintf(it->note, sizeof it->note, "%s",
                     c ? c->note : k < 0 ? "metric not recorded now" : "series no longer in the study");
        else if (kind_changed)
            snprintf(it->note, sizeof it->note, "convergence %s, baseline %s",
                     conv_kind_names[c->c.kind], kind);
    }
    json_decref(gidx);
}

int baseline_compare(const json_t *b, const struct study_analysis *a,
                     const struct report_spec *rs, struct cmp_report *r, struct err *e)
{
    memset(r, 0, sizeof *r);
    const struct rdata *d = a->d;
    size_t nseen = (size_t)a->nmetrics * ((size_t)a->npts + (size_t)a->ngroups) + 1;
    char *seen = mem_calloc(nseen, 1);
    if (!seen)
        return err_nomem(e, "comparison");
    /* jobs that did not succeed this time */
    for (long j = 0; j < d->njobs; j++) {
        const struct rd_job *job = &d->jobs[j];
        if (strcmp(job->state, "done") == 0)
            continue;
        char where[SA_LABEL_MAX];
        if (job->prep)
            snprintf(where, sizeof where, "%s (preparation job %s)", job->key,
                     job->name ? job->name : "");
        else {
            char lab[SA_LABEL_MAX - 32];
            sa_job_label(d, job->params, lab, sizeof lab);
            snprintf(where, sizeof where, "%s (%s)", job->key, lab);
        }
        struct cmp_item *it = cmp_add_item(r, CMP_FAILED, "-", "job", where);
        if (it)
            snprintf(it->note, sizeof it->note, "%s%s%s", job->state,
                     job->message ? ": " : "", job->message ? job->message : "");
    }
    compare_values(b, a, rs, r, seen);
    compare_orders(b, a, rs, r, seen);
    baseline_conv_compare(b, a, rs, r);
    /* what the baseline does not know */
    for (int k = 0; k < a->nmetrics; k++) {
        int m = a->metrics[k];
        for (int p = 0; p < a->npts; p++)
            if (!seen[(size_t)k * (size_t)a->npts + (size_t)p] && isfinite(a->pts[p].mean[m])) {
                struct cmp_item *it = cmp_add_item(r, CMP_NEW, d->metric[m], "value", a->pts[p].label);
                if (it) {
                    it->now = a->pts[p].mean[m];
                    snprintf(it->note, sizeof it->note, "not in the baseline");
                }
            }
        for (int g = 0; a->conv && g < a->ngroups; g++) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            if (!seen[(size_t)a->nmetrics * (size_t)a->npts + (size_t)k * (size_t)a->ngroups +
                      (size_t)g] &&
                c->status == SA_OK && isfinite(c->c.p)) {
                struct cmp_item *it = cmp_add_item(r, CMP_NEW, d->metric[m], "order p",
                                               a->groups[g].label);
                if (it) {
                    it->now = c->c.p;
                    snprintf(it->note, sizeof it->note, "not in the baseline");
                }
            }
        }
    }
    free(seen);
    return 0;
}

void cmp_free(struct cmp_report *r)
{
    free(r->it);
    memset(r, 0, sizeof *r);
}

/* --- output -------------------------------------------------------------------- */

static void num(double x, const char *fmt, char *out, size_t len)
{
    if (isnan(x))
        snprintf(out, len, "-");
    else
        snprintf(out, len, fmt, x);
}

#define NCOL 9

static void item_cells(const struct cmp_item *it, char cells[NCOL][SA_LABEL_MAX])
{
    snprintf(cells[0], SA_LABEL_MAX, "%s", cmp_verdict_names[it->verdict]);
    snprintf(cells[1], SA_LABEL_MAX, "%s", it->metric);
    snprintf(cells[2], SA_LABEL_MAX, "%s", it->what);
    snprintf(cells[3], SA_LABEL_MAX, "%s", it->where);
    num(it->base, "%.10g", cells[4], SA_LABEL_MAX);
    num(it->now, "%.10g", cells[5], SA_LABEL_MAX);
    num(isfinite(it->base) && isfinite(it->now) ? it->now - it->base : NAN, "%+.3g", cells[6],
        SA_LABEL_MAX);
    num(it->tol, "%.3g", cells[7], SA_LABEL_MAX);
    snprintf(cells[8], SA_LABEL_MAX, "%s", it->note);
}

static const char *const cmp_header[NCOL] = {"verdict", "metric", "what", "where", "baseline",
                                             "now", "diff", "tolerance", "note"};

/* Length of the first line of s wrapped at width w: up to the last space
 * that fits, so a label ("md.timestep=0.001 md.skin=2.0 ...") breaks
 * between its entries, never inside a word (one longer word overflows). */
static int wrap_len(const char *s, int w)
{
    int n = (int)strlen(s);
    if (n <= w)
        return n;
    for (int k = w; k > 0; k--)
        if (s[k] == ' ')
            return k;
    const char *sp = strchr(s, ' ');
    return sp ? (int)(sp - s) : n;
}

#define WHERE_WIDTH 80

void cmp_print(const struct cmp_report *r, FILE *out, int all)
{
    static char cells[NCOL][SA_LABEL_MAX];
    int w[NCOL];
    for (int c = 0; c < NCOL; c++)
        w[c] = (int)strlen(cmp_header[c]);
    int shown = 0;
    for (int i = 0; i < r->n; i++) {
        if (!all && r->it[i].verdict == CMP_OK)
            continue;
        shown++;
        item_cells(&r->it[i], cells);
        for (int c = 0; c < NCOL; c++) {
            int n = c == 3 ? wrap_len(cells[c], WHERE_WIDTH) : (int)strlen(cells[c]);
            if (n > w[c])
                w[c] = n;
        }
    }
    if (!shown)
        return;
    for (int c = 0; c < NCOL; c++)
        fprintf(out, "%-*s%s", c == NCOL - 1 ? 0 : w[c], cmp_header[c], c == NCOL - 1 ? "\n" : "  ");
    for (int i = 0; i < r->n; i++) {
        if (!all && r->it[i].verdict == CMP_OK)
            continue;
        item_cells(&r->it[i], cells);
        const char *where = cells[3];
        int first = wrap_len(where, w[3]);
        for (int c = 0; c < NCOL; c++) {
            int right = c >= 4 && c <= 7;
            if (c == NCOL - 1)
                fprintf(out, "%s\n", cells[c]);
            else if (c == 3)
                fprintf(out, "%-*.*s  ", w[c], first, where);
            else
                fprintf(out, right ? "%*s  " : "%-*s  ", w[c], cells[c]);
        }
        /* the rest of a long "where" on continuation lines under its column */
        where += first;
        while (*where == ' ')
            where++;
        while (*where) {
            int n = wrap_len(where, w[3]);
            int indent = 0;
            for (int c = 0; c < 3; c++)
                indent += w[c] + 2;
            fprintf(out, "%*s%.*s\n", indent, "", n, where);
            where += n;
            while (*where == ' ')
                where++;
        }
    }
}

/* A table of the items for which keep() holds. */
static void items_table(const struct cmp_report *r, struct rdoc *doc,
                        int (*keep)(const struct cmp_item *))
{
    int rows = 0;
    for (int i = 0; i < r->n; i++)
        rows += keep(&r->it[i]);
    if (!rows)
        return;
    char(*cells)[SA_LABEL_MAX] = mem_alloc((size_t)rows * NCOL * SA_LABEL_MAX);
    const char **ptr = mem_alloc((size_t)rows * NCOL * sizeof *ptr);
    if (cells && ptr) {
        int row = 0;
        for (int i = 0; i < r->n; i++) {
            if (!keep(&r->it[i]))
                continue;
            item_cells(&r->it[i], &cells[row * NCOL]);
            for (int c = 0; c < NCOL; c++)
                ptr[row * NCOL + c] = cells[row * NCOL + c];
            row++;
        }
        rdoc_table(doc, NCOL, cmp_header, rows, ptr);
    }
    free(cells);
    free(ptr);
}

static int not_passed(const struct cmp_item *it)
{
    return it->verdict != CMP_OK;
}

static int passed_order(const struct cmp_item *it)
{
    return it->verdict == CMP_OK && strcmp(it->what, "order p") == 0;
}

void cmp_to_doc(const struct cmp_report *r, struct rdoc *doc, const char *baseline_path,
                const char *baseline_solver)
{
    rdoc_heading(doc, 1, "Regression check");
    int values_ok = 0;
    for (int i = 0; i < r->n; i++)
        values_ok += r->it[i].verdict == CMP_OK && strcmp(r->it[i].what, "value") == 0;
    rdoc_para(doc, "Verdict: %s.  Baseline %s (values from solver %s): %d entries compared, %d "
                   "regressed or missing%s, %d new.  A value passes when |now - baseline| <= abs + "
                   "rel |baseline|, an order when |p_now - p_baseline| <= its tolerance and the "
                   "kind of convergence is unchanged.",
              r->regressed ? "REGRESSED" : "passed", baseline_path, baseline_solver, r->compared,
              r->regressed, r->regressed ? " (failed jobs included)" : "", r->added);
    if (r->regressed || r->added) {
        rdoc_heading(doc, 2, "Entries that did not pass, and new ones");
        items_table(r, doc, not_passed);
    }
    rdoc_heading(doc, 2, "Observed orders within tolerance");
    items_table(r, doc, passed_order);
    rdoc_para(doc, "%d metric values within tolerance (not listed).", values_ok);
}

json_t *cmp_failures_json(const struct cmp_report *r)
{
    json_t *list = json_array();
    for (int i = 0; i < r->n; i++) {
        const struct cmp_item *it = &r->it[i];
        if (it->verdict == CMP_OK || it->verdict == CMP_NEW)
            continue;
        json_t *o = json_pack("{s:s, s:s, s:s, s:s, s:s}", "verdict",
                              cmp_verdict_names[it->verdict], "metric", it->metric, "what",
                              it->what, "where", it->where, "note", it->note);
        if (isfinite(it->base))
            json_object_set_new(o, "baseline", json_real(it->base));
        if (isfinite(it->now))
            json_object_set_new(o, "now", json_real(it->now));
        if (isfinite(it->tol))
            json_object_set_new(o, "tolerance", json_real(it->tol));
        json_array_append_new(list, o);
    }
    return list;
}
