/*
 * The nightly history and dashboard end to end, with the stand-in solver
 * (exact, instant metrics x_squared = x^2 and sum = x + y): three nights of
 * `cascade regress` -- two that pass and one whose baseline moved a value
 * beyond its tolerance -- leave one regress_values row per compared entry
 * per night (value, baseline, tolerance, verdict, run directory, machine,
 * commit), and `cascade report --nightly` writes one self-contained page:
 * one figure per metric and kind with an inline SVG each, the tolerance
 * band centred on the baseline, the regressed night shaded and its marker
 * outside the band, the nights table with the regressed night marked and
 * links that resolve to the run directories.  No browser here (make
 * test-browser renders the page in headless Chromium).
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/ct.h"

static const char *fake_study = "name: fakenight\n"
                                "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
                                "sweep:\n"
                                "  grid:\n"
                                "    fake.y: [1.0, 2.0]\n"
                                "    fake.x: [0.1, 0.2, 0.4, 0.8]\n"
                                "metrics: [x_squared, sum]\n"
                                "report:\n"
                                "  resolution: fake.x\n"
                                "regress:\n"
                                "  tolerances:\n"
                                "    default: {abs: 0, rel: 1.0e-9}\n"
                                "    sum: {abs: 1.0e-6, rel: 0}\n"
                                "  order: 0.01\n";

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    cr_assert_eq(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

static int count(const char *hay, const char *needle)
{
    int n = 0;
    for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

/* The number after `attr="` in the element starting at `el`. */
static double attr(const char *el, const char *name)
{
    char key[64];
    snprintf(key, sizeof key, " %s=\"", name);
    const char *p = strstr(el, key);
    cr_assert_not_null(p, "no %s in %.200s", name, el);
    return strtod(p + strlen(key), NULL);
}

/* Move the baseline value of sum at x = 0.1, y = 1 by delta. */
static void move_sum(const char *dir, double delta)
{
    char path[512];
    snprintf(path, sizeof path, "%s/baselines/fakenight.json", dir);
    json_t *b = json_load_file(path, 0, NULL);
    cr_assert_not_null(b);
    size_t i;
    json_t *v;
    int n = 0;
    json_array_foreach(json_object_get(b, "values"), i, v)
    {
        json_t *p = json_object_get(v, "params");
        if (strcmp(json_string_value(json_object_get(v, "metric")), "sum") == 0 &&
            json_real_value(json_object_get(p, "fake.x")) == 0.1 &&
            json_real_value(json_object_get(p, "fake.y")) == 1.0) {
            json_object_set_new(v, "value", json_real(json_number_value(json_object_get(v, "value")) + delta));
            n++;
        }
    }
    cr_assert_eq(n, 1);
    cr_assert_eq(json_dump_file(b, path, JSON_INDENT(1)), 0);
    json_decref(b);
}

Test(nightly, history_table_and_dashboard_page, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "fake.yaml", fake_study);
    const char *fake = ct_standin();
    /* no check yet: the page says so and writes nothing */
    int rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                        "--update-baseline", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "--nightly", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "no regression check in"), "%s", out);
    /* night 1 and 2 pass; night 3 compares with a baseline moved beyond the
     * tolerance of sum (abs 1e-6) */
    for (int night = 1; night <= 3; night++) {
        if (night == 3)
            move_sum(dir, 5e-6);
        rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                        "--brief", "--quiet", NULL);
        cr_assert_eq(rc, night == 3 ? 1 : 0, "night %d: %s", night, out);
    }
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT check_id) FROM regress_values"), 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_values"), 3 * 20);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_history WHERE study = 'fakenight' AND "
                            "commit_git = 'standin' AND what = 'value' AND unit = '1'"),
                 3 * 16);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_history WHERE verdict != 'ok'"), 1);
    /* the regressed entry: that night's value, the moved baseline, its tolerance */
    cr_assert_float_eq(ct_real(db, "SELECT value FROM regress_history WHERE verdict = 'REGRESSED'"),
                       1.1, 1e-12);
    cr_assert_float_eq(
        ct_real(db, "SELECT baseline FROM regress_history WHERE verdict = 'REGRESSED'"),
        1.1 + 5e-6, 1e-12);
    cr_assert_float_eq(
        ct_real(db, "SELECT tolerance FROM regress_history WHERE verdict = 'REGRESSED'"), 1e-6,
        1e-18);
    char text[4096], host[256];
    ct_text(db, "SELECT point || ' ' || metric FROM regress_history WHERE verdict = 'REGRESSED'",
            text, sizeof text);
    cr_assert_str_eq(text, "fake.y=1.0 fake.x=0.1 sum");
    cr_assert_eq(ct_int(db, "SELECT night_passed FROM regress_history WHERE verdict = "
                            "'REGRESSED'"),
                 0);
    /* the machine, and the run directory the value came from */
    gethostname(host, sizeof host);
    ct_text(db, "SELECT DISTINCT machine FROM regress_history", text, sizeof text);
    cr_assert_str_eq(text, host);
    ct_text(db, "SELECT json_extract(run_dirs, '$[0]') FROM regress_history WHERE verdict = "
                "'REGRESSED'",
            text, sizeof text);
    char result[4200];
    snprintf(result, sizeof result, "%s/result.json", text);
    cr_assert_eq(access(result, R_OK), 0, "%s", result);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_values WHERE what = 'order p' AND "
                            "run_dirs = '[]' AND unit = '1'"),
                 3 * 4);
    sqlite3_close(db);

    /* the page */
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "--nightly", "--out", "dash/n.html", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "(4 figures)"), "%s", out);
    char path[512];
    snprintf(path, sizeof path, "%s/dash/n.html", dir);
    char *html = slurp(path);
    /* x_squared and sum, each as values and as observed orders */
    cr_assert_eq(count(html, "<figure class=\"trend\""), 4);
    cr_assert_eq(count(html, "<svg"), 4);
    cr_assert_eq(count(html, "</svg>"), 4);
    cr_assert_eq(count(html, "<rect class=\"band\""), 4);
    cr_assert_eq(count(html, "<line class=\"baseline\""), 4);
    cr_assert_not_null(strstr(html, "<h3>sum: observed order p</h3>"));
    /* self-contained: no scripts, no stylesheets or images from elsewhere */
    cr_assert_null(strstr(html, "<script"));
    cr_assert_null(strstr(html, "<link"));
    cr_assert_null(strstr(html, "src="));
    cr_assert_eq(count(html, "http"), 4, "only the SVG namespace");
    /* markers: 8 points x 3 nights per value figure, 2 series x 3 per order */
    cr_assert_eq(count(html, "<circle "), 2 * 24 + 2 * 6);
    /* one regressed night, in the sum figure only, its marker outside the band */
    cr_assert_eq(count(html, "class=\"regressed-night\""), 1);
    cr_assert_eq(count(html, "class=\"regressed\""), 1);
    const char *fig = strstr(html, "<h3>sum</h3>");
    cr_assert_not_null(fig);
    const char *band = strstr(fig, "<rect class=\"band\"");
    const char *base = strstr(fig, "<line class=\"baseline\"");
    const char *bad = strstr(fig, "class=\"regressed\"");
    while (bad > fig && strncmp(bad, "<circle", 7) != 0)
        bad--;
    double by = attr(band, "y"), bh = attr(band, "height"), ly = attr(base, "y1");
    cr_assert_gt(bh, 10);
    cr_assert_float_eq(ly, by + bh / 2, 0.11, "the baseline in the middle of the band");
    /* value - baseline = -5 tolerances: below the band (SVG y grows downwards) */
    double cy = attr(bad, "cy");
    cr_assert_gt(cy, by + bh, "cy %g, band %g..%g", cy, by, by + bh);
    /* the nights table: newest first, the regressed one marked */
    cr_assert_eq(count(html, "<tr class=\"night regressed\">"), 1);
    cr_assert_eq(count(html, "<tr class=\"night\">"), 2);
    cr_assert(strstr(html, "<tr class=\"night regressed\">") < strstr(html, "<tr class=\"night\">"));
    /* links to the run directories resolve from the page's directory */
    cr_assert_eq(count(html, "<a class=\"rundir\""), 3 * 8);
    const char *href = strstr(html, "<a class=\"rundir\" href=\"");
    cr_assert_not_null(href);
    href += strlen("<a class=\"rundir\" href=\"");
    char link[1024];
    snprintf(link, sizeof link, "%.*s", (int)(strchr(href, '"') - href), href);
    cr_assert_eq(strncmp(link, "../runs/fakenight/", 18), 0, "%s", link);
    snprintf(result, sizeof result, "%s/dash/%s/result.json", dir, link);
    cr_assert_eq(access(result, R_OK), 0, "%s", result);
    free(html);
    /* one study, or an unknown one */
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "--nightly", "nosuch", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "no regression check of study 'nosuch'"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "--nightly", "fakenight", "--nights",
                    "2", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    snprintf(path, sizeof path, "%s/reports/nightly.html", dir);
    html = slurp(path);
    cr_assert_eq(count(html, "<tr class=\"night"), 2);
    free(html);
    ct_rmrf(dir);
}
