/* nightly_page: the nightly dashboard as one static HTML page (see
 * nightly_page.h). */
#include "nightly_page.h"

#include <errno.h>
#include <jansson.h>
#include <libgen.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "baseline.h"
#include "build_info.h"
#include "db.h"
#include "launch.h"
#include "sysinfo.h"

/* --- the history of one study, read from the database ----------------------- */

struct np_night {
    long long id;
    char checked[40], git[64], version[64], machine[128];
    int passed, compared, regressed;
    int recorded;           /* it has regress_values rows (schema version 5 on) */
    json_t *dirs;           /* owned: distinct run directories of its values */
};

struct np_entry {
    char *metric, *what, *point, *unit;
    double *base, *val, *tol;   /* [nnights], NaN where none */
    int *verdict;               /* [nnights]: enum cmp_verdict, -1 not compared that night */
};

struct np_study {
    char name[128];
    struct np_night *nights;    /* oldest first */
    int nnights;
    struct np_entry *ent;
    int nent, cap;
};

static void np_study_free(struct np_study *s)
{
    for (int i = 0; i < s->nnights; i++)
        json_decref(s->nights[i].dirs);
    free(s->nights);
    for (int i = 0; i < s->nent; i++) {
        struct np_entry *x = &s->ent[i];
        free(x->metric);
        free(x->what);
        free(x->point);
        free(x->unit);
        free(x->base);
        free(x->val);
        free(x->tol);
        free(x->verdict);
    }
    free(s->ent);
    memset(s, 0, sizeof *s);
}

static const char *col_text(sqlite3_stmt *st, int c)
{
    const char *t = (const char *)sqlite3_column_text(st, c);
    return t ? t : "";
}

static double col_real(sqlite3_stmt *st, int c)
{
    return sqlite3_column_type(st, c) == SQLITE_NULL ? NAN : sqlite3_column_double(st, c);
}

static struct np_entry *entry_of(struct np_study *s, const char *metric, const char *what,
                                 const char *point, const char *unit)
{
    for (int i = 0; i < s->nent; i++)
        if (strcmp(s->ent[i].metric, metric) == 0 && strcmp(s->ent[i].what, what) == 0 &&
            strcmp(s->ent[i].point, point) == 0)
            return &s->ent[i];
    if (s->nent == s->cap) {
        int cap = s->cap ? 2 * s->cap : 32;
        struct np_entry *g = realloc(s->ent, (size_t)cap * sizeof *g);
        if (!g)
            return NULL;
        s->ent = g;
        s->cap = cap;
    }
    struct np_entry *x = &s->ent[s->nent];
    memset(x, 0, sizeof *x);
    size_t n = (size_t)s->nnights;
    x->metric = strdup(metric);
    x->what = strdup(what);
    x->point = strdup(point);
    x->unit = strdup(unit);
    x->base = malloc(n * sizeof *x->base);
    x->val = malloc(n * sizeof *x->val);
    x->tol = malloc(n * sizeof *x->tol);
    x->verdict = malloc(n * sizeof *x->verdict);
    s->nent++;
    if (!x->metric || !x->what || !x->point || !x->unit || !x->base || !x->val || !x->tol ||
        !x->verdict)
        return NULL;
    for (size_t i = 0; i < n; i++) {
        x->base[i] = x->val[i] = x->tol[i] = NAN;
        x->verdict[i] = -1;
    }
    return x;
}

static int verdict_code(const char *name)
{
    for (int v = 0; cmp_verdict_names[v]; v++)
        if (strcmp(cmp_verdict_names[v], name) == 0)
            return v;
    return -1;
}

static int load_study(sqlite3 *db, const char *name, int max_nights, struct np_study *s,
                      struct err *e)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name);
    sqlite3_stmt *st = NULL;
    int rc = db_prepare(db,
                        "SELECT c.id, c.checked, c.solver_git, c.solver_version, "
                        "coalesce(c.machine, ''), c.passed, c.compared, c.regressed, "
                        "EXISTS (SELECT 1 FROM regress_values v WHERE v.check_id = c.id) "
                        "FROM regress_checks c JOIN baselines b ON b.id = c.baseline_id "
                        "JOIN studies s ON s.id = b.study_id WHERE s.name = ?1 "
                        "ORDER BY c.checked DESC, c.id DESC LIMIT ?2",
                        &st, e);
    if (rc)
        return rc;
    sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 2, max_nights);
    int cap = 0;
    while (!rc && sqlite3_step(st) == SQLITE_ROW) {
        if (s->nnights == cap) {
            cap = cap ? 2 * cap : 16;
            struct np_night *g = realloc(s->nights, (size_t)cap * sizeof *g);
            if (!g) {
                rc = err_nomem(e, "nightly page");
                break;
            }
            s->nights = g;
        }
        struct np_night *n = &s->nights[s->nnights++];
        memset(n, 0, sizeof *n);
        n->id = sqlite3_column_int64(st, 0);
        snprintf(n->checked, sizeof n->checked, "%s", col_text(st, 1));
        snprintf(n->git, sizeof n->git, "%s", col_text(st, 2));
        snprintf(n->version, sizeof n->version, "%s", col_text(st, 3));
        snprintf(n->machine, sizeof n->machine, "%s", col_text(st, 4));
        n->passed = sqlite3_column_int(st, 5);
        n->compared = sqlite3_column_int(st, 6);
        n->regressed = sqlite3_column_int(st, 7);
        n->recorded = sqlite3_column_int(st, 8);
        n->dirs = json_array();
    }
    sqlite3_finalize(st);
    /* oldest first */
    for (int i = 0, j = s->nnights - 1; i < j; i++, j--) {
        struct np_night t = s->nights[i];
        s->nights[i] = s->nights[j];
        s->nights[j] = t;
    }
    if (!rc)
        rc = db_prepare(db,
                        "SELECT metric, what, point, unit, baseline, value, tolerance, verdict, "
                        "run_dirs FROM regress_values WHERE check_id = ?1 ORDER BY seq",
                        &st, e);
    for (int k = 0; !rc && k < s->nnights; k++) {
        sqlite3_reset(st);
        sqlite3_bind_int64(st, 1, s->nights[k].id);
        while (!rc && sqlite3_step(st) == SQLITE_ROW) {
            struct np_entry *x = entry_of(s, col_text(st, 0), col_text(st, 1), col_text(st, 2),
                                          col_text(st, 3));
            if (!x) {
                rc = err_nomem(e, "nightly page");
                break;
            }
            x->base[k] = col_real(st, 4);
            x->val[k] = col_real(st, 5);
            x->tol[k] = col_real(st, 6);
            x->verdict[k] = verdict_code(col_text(st, 7));
            json_t *dirs = json_loads(col_text(st, 8), 0, NULL);
            size_t i;
            json_t *d;
            json_array_foreach(dirs, i, d)
            {
                int seen = 0;
                size_t j;
                json_t *o;
                json_array_foreach(s->nights[k].dirs, j, o) seen |= json_equal(o, d);
                if (!seen)
                    json_array_append(s->nights[k].dirs, d);
            }
            json_decref(dirs);
        }
    }
    sqlite3_finalize(st);
    if (rc)
        np_study_free(s);
    return rc;
}

/* --- HTML and SVG ------------------------------------------------------------- */

static void esc(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

static void num(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.10g", x);
    else
        fputs("&ndash;", f);
}

/* A path relative to directory `from` (both absolute), for links that keep
 * working when the tree moves as a whole. */
static void relative_path(const char *from, const char *to, char *out, size_t len)
{
    size_t common = 0, i = 0;
    for (; from[i] && to[i] && from[i] == to[i]; i++)
        if (from[i] == '/')
            common = i;
    if (!from[i] && (to[i] == '/' || !to[i]))
        common = i;
    out[0] = '\0';
    for (const char *p = from + common; *p; p++)
        if (*p == '/')
            strncat(out, "../", len - strlen(out) - 1);
    const char *rest = to + common + (to[common] == '/');
    strncat(out, rest, len - strlen(out) - 1);
    if (!out[0])
        snprintf(out, len, ".");
}

static const char *const palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd",
                                      "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
#define NPAL 8

static int bad_verdict(int v)
{
    return v == CMP_REGRESSED || v == CMP_MISSING || v == CMP_FAILED;
}

/* (value - baseline) / tolerance; +-inf when the tolerance is 0 and the
 * value moved. */
static double deviation(const struct np_entry *x, int k)
{
    double d = x->val[k] - x->base[k];
    if (!isfinite(d))
        return NAN;
    if (x->tol[k] > 0)
        return d / x->tol[k];
    return d == 0 ? 0 : d > 0 ? INFINITY : -INFINITY;
}

#define FIG_W 760
#define FIG_H 250
#define M_L 64
#define M_R 16
#define M_T 16
#define M_B 52

/* One trend figure: entries [ents] of one metric and kind. */
static void trend_svg(FILE *f, const struct np_study *s, const int *ents, int n)
{
    int nn = s->nnights;
    double ymax = 1.5;
    for (int q = 0; q < n; q++)
        for (int k = 0; k < nn; k++) {
            double d = fabs(deviation(&s->ent[ents[q]], k));
            if (isfinite(d) && d * 1.15 > ymax)
                ymax = d * 1.15;
        }
    if (ymax > 5)
        ymax = 5;   /* beyond: drawn at the edge, with the value in the tooltip */
    double pw = FIG_W - M_L - M_R, ph = FIG_H - M_T - M_B, step = pw / (nn > 0 ? nn : 1);
#define XN(k) (M_L + ((k) + 0.5) * step)
#define YV(v) (M_T + ph * (1 - ((v) + ymax) / (2 * ymax)))
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 "
               "%d %d\" role=\"img\">\n",
            FIG_W, FIG_H, FIG_W, FIG_H);
    fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%g\" height=\"%g\" fill=\"#fff\" stroke=\"#999\"/>\n",
            M_L, M_T, pw, ph);
    /* the nights on which an entry of this metric did not pass */
    for (int k = 0; k < nn; k++) {
        int bad = 0;
        for (int q = 0; q < n; q++)
            bad |= bad_verdict(s->ent[ents[q]].verdict[k]);
        if (bad)
            fprintf(f, "<rect class=\"regressed-night\" x=\"%.1f\" y=\"%d\" width=\"%.1f\" "
                       "height=\"%g\" fill=\"#f8d0d0\"><title>%s: regressed</title></rect>\n",
                    XN(k) - step / 2, M_T, step, ph, s->nights[k].checked);
    }
    /* the tolerance band and the baseline */
    fprintf(f, "<rect class=\"band\" x=\"%d\" y=\"%.1f\" width=\"%g\" height=\"%.1f\" "
               "fill=\"#cfe3f7\" fill-opacity=\"0.8\"><title>tolerance band: |value - baseline| "
               "&lt;= tolerance</title></rect>\n",
            M_L, YV(1.0), pw, YV(-1.0) - YV(1.0));
    fprintf(f, "<line class=\"baseline\" x1=\"%d\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#222\" "
               "stroke-dasharray=\"6 3\"/>\n",
            M_L, YV(0.0), M_L + pw, YV(0.0));
    /* y axis */
    const double ticks[] = {-1, 0, 1};
    for (int t = 0; t < 3; t++)
        fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+g</text>\n",
                M_L - 6, YV(ticks[t]) + 4, ticks[t]);
    fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+.2g</text>\n",
            M_L - 6, YV(ymax) + 10, ymax);
    fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+.2g</text>\n",
            M_L - 6, YV(-ymax), -ymax);
    fprintf(f, "<text transform=\"translate(14 %.1f) rotate(-90)\" font-size=\"11\" "
               "text-anchor=\"middle\">(value &#8722; baseline) / tolerance</text>\n",
            M_T + ph / 2);
    /* x axis: the nights (at most about 12 labels) */
    int every = nn > 12 ? (nn + 11) / 12 : 1;
    for (int k = 0; k < nn; k++) {
        if ((nn - 1 - k) % every)
            continue;
        /* "11-25 02:30": month, day and time (several checks a day stay apart) */
        const char *c = s->nights[k].checked;
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"10\" text-anchor=\"middle\">%.5s "
                   "%.5s</text>\n",
                XN(k), FIG_H - M_B + 16, strlen(c) >= 16 ? c + 5 : c, strlen(c) >= 16 ? c + 11 : "");
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"9\" fill=\"#555\" "
                   "text-anchor=\"middle\">%.8s</text>\n",
                XN(k), FIG_H - M_B + 29, s->nights[k].git);
    }
    fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"11\" text-anchor=\"middle\">night (date, "
               "commit)</text>\n",
            M_L + pw / 2, FIG_H - 6);
    /* one line per point of the sweep */
    for (int q = 0; q < n; q++) {
        const struct np_entry *x = &s->ent[ents[q]];
        const char *color = palette[q % NPAL];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", color);
        for (int k = 0; k < nn; k++) {
            double d = deviation(x, k);
            if (isnan(d))
                continue;
            d = d > ymax ? ymax : d < -ymax ? -ymax : d;
            fprintf(f, "%.1f,%.1f ", XN(k), YV(d));
        }
        fputs("\"/>\n", f);
        for (int k = 0; k < nn; k++) {
            if (x->verdict[k] < 0 || x->verdict[k] == CMP_NEW)
                continue;
            double d = deviation(x, k);
            int bad = bad_verdict(x->verdict[k]);
            if (isnan(d)) {   /* no value that night: a cross at the top */
                fprintf(f, "<path class=\"novalue\" d=\"M%.1f %.1f l8 8 m0 -8 l-8 8\" "
                           "stroke=\"#c00\" stroke-width=\"2\"><title>",
                        XN(k) - 4, YV(ymax) + 2);
            } else {
                double y = d > ymax ? ymax : d < -ymax ? -ymax : d;
                fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%d\" fill=\"%s\" stroke=\"%s\" "
                           "stroke-width=\"%d\"%s><title>",
                        XN(k), YV(y), bad ? 5 : 3, color, bad ? "#c00" : color, bad ? 2 : 1,
                        bad ? " class=\"regressed\"" : "");
            }
            esc(f, s->nights[k].checked);
            fputs(" ", f);
            esc(f, x->point);
            fprintf(f, ": value %.10g, baseline %.10g, tolerance %.3g (%s)</title>%s\n", x->val[k],
                    x->base[k], x->tol[k], cmp_verdict_names[x->verdict[k]],
                    isnan(d) ? "</path>" : "</circle>");
        }
    }
    fputs("</svg>\n", f);
#undef XN
#undef YV
}

/* The numbers of the latest night a group was compared, under its figure. */
static void latest_table(FILE *f, const struct np_study *s, const int *ents, int n)
{
    fputs("<table class=\"latest\"><tr><th></th><th>point</th><th>baseline</th><th>latest "
          "value</th><th>tolerance</th><th>verdict</th><th>night</th></tr>\n",
          f);
    for (int q = 0; q < n; q++) {
        const struct np_entry *x = &s->ent[ents[q]];
        int k = s->nnights - 1;
        while (k > 0 && x->verdict[k] < 0)
            k--;
        int v = k >= 0 ? x->verdict[k] : -1;
        fprintf(f, "<tr%s><td><span class=\"swatch\" style=\"background:%s\"></span></td><td>",
                bad_verdict(v) ? " class=\"bad\"" : "", palette[q % NPAL]);
        esc(f, x->point);
        fputs("</td><td class=\"num\">", f);
        num(f, x->base[k]);
        fputs("</td><td class=\"num\">", f);
        num(f, x->val[k]);
        fputs("</td><td class=\"num\">", f);
        num(f, x->tol[k]);
        fprintf(f, "</td><td>%s</td><td class=\"num\">%.10s</td></tr>\n",
                v >= 0 ? cmp_verdict_names[v] : "", s->nights[k].checked);
    }
    fputs("</table>\n", f);
}

static void nights_table(FILE *f, const struct np_study *s, const char *page_dir)
{
    fputs("<table class=\"nights\"><tr><th>night (UTC)</th><th>commit</th><th>solver</th>"
          "<th>machine</th><th>verdict</th><th>compared</th><th>regressed</th><th>run "
          "directories</th></tr>\n",
          f);
    for (int k = s->nnights - 1; k >= 0; k--) {
        const struct np_night *n = &s->nights[k];
        fprintf(f, "<tr class=\"night%s\"><td>", n->passed ? "" : " regressed");
        esc(f, n->checked);
        fputs("</td><td><code>", f);
        esc(f, n->git);
        fputs("</code></td><td>", f);
        esc(f, n->version);
        fputs("</td><td>", f);
        esc(f, n->machine[0] ? n->machine : "?");
        fprintf(f, "</td><td>%s</td><td>%d</td><td>%d</td><td>", n->passed ? "passed" : "REGRESSED",
                n->compared, n->regressed);
        size_t nd = json_array_size(n->dirs);
        if (!n->recorded) {
            fputs("(recorded before the history table)", f);
        } else if (nd == 0) {
            fputs("none", f);
        } else {
            fprintf(f, "<details><summary>%zu director%s</summary>", nd, nd == 1 ? "y" : "ies");
            size_t i;
            json_t *d;
            json_array_foreach(n->dirs, i, d)
            {
                const char *abs = json_string_value(d);
                char rel[PATH_MAX], shown[PATH_MAX];
                relative_path(page_dir, abs, rel, sizeof rel);
                /* the last two components: KEY/attempt-N */
                const char *cut = abs + strlen(abs);
                for (int slashes = 0; cut > abs; cut--)
                    if (*(cut - 1) == '/' && ++slashes == 2)
                        break;
                snprintf(shown, sizeof shown, "%s", cut);
                fputs("<a class=\"rundir\" href=\"", f);
                esc(f, rel);
                fputs("\">", f);
                esc(f, shown);
                fputs("</a> ", f);
            }
            fputs("</details>", f);
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</table>\n", f);
}

static const char *css =
    "body{font-family:sans-serif;margin:1.5em auto;max-width:62em;color:#222}"
    "h1{font-size:1.5em}h2{font-size:1.25em;border-bottom:1px solid #ccc;margin-top:2em}"
    "h3{font-size:1.05em;margin-bottom:.3em}"
    "table{border-collapse:collapse;font-size:.85em;margin:.4em 0}"
    "td,th{border:1px solid #ccc;padding:.2em .5em;text-align:left;vertical-align:top}"
    "td.num{white-space:nowrap;text-align:right}"
    "tr.regressed td,tr.bad td{background:#fbe0e0}"
    ".swatch{display:inline-block;width:1.2em;height:.8em}"
    "figure{margin:.5em 0 1.5em 0}figcaption{font-size:.85em;color:#444}"
    "summary{cursor:pointer}a.rundir{display:inline-block;margin-right:.6em}"
    ".verdict-ok{color:#070}.verdict-bad{color:#b00;font-weight:bold}";

/* The figures of one study: one per metric and kind (value, order). */
static int study_section(FILE *f, const struct np_study *s, const char *page_dir, int *fig)
{
    fputs("<h2 id=\"", f);
    esc(f, s->name);
    fputs("\">Study ", f);
    esc(f, s->name);
    fputs("</h2>\n", f);
    const struct np_night *last = &s->nights[s->nnights - 1];
    fprintf(f, "<p>Latest night %s: <span class=\"%s\">%s</span> (%d entries compared, %d "
               "regressed). %d night%s shown.</p>\n",
            last->checked, last->passed ? "verdict-ok" : "verdict-bad",
            last->passed ? "passed" : "REGRESSED", last->compared, last->regressed, s->nnights,
            s->nnights == 1 ? "" : "s");
    nights_table(f, s, page_dir);
    int *ents = malloc((size_t)(s->nent ? s->nent : 1) * sizeof *ents);
    char *done = calloc((size_t)(s->nent ? s->nent : 1), 1);
    if (!ents || !done) {
        free(ents);
        free(done);
        return -1;
    }
    for (int i = 0; i < s->nent; i++) {
        if (done[i] || strcmp(s->ent[i].what, "job") == 0)
            continue;
        int n = 0;
        for (int j = i; j < s->nent; j++)
            if (!done[j] && strcmp(s->ent[j].metric, s->ent[i].metric) == 0 &&
                strcmp(s->ent[j].what, s->ent[i].what) == 0) {
                ents[n++] = j;
                done[j] = 1;
            }
        int order = strcmp(s->ent[i].what, "order p") == 0;
        (*fig)++;
        fprintf(f, "<figure class=\"trend\" id=\"fig-%d\">\n<h3>", *fig);
        esc(f, s->ent[i].metric);
        fputs(order ? ": observed order p" : "", f);
        if (!order && strcmp(s->ent[i].unit, "1") != 0) {
            fputs(" (", f);
            esc(f, s->ent[i].unit);
            fputs(")", f);
        }
        fputs("</h3>\n", f);
        trend_svg(f, s, ents, n);
        fprintf(f, "<figcaption>Figure %d. %s of %s over the nights, one line per %s: (value "
                   "&#8722; baseline) / tolerance. Shaded blue: the tolerance band; dashed: the "
                   "baseline; red columns and markers: nights on which an entry regressed or "
                   "had no value; a cross: no value that night.</figcaption>\n",
                *fig, order ? "The observed order" : "The value", s->ent[i].metric,
                order ? "series" : "point of the sweep");
        latest_table(f, s, ents, n);
        fputs("</figure>\n", f);
    }
    free(ents);
    free(done);
    return 0;
}

static int study_names(sqlite3 *db, const char *only, json_t *names, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "SELECT DISTINCT s.name FROM regress_checks c JOIN baselines b ON "
                            "b.id = c.baseline_id JOIN studies s ON s.id = b.study_id WHERE ?1 "
                            "IS NULL OR s.name = ?1 ORDER BY s.name",
                        &st, e);
    if (rc)
        return rc;
    if (only)
        sqlite3_bind_text(st, 1, only, -1, SQLITE_STATIC);
    while (sqlite3_step(st) == SQLITE_ROW)
        json_array_append_new(names, json_string(col_text(st, 0)));
    sqlite3_finalize(st);
    return 0;
}

int nightly_page_write(sqlite3 *db, const struct nightly_page_opts *o, int *nfigures,
                       struct err *e)
{
    *nfigures = 0;
    json_t *names = json_array();
    int rc = names ? study_names(db, o->study, names, e) : err_nomem(e, "nightly page");
    if (!rc && json_array_size(names) == 0)
        rc = o->study ? err_set(e, ERR_INPUT, "no regression check of study '%s' in %s (run "
                                              "cascade regress first)",
                                o->study, o->db_label)
                      : err_set(e, ERR_INPUT, "no regression check in %s (run cascade regress "
                                              "first, e.g. make nightly)",
                                o->db_label);
    char outcopy[PATH_MAX], dir[PATH_MAX], page_dir[PATH_MAX], tmp[PATH_MAX + 16];
    snprintf(outcopy, sizeof outcopy, "%s", o->out);
    snprintf(dir, sizeof dir, "%s", dirname(outcopy));
    if (!rc)
        rc = launch_mkdirs(dir, e);
    if (!rc && !realpath(dir, page_dir))
        rc = err_set(e, ERR_INPUT, "%s: %s", dir, strerror(errno));
    snprintf(tmp, sizeof tmp, "%s.tmp", o->out);
    FILE *f = NULL;
    if (!rc && !(f = fopen(tmp, "w")))
        rc = err_set(e, ERR_INPUT, "cannot write %s: %s", tmp, strerror(errno));
    if (!rc) {
        char now[40];
        sys_iso_time(sys_now(), now, sizeof now);
        fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                   "<title>Cascade nightly regressions</title>\n<style>%s</style>\n</head><body>\n"
                   "<h1>Cascade nightly regressions</h1>\n<p>Written %s by cascade %s (%s) "
                   "from <code>",
                css, now, CASCADE_VERSION, CASCADE_GIT_HASH);
        esc(f, o->db_label);
        fputs("</code> (the tables regress_checks and regress_values; docs/nightly.md). Each "
              "figure follows one metric over the nights: a value passes while it stays in the "
              "blue band, |value &#8722; baseline| &lt;= abs + rel |baseline| (an order: "
              "|p &#8722; p<sub>baseline</sub>| &lt;= its tolerance). Hover a marker for its "
              "numbers.</p>\n<ul>\n",
              f);
        size_t i;
        json_t *nm;
        json_array_foreach(names, i, nm)
        {
            fputs("<li><a href=\"#", f);
            esc(f, json_string_value(nm));
            fputs("\">", f);
            esc(f, json_string_value(nm));
            fputs("</a></li>\n", f);
        }
        fputs("</ul>\n", f);
        json_array_foreach(names, i, nm)
        {
            struct np_study s;
            rc = load_study(db, json_string_value(nm), o->nights, &s, e);
            if (rc)
                break;
            if (s.nnights > 0 && study_section(f, &s, page_dir, nfigures) != 0)
                rc = err_nomem(e, "nightly page");
            np_study_free(&s);
            if (rc)
                break;
        }
        fputs("</body></html>\n", f);
        if (!rc && (ferror(f) || fflush(f) != 0))
            rc = err_set(e, ERR_RUNTIME, "writing %s: %s", tmp, strerror(errno));
        if (fclose(f) != 0 && !rc)
            rc = err_set(e, ERR_RUNTIME, "writing %s: %s", tmp, strerror(errno));
        if (!rc && rename(tmp, o->out) != 0)
            rc = err_set(e, ERR_RUNTIME, "cannot write %s: %s", o->out, strerror(errno));
        if (rc)
            remove(tmp);
    }
    json_decref(names);
    return rc;
}
