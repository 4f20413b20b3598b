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
#include "launch.h"
#include "nightly_history.h"
#include "nightly_svg.h"
#include "sysinfo.h"

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
                np_bad_verdict(v) ? " class=\"bad\"" : "", np_color(q));
        np_esc(f, x->point);
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
        np_esc(f, n->checked);
        fputs("</td><td><code>", f);
        np_esc(f, n->git);
        fputs("</code></td><td>", f);
        np_esc(f, n->version);
        fputs("</td><td>", f);
        np_esc(f, n->machine[0] ? n->machine : "?");
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
                np_esc(f, rel);
                fputs("\">", f);
                np_esc(f, shown);
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
    np_esc(f, s->name);
    fputs("\">Study ", f);
    np_esc(f, s->name);
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
        /* value; order p; and what else regress compares per series (the
         * level and the value a refined series converged at) */
        const char *what = s->ent[i].what;
        int value = strcmp(what, "value") == 0, order = strcmp(what, "order p") == 0;
        (*fig)++;
        fprintf(f, "<figure class=\"trend\" id=\"fig-%d\">\n<h3>", *fig);
        np_esc(f, s->ent[i].metric);
        if (!value) {
            fputs(order ? ": observed order p" : ": ", f);
            if (!order)
                np_esc(f, what);
        }
        if (!order && strcmp(s->ent[i].unit, "1") != 0) {
            fputs(" (", f);
            np_esc(f, s->ent[i].unit);
            fputs(")", f);
        }
        fputs("</h3>\n", f);
        np_trend_svg(f, s, ents, n);
        fprintf(f, "<figcaption>Figure %d. %s of %s over the nights, one line per %s: (value "
                   "&#8722; baseline) / tolerance. Shaded blue: the tolerance band; dashed: the "
                   "baseline; red columns and markers: nights on which an entry regressed or "
                   "had no value; a cross: no value that night.</figcaption>\n",
                *fig, value ? "The value" : order ? "The observed order" : "The entry",
                s->ent[i].metric, value ? "point of the sweep" : "series");
        latest_table(f, s, ents, n);
        fputs("</figure>\n", f);
    }
    free(ents);
    free(done);
    return 0;
}

int nightly_page_write(sqlite3 *db, const struct nightly_page_opts *o, int *nfigures,
                       struct err *e)
{
    *nfigures = 0;
    json_t *names = json_array();
    int rc = names ? np_study_names(db, o->study, names, e) : err_nomem(e, "nightly page");
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
        np_esc(f, o->db_label);
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
            np_esc(f, json_string_value(nm));
            fputs("\">", f);
            np_esc(f, json_string_value(nm));
            fputs("</a></li>\n", f);
        }
        fputs("</ul>\n", f);
        json_array_foreach(names, i, nm)
        {
            struct np_study s;
            rc = np_study_load(db, json_string_value(nm), o->nights, &s, e);
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
