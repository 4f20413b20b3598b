/* report_build: the sections and figures of a study report (see report_build.h). */
#include "report_build.h"

#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "plot.h"
#include "util/mem.h"

#define CELL 160
/* A study with many series gets value figures for the first few only, and
 * error figures for the first REPORT_MAX_ERROR_FIGS x PLOT_MAX_SERIES series
 * (the tables list them all). */
#define REPORT_MAX_VALUE_FIGS 12
#define REPORT_MAX_ERROR_FIGS 4

void report_num(double x, int digits, char *out, size_t len)
{
    if (isnan(x)) {
        snprintf(out, len, "—");
        return;
    }
    if (isinf(x)) {
        snprintf(out, len, x > 0 ? "inf" : "-inf");
        return;
    }
    snprintf(out, len, "%.*g", digits, x);
}

/* Four significant digits, trailing zeros kept (the GCI band). */
static void sig4(double x, char *out, size_t len)
{
    if (isfinite(x))
        snprintf(out, len, "%#.4g", x);
    else
        report_num(x, 4, out, len);
}

static void pct(double frac, char *out, size_t len)
{
    if (!isfinite(frac)) {
        snprintf(out, len, "—");
        return;
    }
    snprintf(out, len, "%#.4g %%", 100 * frac);   /* 4 significant digits; report.json has all */
}

/* --- a growing table ------------------------------------------------------ */

struct tab {
    int ncols, nrows, cap;
    char (*cells)[CELL];
    int oom;   /* a row could not be added: the table (and report) is incomplete */
};

static char *tab_cell(struct tab *t, int col)
{
    if (t->oom)
        return NULL;
    if (col == 0) {
        if (t->nrows == t->cap) {
            int cap = t->cap ? 2 * t->cap : 16;
            char(*g)[CELL] = mem_realloc(t->cells, (size_t)cap * (size_t)t->ncols * CELL);
            if (!g) {
                t->oom = 1;
                return NULL;
            }
            t->cells = g;
            t->cap = cap;
        }
        memset(t->cells[t->nrows * t->ncols], 0, (size_t)t->ncols * CELL);
        t->nrows++;
    }
    return t->cells[(t->nrows - 1) * t->ncols + col];
}

__attribute__((format(printf, 3, 4))) static void tab_put(struct tab *t, int col, const char *fmt,
                                                          ...)
{
    char *c = tab_cell(t, col);
    if (!c)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c, CELL, fmt, ap);
    va_end(ap);
}

static void tab_emit(struct rdoc *doc, struct tab *t, const char *const *hdr)
{
    const char **cells =
        t->oom ? NULL : mem_alloc((size_t)(t->nrows ? t->nrows : 1) * (size_t)t->ncols * sizeof *cells);
    if (!cells)
        rdoc_mark_incomplete(doc);
    if (cells) {
        for (int i = 0; i < t->nrows * t->ncols; i++)
            cells[i] = t->cells[i];
        rdoc_table(doc, t->ncols, hdr, t->nrows, cells);
        free(cells);
    }
    free(t->cells);
    memset(t, 0, sizeof *t);
}

/* --- names ----------------------------------------------------------------- */

static void file_safe(const char *in, char *out, size_t len)
{
    size_t n = 0;
    for (; *in && n + 1 < len; in++)
        out[n++] = (*in >= 'a' && *in <= 'z') || (*in >= 'A' && *in <= 'Z') ||
                           (*in >= '0' && *in <= '9') || *in == '-'
                       ? *in
                       : '_';
    out[n] = '\0';
}

static const char *unit_of(const struct study_analysis *a, int m)
{
    const char *u = a->d->unit[m];
    return u && u[0] ? u : "1";
}

/* " eV" after a number; nothing for a dimensionless metric */
static const char *unit_after(const struct study_analysis *a, int m, char *buf, size_t len)
{
    const char *u = unit_of(a, m);
    snprintf(buf, len, "%s%s", strcmp(u, "1") ? " " : "", strcmp(u, "1") ? u : "");
    return buf;
}

/* Remove the figures an earlier report left (fig-*.svg) so none go stale. */
static void clean_figures(const char *dir)
{
    DIR *dp = opendir(dir);
    if (!dp)
        return;
    struct dirent *de;
    while ((de = readdir(dp))) {
        size_t n = strlen(de->d_name);
        if (strncmp(de->d_name, "fig-", 4) == 0 && n > 8 && strcmp(de->d_name + n - 4, ".svg") == 0) {
            char path[4096 + 256];
            snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
            unlink(path);
        }
    }
    closedir(dp);
}

/* --- header, summary and failures ------------------------------------------ */

static int is_failed_state(const char *s)
{
    return strcmp(s, "failed") == 0 || strcmp(s, "crashed") == 0 || strcmp(s, "timeout") == 0 ||
           strcmp(s, "diverged") == 0 || strcmp(s, "cancelled") == 0;
}

static void header(struct rdoc *doc, const struct study_analysis *a, const struct report_info *ri)
{
    const struct rdata *d = a->d;
    if (d->description && d->description[0])
        rdoc_para(doc, "%s", d->description);
    long failed = 0, pending = 0, running = 0, done = 0;
    for (long j = 0; j < d->njobs; j++) {
        const char *s = d->jobs[j].state;
        if (strcmp(s, "done") == 0)
            done++;
        else if (strcmp(s, "running") == 0)
            running++;
        else if (is_failed_state(s))
            failed++;
        else
            pending++;
    }
    rdoc_para(doc, "Study file %s; database %s.  %ld job%s (%ld sweep): %ld done, %ld failed, %ld "
                   "running, %ld not run.  Values are each job's latest successful run, averaged "
                   "over repeats.  Generated %s.",
              d->spec_path ? d->spec_path : "?", ri && ri->db_path ? ri->db_path : "?", d->njobs,
              d->njobs == 1 ? "" : "s", a->nsweep, done, failed, running, pending,
              ri && ri->generated ? ri->generated : "");
    /* which solver versions the values come from */
    char versions[1024] = "";
    int nv = 0;
    for (long j = 0; j < d->njobs; j++) {
        const char *s = d->jobs[j].solver;
        if (!s || strstr(versions, s))
            continue;
        size_t used = strlen(versions);
        snprintf(versions + used, sizeof versions - used, "%s%s", used ? ", " : "", s);
        nv++;
    }
    if (nv)
        rdoc_para(doc, "Solver: %s%s", versions,
                  nv > 1 ? " -- the values mix solver versions; rerun the study to compare like "
                           "with like."
                         : ".");
    rdoc_para(doc, "%s.", a->res.why);
}

static void summary(struct rdoc *doc, const struct study_analysis *a)
{
    if (!a->conv)
        return;
    rdoc_heading(doc, 1, "Summary");
    rdoc_para(doc, "Observed order p from the three finest grids with a value, Richardson-"
                   "extrapolated value and fine-grid GCI (Celik et al. 2008), per metric and "
                   "combination of the other swept values.  The band is the fine-grid GCI in the "
                   "metric's unit.");
    const char *hdr[] = {"metric", "unit", "series", "grids", "p", "formal", "extrapolated",
                         "GCI fine", "band ±", "flags"};
    struct tab t = {10, 0, 0, NULL, 0};
    for (int k = 0; k < a->nmetrics; k++)
        for (int g = 0; g < a->ngroups; g++) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            int m = a->metrics[k];
            tab_put(&t, 0, "%s", a->d->metric[m]);
            tab_put(&t, 1, "%s", unit_of(a, m));
            tab_put(&t, 2, "%s", a->groups[g].label);
            tab_put(&t, 3, "%d", c->npts);
            char b[4][64];
            if (c->status == SA_OK && isfinite(c->c.p))
                snprintf(b[0], sizeof b[0], "%.3f", c->c.p);
            else
                report_num(NAN, 4, b[0], sizeof b[0]);
            report_num(c->formal, 3, b[1], sizeof b[1]);
            report_num(c->status == SA_OK ? c->c.phi_ext : NAN, 9, b[2], sizeof b[2]);
            sig4(c->status == SA_OK ? c->abs_unc : NAN, b[3], sizeof b[3]);
            tab_put(&t, 4, "%s", b[0]);
            tab_put(&t, 5, "%s", b[1]);
            tab_put(&t, 6, "%s", b[2]);
            char g1[64];
            pct(c->status == SA_OK && !c->limit_near_zero ? c->c.gci_fine : NAN, g1, sizeof g1);
            tab_put(&t, 7, "%s", g1);
            tab_put(&t, 8, "%s", b[3]);
            tab_put(&t, 9, "%s", c->flags[0] ? c->flags : "ok");
        }
    tab_emit(doc, &t, hdr);
}

static void failures(struct rdoc *doc, const struct study_analysis *a)
{
    const struct rdata *d = a->d;
    long n = 0;
    for (long j = 0; j < d->njobs; j++)
        n += strcmp(d->jobs[j].state, "done") != 0;
    if (!n)
        return;
    rdoc_heading(doc, 1, "Failed and missing jobs");
    rdoc_para(doc, "%ld job%s without a successful latest attempt (cascade show KEY for details, "
                   "cascade retry %s --failed to run the failed ones again).",
              n, n == 1 ? "" : "s", d->name);
    const char *hdr[] = {"job", "parameters", "state", "attempts", "reason"};
    struct tab t = {5, 0, 0, NULL, 0};
    for (long j = 0; j < d->njobs; j++) {
        const struct rd_job *job = &d->jobs[j];
        if (strcmp(job->state, "done") == 0)
            continue;
        char params[SA_LABEL_MAX];
        if (job->prep)
            snprintf(params, sizeof params, "preparation job %s", job->name ? job->name : "");
        else
            sa_job_label(d, job->params, params, sizeof params);
        char reason[CELL];
        if (job->message && job->message[0])
            snprintf(reason, sizeof reason, "%s", job->message);
        else if (job->signal > 0)
            snprintf(reason, sizeof reason, "killed by signal %d", job->signal);
        else if (job->exit_code > 0)
            snprintf(reason, sizeof reason, "exit code %d", job->exit_code);
        else if (strcmp(job->state, "pending") == 0)
            snprintf(reason, sizeof reason, "not run yet");
        else if (strcmp(job->state, "running") == 0)
            snprintf(reason, sizeof reason, "running (or its runner died: cascade status)");
        else
            snprintf(reason, sizeof reason, "%s", job->state);
        if (job->solver)
            snprintf(reason + strlen(reason), sizeof reason - strlen(reason),
                     " (values from an earlier successful run are used)");
        tab_put(&t, 0, "%s", job->key);
        tab_put(&t, 1, "%s", params);
        tab_put(&t, 2, "%s", job->state);
        tab_put(&t, 3, "%d", job->attempt);
        tab_put(&t, 4, "%s", reason);
    }
    tab_emit(doc, &t, hdr);
}

/* --- convergence ------------------------------------------------------------- */

static int res_group_axes(const struct study_analysis *a, int *ax, int max)
{
    int n = 0;
    for (int i = 0; i < a->d->naxes && n < max; i++)
        if (a->d->axes[i].grp == a->res.grp && !a->d->axes[i].repeat)
            ax[n++] = i;
    return n;
}

static void values_table(struct rdoc *doc, const struct study_analysis *a, int k, int g)
{
    const struct rdata *d = a->d;
    const struct sa_conv *c = sa_conv_at(a, k, g);
    const struct sa_group *gr = &a->groups[g];
    int m = a->metrics[k];
    int ax[16], nax = res_group_axes(a, ax, 16);
    int repeats = 0;
    for (int i = 0; i < gr->npts; i++)
        repeats |= a->pts[gr->pts[i]].njobs > 1;
    const char *hdr[24];
    char hbuf[24][CELL];
    int nc = 0;
    hdr[nc++] = "h";
    for (int i = 0; i < nax; i++)
        hdr[nc++] = d->axes[ax[i]].name;
    snprintf(hbuf[0], CELL, "%s [%s]", d->metric[m], unit_of(a, m));
    hdr[nc++] = hbuf[0];
    if (repeats)
        hdr[nc++] = "sd (n)";
    hdr[nc++] = "change from coarser";
    hdr[nc++] = "local p";
    struct tab t = {nc, 0, 0, NULL, 0};
    for (int i = 0; i < gr->npts; i++) {
        const struct sa_point *pt = &a->pts[gr->pts[i]];
        int col = 0;
        char b[64];
        report_num(pt->h, 6, b, sizeof b);
        tab_put(&t, col++, "%s", b);
        for (int q = 0; q < nax; q++) {
            json_t *one = json_object();
            json_object_set(one, d->axes[ax[q]].name, json_object_get(pt->params, d->axes[ax[q]].name));
            char lab[SA_LABEL_MAX];
            sa_params_label(one, lab, sizeof lab);
            json_decref(one);
            const char *eq = strchr(lab, '=');
            tab_put(&t, col++, "%s", eq ? eq + 1 : lab);
        }
        report_num(pt->mean[m], 10, b, sizeof b);
        if (pt->n[m] == 0)
            tab_put(&t, col++, "no value (%d job%s)", pt->njobs, pt->njobs == 1 ? "" : "s");
        else
            tab_put(&t, col++, "%s", b);
        if (repeats) {
            char s[64];
            report_num(pt->sd[m], 3, s, sizeof s);
            tab_put(&t, col++, "%s (%d)", s, pt->n[m]);
        }
        /* change from the next coarser grid with a value, and the local order */
        int ci = -1;
        for (int q = 0; q < c->npts; q++)
            if (c->pts[q] == gr->pts[i])
                ci = q;
        if (ci >= 0 && ci + 1 < c->npts) {
            report_num(pt->mean[m] - a->pts[c->pts[ci + 1]].mean[m], 4, b, sizeof b);
            tab_put(&t, col++, "%s", b);
        } else {
            tab_put(&t, col++, "—");
        }
        if (ci >= 0 && isfinite(c->local_p[ci])) {
            report_num(c->local_p[ci], 4, b, sizeof b);
            int kind = c->local_kind[ci];
            tab_put(&t, col++, "%s%s%s", b, kind == CONV_MONOTONE || kind < 0 ? "" : " ",
                    kind == CONV_MONOTONE || kind < 0 ? "" : conv_kind_names[kind]);
        } else {
            tab_put(&t, col++, "—");
        }
    }
    tab_emit(doc, &t, hdr);
}

static void conv_table(struct rdoc *doc, const struct study_analysis *a, int k, int g)
{
    const struct sa_conv *c = sa_conv_at(a, k, g);
    int m = a->metrics[k];
    if (c->status != SA_OK) {
        rdoc_para(doc, "No convergence estimate: %s.", c->note);
        return;
    }
    const struct conv_result *r = &c->c;
    const char *hdr[] = {"quantity", "value"};
    struct tab t = {2, 0, 0, NULL, 0};
    char b[64];
#define ROW(name, ...)                                                                             \
    do {                                                                                           \
        tab_put(&t, 0, "%s", name);                                                                \
        tab_put(&t, 1, __VA_ARGS__);                                                               \
    } while (0)
    report_num(r->h[0], 6, b, sizeof b);
    char b2[64], b3[64];
    report_num(r->h[1], 6, b2, sizeof b2);
    report_num(r->h[2], 6, b3, sizeof b3);
    ROW("grids h1, h2, h3 (finest first)", "%s, %s, %s", b, b2, b3);
    ROW("refinement ratios r21, r32", "%.4g, %.4g", r->r21, r->r32);
    report_num(r->ratio, 4, b, sizeof b);
    ROW("convergence ratio R = eps21/eps32", "%s (%s)", b, conv_kind_names[r->kind]);
    snprintf(b, sizeof b, "%.4f", r->p);
    if (isfinite(c->formal))
        ROW("observed order p", "%s (formal %g; %d fixed-point iterations)", b, c->formal,
            r->iterations);
    else
        ROW("observed order p", "%s (%d fixed-point iterations)", b, r->iterations);
    report_num(r->phi_ext, 10, b, sizeof b);
    char ub[64];
    ROW("extrapolated value phi_ext21", "%s%s", b, unit_after(a, m, ub, sizeof ub));
    pct(r->e_a21, b, sizeof b);
    ROW("approximate relative error e_a21", "%s", b);
    pct(r->e_ext21, b, sizeof b);
    ROW("extrapolated relative error e_ext21", "%s", b);
    pct(r->gci_fine, b, sizeof b);
    ROW("GCI fine (GCI_21)", "%s", b);
    pct(r->gci_medium, b, sizeof b);
    ROW("GCI medium (GCI_32)", "%s", b);
    sig4(c->abs_unc, b, sizeof b);
    if (isfinite(c->abs_unc))
        ROW("band: fine value ± GCI in units", "± %s%s", b, unit_after(a, m, ub, sizeof ub));
    else
        ROW("band: fine value ± GCI in units", "—");
    report_num(r->asymptotic, 5, b, sizeof b);
    ROW("asymptotic ratio GCI_32 / (r21^p GCI_21)", "%s", b);
    ROW("flags", "%s", c->flags[0] ? c->flags : "none");
#undef ROW
    tab_emit(doc, &t, hdr);
}

/* The value of metric slot k against h in group g, with the Richardson
 * curve phi_ext + C h^p through the three finest grids. */
static int value_figure(struct rdoc *doc, const struct study_analysis *a, int k, int g,
                        const char *dir, struct err *e)
{
    const struct rdata *d = a->d;
    const struct sa_conv *c = sa_conv_at(a, k, g);
    int m = a->metrics[k], n = c->npts;
    if (n == 0)
        return 0;
    double *hx = mem_alloc((size_t)n * 2 * sizeof *hx);
    if (!hx)
        return err_nomem(e, "figure");
    double *vy = hx + n;
    for (int i = 0; i < n; i++) {
        hx[i] = a->pts[c->pts[i]].h;
        vy[i] = a->pts[c->pts[i]].mean[m];
    }
    char mname[128], title[SA_LABEL_MAX + 256], ylabel[384], xlabel[256], glab[SA_LABEL_MAX];
    plot_text(d->metric[m], mname, sizeof mname);
    plot_text(a->res.label, xlabel, sizeof xlabel);
    plot_text(a->groups[g].label, glab, sizeof glab);
    char awords[sizeof a->res.axis_words];
    plot_text(a->res.axis_words, awords, sizeof awords);
    if (a->ngroups > 1)
        snprintf(title, sizeof title, "%s against %s, %s", mname, awords, glab);
    else
        snprintf(title, sizeof title, "%s against %s", mname, awords);
    snprintf(ylabel, sizeof ylabel, "%s (%s)", mname, unit_of(a, m));
    struct plot_spec ps = {0};
    ps.title = title;
    ps.xlabel = xlabel;
    ps.ylabel = ylabel;
    ps.series[ps.nseries++] = (struct plot_series){"values", hx, vy, n, PLOT_LINESPOINTS};
    char expr[256], olab[128];
    if (c->status == SA_OK && isfinite(c->c.phi_ext)) {
        const struct conv_result *r = &c->c;
        double C = (r->phi[0] - r->phi_ext) / pow(r->h[0], r->p);
        snprintf(expr, sizeof expr, "(%.12g) + (%.12g)*x**(%.12g)", r->phi_ext, C, r->p);
        snprintf(olab, sizeof olab, "extrapolated %.6g + C h^{%.3f}", r->phi_ext, r->p);
        ps.overlays[ps.noverlays++] = (struct plot_overlay){expr, olab, 1};
    }
    char safe[128], file[256], path[4096 + 256];
    file_safe(d->metric[m], safe, sizeof safe);
    snprintf(file, sizeof file, "fig-%02d-%s-g%d-value.svg", k, safe, g);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    int rc = plot_svg(&ps, path, e);
    if (!rc) {
        char cap[SA_LABEL_MAX + 256];
        snprintf(cap, sizeof cap, "%s against %s%s%s%s", d->metric[m], a->res.axis_words,
                 a->ngroups > 1 ? ", " : "", a->ngroups > 1 ? a->groups[g].label : "",
                 ps.noverlays ? "; dashed: the Richardson curve through the three finest grids"
                              : " (no extrapolation)");
        rdoc_figure(doc, dir, file, cap);
    }
    free(hx);
    return rc;
}

/* The error |phi - phi_ext| against h (log-log) for up to PLOT_MAX_SERIES
 * groups, each with its line C h^p; groups without an extrapolated value
 * show the change between successive grids instead. */
static int error_figure(struct rdoc *doc, const struct study_analysis *a, int k, int g0, int ng,
                        const char *dir, struct err *e)
{
    const struct rdata *d = a->d;
    int m = a->metrics[k];
    size_t np = (size_t)(a->npts ? a->npts : 1);
    double *buf = mem_alloc((size_t)ng * 2 * np * sizeof *buf);
    char(*labels)[SA_LABEL_MAX] = mem_calloc((size_t)ng, sizeof *labels);
    char(*olabels)[128] = mem_calloc((size_t)ng, sizeof *olabels);
    char(*exprs)[256] = mem_calloc((size_t)ng, sizeof *exprs);
    if (!buf || !labels || !olabels || !exprs) {
        free(buf);
        free(labels);
        free(olabels);
        free(exprs);
        return err_nomem(e, "figure");
    }
    char mname[128], title[384], ylabel[384], xlabel[256];
    plot_text(d->metric[m], mname, sizeof mname);
    plot_text(a->res.label, xlabel, sizeof xlabel);
    char awords[sizeof a->res.axis_words];
    plot_text(a->res.axis_words, awords, sizeof awords);
    snprintf(title, sizeof title, "%s: error against %s", mname, awords);
    snprintf(ylabel, sizeof ylabel, "|%s - extrapolated| (%s)", mname, unit_of(a, m));
    struct plot_spec ps = {0};
    ps.title = title;
    ps.xlabel = xlabel;
    ps.ylabel = ylabel;
    ps.logx = ps.logy = 1;
    int any = 0;
    for (int q = 0; q < ng; q++) {
        int g = g0 + q;
        const struct sa_conv *c = sa_conv_at(a, k, g);
        double *ex = buf + (size_t)q * 2 * np, *ey = ex + np;
        int ne = 0;
        char glab[SA_LABEL_MAX];
        plot_text(a->ngroups > 1 ? a->groups[g].label : d->metric[m], glab, sizeof glab);
        if (c->status == SA_OK && isfinite(c->c.phi_ext)) {
            const struct conv_result *r = &c->c;
            for (int i = 0; i < c->npts; i++) {
                double err = fabs(a->pts[c->pts[i]].mean[m] - r->phi_ext);
                if (err > 0) {
                    ex[ne] = a->pts[c->pts[i]].h;
                    ey[ne++] = err;
                }
            }
            double C = (r->phi[0] - r->phi_ext) / pow(r->h[0], r->p);
            snprintf(exprs[q], sizeof exprs[q], "%.12g*x**(%.12g)", fabs(C), r->p);
            snprintf(olabels[q], sizeof olabels[q], "C h^p, p = %.3f", r->p);
            snprintf(labels[q], SA_LABEL_MAX, "%s", glab);
            ps.series[ps.nseries++] = (struct plot_series){labels[q], ex, ey, ne, PLOT_POINTS};
            ps.overlays[ps.noverlays++] = (struct plot_overlay){exprs[q], olabels[q], ps.nseries};
        } else {
            for (int i = 0; i + 1 < c->npts; i++) {
                double diff = fabs(a->pts[c->pts[i + 1]].mean[m] - a->pts[c->pts[i]].mean[m]);
                if (diff > 0) {
                    ex[ne] = a->pts[c->pts[i + 1]].h;
                    ey[ne++] = diff;
                }
            }
            snprintf(labels[q], SA_LABEL_MAX, "%s: change from the next finer grid", glab);
            ps.series[ps.nseries++] = (struct plot_series){labels[q], ex, ey, ne, PLOT_LINESPOINTS};
        }
        any |= ne > 0;
    }
    int rc = 0;
    if (any) {
        char safe[128], file[256], path[4096 + 256];
        file_safe(d->metric[m], safe, sizeof safe);
        snprintf(file, sizeof file, "fig-%02d-%s-g%d-error.svg", k, safe, g0);
        snprintf(path, sizeof path, "%s/%s", dir, file);
        rc = plot_svg(&ps, path, e);
        if (!rc) {
            char cap[512];
            if (ps.noverlays == ps.nseries)
                snprintf(cap, sizeof cap, "%s: distance from the extrapolated value against h "
                                          "(log-log); dashed: C h^p with the observed order, "
                                          "whose slope is p",
                         d->metric[m]);
            else
                snprintf(cap, sizeof cap, "%s against h (log-log): distance from the "
                                          "extrapolated value where there is one, else the "
                                          "change between successive grids",
                         d->metric[m]);
            rdoc_figure(doc, dir, file, cap);
        }
    }
    free(buf);
    free(labels);
    free(olabels);
    free(exprs);
    return rc;
}

static int convergence(struct rdoc *doc, const struct study_analysis *a, const char *dir,
                       struct err *e)
{
    if (!a->conv)
        return 0;
    const struct rdata *d = a->d;
    char h[256];
    snprintf(h, sizeof h, "Convergence along %s", d->axes[a->res.axis].name);
    rdoc_heading(doc, 1, h);
    int rc = 0;
    for (int k = 0; k < a->nmetrics && !rc; k++) {
        int m = a->metrics[k];
        char mh[256];
        snprintf(mh, sizeof mh, "%s (%s)", d->metric[m], unit_of(a, m));
        rdoc_heading(doc, 2, mh);
        for (int g = 0; g < a->ngroups && !rc; g++) {
            if (a->ngroups > 1)
                rdoc_heading(doc, 3, a->groups[g].label);
            values_table(doc, a, k, g);
            conv_table(doc, a, k, g);
            if (g < REPORT_MAX_VALUE_FIGS)
                rc = value_figure(doc, a, k, g, dir, e);
        }
        if (!rc && a->ngroups > REPORT_MAX_VALUE_FIGS)
            rdoc_para(doc, "Value figures are drawn for the first %d of the %d series.",
                      REPORT_MAX_VALUE_FIGS, a->ngroups);
        int max_err = REPORT_MAX_ERROR_FIGS * PLOT_MAX_SERIES;
        if (!rc && a->ngroups > 1)
            rdoc_heading(doc, 3, a->ngroups > max_err ? "Error against h, the first series"
                                                      : "Error against h, all series");
        for (int g0 = 0; g0 < a->ngroups && g0 < max_err && !rc; g0 += PLOT_MAX_SERIES) {
            int ng = a->ngroups - g0 < PLOT_MAX_SERIES ? a->ngroups - g0 : PLOT_MAX_SERIES;
            rc = error_figure(doc, a, k, g0, ng, dir, e);
        }
    }
    return rc;
}

/* --- other axes and fits ---------------------------------------------------- */

static const char *axis_label(const struct study_analysis *a, const struct sa_xplot *p)
{
    if (p->xaxis < 0)
        return a->d->metric[p->xmetric];
    const struct rspec_axis *o = report_spec_axis(a->rs, a->d->axes[p->xaxis].name);
    return o && o->label[0] ? o->label : a->d->axes[p->xaxis].name;
}

static void fit_table(struct rdoc *doc, const struct study_analysis *a, const struct sa_xplot *p)
{
    const struct rspec_fit *f = &a->rs->fits[p->fit];
    const char *xname = p->xaxis >= 0 ? a->d->axes[p->xaxis].name : a->d->metric[p->xmetric];
    if (f->model == FIT_LINEAR)
        rdoc_para(doc, "Least-squares fit %s = %s + %s * %s%s (standard errors from the scatter of "
                       "the points).",
                  f->metric, f->names[0], f->names[1], xname,
                  f->extrapolated ? " on the extrapolated values" : "");
    else
        rdoc_para(doc, "Least-squares fit %s = %s * %s^%s (a straight line in log-log)%s.",
                  f->metric, f->names[0], xname, f->names[1],
                  f->extrapolated ? " on the extrapolated values" : "");
    if (f->has_range)
        rdoc_para(doc, "Only the points with %s from %g to %g enter this fit.", xname, f->range[0],
                  f->range[1]);
    const char *hdr[] = {"series", "points", f->names[0], f->names[1], "R^2", "rms residual"};
    struct tab t = {6, 0, 0, NULL, 0};
    for (int s = p->first; s < p->first + p->n; s++) {
        const struct sa_xseries *xs = &a->xs[s];
        tab_put(&t, 0, "%s", xs->label);
        if (!xs->fit_ok) {
            tab_put(&t, 1, "%d", xs->n);
            tab_put(&t, 2, "too few points");
            tab_put(&t, 3, "—");
            tab_put(&t, 4, "—");
            tab_put(&t, 5, "—");
            continue;
        }
        char v[64], s0[64];
        tab_put(&t, 1, "%d", xs->fr.n);
        report_num(xs->fr.p0, 6, v, sizeof v);
        report_num(xs->fr.s0, 2, s0, sizeof s0);
        tab_put(&t, 2, "%s ± %s", v, s0);
        report_num(xs->fr.p1, 6, v, sizeof v);
        report_num(xs->fr.s1, 2, s0, sizeof s0);
        tab_put(&t, 3, "%s ± %s", v, s0);
        report_num(xs->fr.r2, 6, v, sizeof v);
        tab_put(&t, 4, "%s", v);
        report_num(xs->fr.rms, 3, v, sizeof v);
        tab_put(&t, 5, "%s", v);
    }
    tab_emit(doc, &t, hdr);
}

static int xplot_section(struct rdoc *doc, const struct study_analysis *a, int pi,
                         const char *dir, struct err *e)
{
    const struct sa_xplot *p = &a->xplots[pi];
    const struct rdata *d = a->d;
    int m = p->metric;
    const char *xl = axis_label(a, p);
    char h[512];
    snprintf(h, sizeof h, "%s against %s", d->metric[m], xl);
    rdoc_heading(doc, 2, h);
    int has_ext = 0, has_sd = 0;
    for (int s = p->first; s < p->first + p->n; s++)
        for (int i = 0; i < a->xs[s].n; i++) {
            has_ext |= p->xaxis >= 0 && isfinite(a->xs[s].yext[i]);
            has_sd |= isfinite(a->xs[s].ysd[i]);
        }
    const char *hdr[6];
    char hy[256];
    int nc = 0;
    hdr[nc++] = "series";
    hdr[nc++] = xl;
    snprintf(hy, sizeof hy, "%s [%s]%s", d->metric[m], unit_of(a, m),
             a->conv ? " (finest grid)" : "");
    hdr[nc++] = hy;
    if (has_sd)
        hdr[nc++] = "sd over repeats";
    if (has_ext)
        hdr[nc++] = "extrapolated";
    struct tab t = {nc, 0, 0, NULL, 0};
    for (int s = p->first; s < p->first + p->n; s++) {
        const struct sa_xseries *xs = &a->xs[s];
        for (int i = 0; i < xs->n; i++) {
            char b[64];
            int col = 0;
            tab_put(&t, col++, "%s", xs->label);
            report_num(xs->x[i], 8, b, sizeof b);
            tab_put(&t, col++, "%s", b);
            report_num(xs->y[i], 10, b, sizeof b);
            tab_put(&t, col++, "%s", b);
            if (has_sd) {
                report_num(xs->ysd[i], 3, b, sizeof b);
                tab_put(&t, col++, "%s", b);
            }
            if (has_ext) {
                report_num(xs->yext[i], 10, b, sizeof b);
                tab_put(&t, col++, "%s", b);
            }
        }
    }
    tab_emit(doc, &t, hdr);
    if (p->fit >= 0)
        fit_table(doc, a, p);
    /* the figure: up to PLOT_MAX_SERIES series (extrapolated ones too when few) */
    struct plot_spec ps = {0};
    char title[512], xlabel[256], ylabel[256];
    char mname[128];
    plot_text(d->metric[m], mname, sizeof mname);
    plot_text(xl, xlabel, sizeof xlabel);
    char xlab_t[256];
    plot_text(xl, xlab_t, sizeof xlab_t);
    snprintf(title, sizeof title, "%s against %s", mname, xlab_t);
    snprintf(ylabel, sizeof ylabel, "%s (%s)", mname, unit_of(a, m));
    ps.title = title;
    ps.xlabel = xlabel;
    ps.ylabel = ylabel;
    ps.logx = p->logx;
    int ns = p->n < PLOT_MAX_SERIES ? p->n : PLOT_MAX_SERIES;
    int with_ext = has_ext && 2 * ns <= PLOT_MAX_SERIES;
    char(*labels)[2][SA_LABEL_MAX] = mem_calloc((size_t)ns, sizeof *labels);
    char(*exprs)[256] = mem_calloc((size_t)ns, sizeof *exprs);
    char(*flabels)[SA_LABEL_MAX] = mem_calloc((size_t)ns, sizeof *flabels);
    if (!labels || !exprs || !flabels) {
        free(labels);
        free(exprs);
        free(flabels);
        return err_nomem(e, "figure");
    }
    for (int q = 0; q < ns; q++) {
        const struct sa_xseries *xs = &a->xs[p->first + q];
        const char *base = p->n > 1 ? xs->label : (a->conv ? "finest grid" : mname);
        plot_text(base, labels[q][0], SA_LABEL_MAX);
        ps.series[ps.nseries++] =
            (struct plot_series){labels[q][0], xs->x, xs->y, xs->n, PLOT_LINESPOINTS};
        if (p->fit >= 0 && xs->fit_ok) {
            const struct rspec_fit *f = &a->rs->fits[p->fit];
            fit_expr(&xs->fr, exprs[q], sizeof exprs[q]);
            char n0[64], n1[64];
            plot_text(f->names[0], n0, sizeof n0);
            plot_text(f->names[1], n1, sizeof n1);
            snprintf(flabels[q], SA_LABEL_MAX, "fit: %s = %.4g, %s = %.4g", n0, xs->fr.p0, n1,
                     xs->fr.p1);
            ps.overlays[ps.noverlays++] = (struct plot_overlay){exprs[q], flabels[q], ps.nseries};
        }
    }
    if (with_ext)
        for (int q = 0; q < ns; q++) {
            const struct sa_xseries *xs = &a->xs[p->first + q];
            snprintf(labels[q][1], SA_LABEL_MAX, "%s%sextrapolated", p->n > 1 ? labels[q][0] : "",
                     p->n > 1 ? ", " : "");
            ps.series[ps.nseries++] =
                (struct plot_series){labels[q][1], xs->x, xs->yext, xs->n, PLOT_POINTS};
        }
    char safe[128], safex[128], file[512], path[4096 + 512];
    file_safe(d->metric[m], safe, sizeof safe);
    file_safe(p->xaxis >= 0 ? d->axes[p->xaxis].name : d->metric[p->xmetric], safex, sizeof safex);
    snprintf(file, sizeof file, "fig-x%02d-%s-vs-%s.svg", pi, safe, safex);
    snprintf(path, sizeof path, "%s/%s", dir, file);
    int rc = plot_svg(&ps, path, e);
    if (!rc) {
        char cap[1024];
        snprintf(cap, sizeof cap, "%s against %s%s%s%s", d->metric[m], xl,
                 p->n > ns ? " (the first series only)" : "", p->fit >= 0 ? "; dashed: the fit" : "",
                 p->logx ? "; logarithmic x axis" : "");
        rdoc_figure(doc, dir, file, cap);
    }
    free(labels);
    free(exprs);
    free(flabels);
    return rc;
}

static int other_axes(struct rdoc *doc, const struct study_analysis *a, const char *dir,
                      struct err *e)
{
    int rc = 0;
    if (a->nxplots) {
        rdoc_heading(doc, 1, a->conv ? "Against the other swept values" : "Against the swept values");
        if (a->conv)
            rdoc_para(doc, "Each metric at the finest grid with a value (and extrapolated, where "
                           "the convergence analysis gives a value) against each other swept key "
                           "with numeric values; one series per combination of the rest.");
    }
    for (int i = 0; i < a->nxplots && !rc; i++)
        rc = xplot_section(doc, a, i, dir, e);
    /* fits the data could not serve */
    for (int f = 0; f < a->rs->nfits; f++) {
        const struct rspec_fit *ft = &a->rs->fits[f];
        int used = 0;
        for (int i = 0; i < a->nxplots; i++)
            used |= a->xplots[i].fit == f;
        if (!used)
            rdoc_para(doc, "Fit %s against %s (%s): no data -- the metric has no values, or '%s' "
                           "is neither a swept key with numeric values nor a recorded metric.",
                      ft->metric, ft->against, ft->where, ft->against);
    }
    return rc;
}

static void method(struct rdoc *doc, const struct study_analysis *a)
{
    if (!a->conv)
        return;
    rdoc_heading(doc, 1, "Method");
    rdoc_para(doc, "Celik et al., J. Fluids Eng. 130, 078001 (2008): for the three finest grids "
                   "h1 < h2 < h3 with values phi1, phi2, phi3, r21 = h2/h1, r32 = h3/h2, eps21 = "
                   "phi2 - phi1, eps32 = phi3 - phi2, s = sign(eps32/eps21), the observed order "
                   "solves p = |ln|eps32/eps21| + ln((r21^p - s)/(r32^p - s))| / ln r21 (Eqs. "
                   "5a-5c, fixed-point iteration); phi_ext21 = (r21^p phi1 - phi2)/(r21^p - 1) "
                   "(Eq. 6a); GCI_fine = Fs e_a21/(r21^p - 1) with e_a21 = |(phi1 - phi2)/phi1| "
                   "and Fs = %g (Eq. 8).  R = eps21/eps32 between 0 and 1: monotone; between -1 "
                   "and 0: oscillatory; |R| > 1: divergent (no extrapolation then).  The band "
                   "is Fs |eps21|/(r21^p - 1), the GCI in the metric's unit, which stays "
                   "meaningful when the limit is near zero.  The local p of a row uses that grid "
                   "and the next two coarser ones; with four or more grids, local orders that "
                   "agree show the asymptotic range better than the ratio GCI_32/(r21^p GCI_21), "
                   "which from the same three grids is 1 up to phi1/phi2 by construction.",
              a->rs->safety);
}

int report_build(struct rdoc *doc, const struct study_analysis *a, const struct report_info *ri,
                 const char *dir, struct err *e)
{
    clean_figures(dir);
    header(doc, a, ri);
    summary(doc, a);
    failures(doc, a);
    if (a->nmetrics == 0)
        rdoc_para(doc, "No metric values yet: nothing to analyse.");
    int rc = convergence(doc, a, dir, e);
    if (!rc)
        rc = other_axes(doc, a, dir, e);
    if (!rc)
        method(doc, a);
    return rc;
}

int report_write(const struct rdoc *doc, const char *dir, int md, int html, struct err *e)
{
    char path[4096 + 32];
    int rc = 0;
    if (md) {
        snprintf(path, sizeof path, "%s/report.md", dir);
        rc = rdoc_write_markdown(doc, path, e);
    }
    if (!rc && html) {
        snprintf(path, sizeof path, "%s/report.html", dir);
        rc = rdoc_write_html(doc, path, e);
    }
    return rc;
}
