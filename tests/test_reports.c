/*
 * `cascade report` and `cascade regress` end to end.
 *
 * With the stand-in solver (exact, instant metrics x_squared = x^2 and
 * sum = x + y): regress writes a baseline, passes against it, passes when
 * a baseline value is moved within its tolerance, fails (exit 1) when a
 * value or an observed order is moved beyond it and names the metric, the
 * point and the order; failed jobs make it fail and refuse a new baseline;
 * every baseline and check is recorded in the database.  The report of a
 * study with an oscillatory and a divergent sequence and a failed job
 * flags both and lists the job with its reason, with its figures written
 * and inlined in the HTML page.  With the real solver: the report of a
 * small NVE time-step study (velocity Verlet) finds the observed order 2
 * of the potential energy and of the energy error, order 1 for the
 * time-averaged temperature, and draws the figures.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../campaign/db.h"
#include "helpers/ct.h"

static char *slurp(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
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

static int exists(const char *dir, const char *name)
{
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &sb) == 0 && sb.st_size > 0;
}

static int count(const char *hay, const char *needle)
{
    int n = 0;
    for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

/* x along the resolution axis, two values of y: x_squared has order 2
 * (limit 0), sum = x + y order 1 (limit y). */
static const char *fake_study =
    "name: fakeconv\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
    "sweep:\n"
    "  grid:\n"
    "    fake.y: [1.0, 2.0]\n"
    "    fake.x: [0.1, 0.2, 0.4, 0.8]\n"
    "metrics: [x_squared, sum]\n"
    "report:\n"
    "  resolution: fake.x\n"
    "  order: {x_squared: 2, sum: 1}\n"
    "regress:\n"
    "  tolerances:\n"
    "    default: {abs: 0, rel: 1.0e-9}\n"
    "    sum: {abs: 1.0e-6, rel: 0}\n"
    "  order: 0.01\n";

/* Move one entry of the baseline file. */
static void edit_baseline(const char *dir, const char *list, const char *metric, double x,
                          const char *field, double delta)
{
    char path[512];
    snprintf(path, sizeof path, "%s/baselines/fakeconv.json", dir);
    json_error_t je;
    json_t *b = json_load_file(path, 0, &je);
    cr_assert_not_null(b, "%s: %s", path, je.text);
    size_t i;
    json_t *v;
    int edited = 0;
    json_array_foreach(json_object_get(b, list), i, v)
    {
        if (strcmp(json_string_value(json_object_get(v, "metric")), metric) != 0)
            continue;
        json_t *p = json_object_get(v, strcmp(list, "values") == 0 ? "params" : "group");
        if (strcmp(list, "values") == 0 &&
            (json_real_value(json_object_get(p, "fake.x")) != x ||
             json_real_value(json_object_get(p, "fake.y")) != 1.0))
            continue;
        if (strcmp(list, "orders") == 0 && json_real_value(json_object_get(p, "fake.y")) != 1.0)
            continue;
        double old = json_number_value(json_object_get(v, field));
        json_object_set_new(v, field, json_real(old + delta));
        edited++;
    }
    cr_assert_eq(edited, 1, "no single %s entry of %s to edit", list, metric);
    cr_assert_eq(json_dump_file(b, path, JSON_INDENT(1)), 0);
    json_decref(b);
}

Test(reports, regress_fails_beyond_tolerance_and_names_the_metric, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "fake.yaml", fake_study);
    const char *fake = ct_standin();
    /* no baseline yet: bad input, and it says how to make one */
    int rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "--update-baseline"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                    "--update-baseline", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "16 values, 4 orders"), "%s", out);
    cr_assert(exists(dir, "baselines/fakeconv.json"));
    cr_assert(exists(dir, "reports/fakeconv/report.html"));
    /* the same results pass */
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake, NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "passed: 20 baseline entries within tolerance"), "%s", out);
    cr_assert_not_null(strstr(out, "8 done (8 earlier)"), "the jobs are reused: %s", out);
    /* a value moved within its tolerance (abs 1e-6) passes */
    edit_baseline(dir, "values", "sum", 0.1, "value", 5e-7);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                    "--no-run", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    /* ... and beyond it fails, naming the metric and the point */
    edit_baseline(dir, "values", "sum", 0.1, "value", 5e-6);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                    "--no-run", "--brief", NULL);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert_not_null(strstr(out, "REGRESSED: 1 of 20 baseline entries (sum value)"), "%s", out);
    cr_assert_not_null(strstr(out, "fake.y=1.0 fake.x=0.1"), "%s", out);
    cr_assert_eq(count(out, "\nREGRESSED "), 1, "--brief lists only what did not pass: %s", out);
    /* an observed order moved beyond 0.01 fails too */
    edit_baseline(dir, "values", "sum", 0.1, "value", -5.5e-6);
    edit_baseline(dir, "orders", "x_squared", 0, "p", 0.05);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "fake.yaml", "--solver", fake,
                    "--no-run", NULL);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert_not_null(strstr(out, "(x_squared order p)"), "%s", out);
    /* the report carries the verdict */
    char *html = slurp(dir, "reports/fakeconv/report.html");
    cr_assert_not_null(strstr(html, "Verdict: REGRESSED"));
    free(html);
    /* every distinct baseline and every check is in the database */
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM baselines"), 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_checks"), 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM regress_checks WHERE passed = 1"), 2);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM baseline_values v JOIN baselines b ON b.id = "
                            "v.baseline_id WHERE b.id = 1 AND quantity = 'order'"),
                 4);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM baselines WHERE solver_version = 'fake-1.0' "
                            "AND solver_git = 'standin'"),
                 4);
    char diff[4096];
    ct_text(db, "SELECT diff FROM regress_checks ORDER BY id DESC LIMIT 1", diff, sizeof diff);
    cr_assert_not_null(strstr(diff, "\"metric\":\"x_squared\""), "%s", diff);
    int nmig;
    db_migrations(&nmig);   /* regress migrated the database to the newest schema */
    cr_assert_eq(ct_int(db, "PRAGMA user_version"), nmig);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* The finest grid fails; the three finest grids that remain (x = 2, 4, 8,
 * h = 1/x) give sum = 0.7, 1.2, 1.0 (oscillatory) and x_squared = 4, 16, 64
 * (divergent as h falls). */
static const char *flag_study =
    "name: flags\n"
    "base: {type: fake}\n"
    "sweep:\n"
    "  zip:\n"
    "    fake.x: [1, 2, 4, 8, 16]\n"
    "    fake.y: [0.0, -1.3, -2.8, -7.0, 0.0]\n"
    "    fake.action: [ok, ok, ok, ok, exit]\n"
    "metrics: [x_squared, sum]\n"
    "retries: 0\n"
    "report:\n"
    "  resolution: {axis: fake.x, h: inverse, label: h = 1/x}\n";

Test(reports, report_flags_oscillation_divergence_and_failed_jobs, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "flags.yaml", flag_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "flags.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 1, "one job fails: %s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "flags", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "2 flagged"), "%s", out);
    char rdir[128];
    snprintf(rdir, sizeof rdir, "%s/reports/flags", dir);
    char *md = slurp(rdir, "report.md");
    /* the summary rows: x_squared divergent, sum oscillatory */
    cr_assert_not_null(strstr(md, "| x_squared | 1 | all jobs | 4 |"), "%s", md);
    cr_assert_not_null(strstr(md, "divergent; finest grid has no value"), "%s", md);
    cr_assert_not_null(strstr(md, "oscillatory; finest grid has no value"), "%s", md);
    /* the failed job with its reason, and the missing value in the table */
    cr_assert_not_null(strstr(md, "## Failed and missing jobs"), "%s", md);
    cr_assert_not_null(strstr(md, "| failed | 1 | exit 3"), "%s", md);
    cr_assert_not_null(strstr(md, "no value (1 job)"), "%s", md);
    /* figures: value figures for both metrics, error figures, all inlined */
    const char *figs[] = {"fig-00-x_squared-g0-value.svg", "fig-00-x_squared-g0-error.svg",
                          "fig-01-sum-g0-value.svg", "fig-01-sum-g0-error.svg", NULL};
    for (int i = 0; figs[i]; i++) {
        cr_assert(exists(rdir, figs[i]), "%s missing", figs[i]);
        char ref[128];
        snprintf(ref, sizeof ref, "](%s)", figs[i]);
        cr_assert_not_null(strstr(md, ref), "%s not referenced", figs[i]);
    }
    char *html = slurp(rdir, "report.html");
    cr_assert_eq(count(html, "<svg"), 4);
    cr_assert_null(strstr(html, "figure missing"));
    cr_assert_null(strstr(html, "<?xml"));
    free(md);
    free(html);
    /* only Markdown when asked; a bad format is refused */
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "flags", "--format", "md", "--out",
                    "only_md", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    snprintf(rdir, sizeof rdir, "%s/only_md", dir);
    cr_assert(exists(rdir, "report.md") && !exists(rdir, "report.html"));
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "flags", "--format", "pdf", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "nosuchstudy", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "no study named 'nosuchstudy'"), "%s", out);
    /* a baseline needs every job done */
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "flags.yaml", "--solver", ct_standin(),
                    "--update-baseline", "--quiet", NULL);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert_not_null(strstr(out, "1 job of flags is not done"), "%s", out);
    ct_rmrf(dir);
}

/* 108 atoms of Sutton-Chen copper, NVE for 0.2 ps at four time steps and
 * two neighbour-list skins (which must not matter). */
static const char *md_study =
    "name: mdconv\n"
    "base:\n"
    "  seed: 5\n"
    "  system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n"
    "  potential: {style: sutton_chen}\n"
    "  md: {temperature: 600}\n"
    "  output: {hdf5: false, thermo_every: 50}\n"
    "sweep:\n"
    "  zip:\n"
    "    md.timestep: [0.0005, 0.001, 0.002, 0.004]\n"
    "    md.steps: [400, 200, 100, 50]\n"
    "  grid:\n"
    "    md.skin: [1.0, 2.0]\n"
    "metrics: [pe_per_atom, energy_drift, temperature_mean]\n"
    "report:\n"
    "  order: {default: 2, temperature_mean: 1}\n";

/* The observed order of a summary row: "| metric | unit | series | grids | p |". */
static double summary_p(const char *md, const char *metric, const char *series)
{
    char key[256];
    snprintf(key, sizeof key, "| %s | ", metric);
    for (const char *row = strstr(md, key); row; row = strstr(row + 1, key)) {
        const char *eol = strchr(row, '\n');
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)(eol ? eol - row : 1000), row);
        if (!strstr(line, series))
            continue;
        char *cells[12];
        int n = 0;
        for (char *t = strtok(line, "|"); t && n < 12; t = strtok(NULL, "|"))
            cells[n++] = t;
        cr_assert_geq(n, 5, "%s", line);
        return strtod(cells[4], NULL);
    }
    cr_assert_fail("no summary row for %s, %s", metric, series);
    return NAN;
}

Test(reports, report_of_a_real_time_step_study, .timeout = 180)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "md.yaml", md_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "md.yaml", "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "md.yaml", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "3 metrics, 2 series along md.timestep"), "%s", out);
    char rdir[128];
    snprintf(rdir, sizeof rdir, "%s/reports/mdconv", dir);
    char *md = slurp(rdir, "report.md");
    /* resolution axis inferred from its name; velocity Verlet is second order */
    cr_assert_not_null(strstr(md, "resolution axis md.timestep (inferred"), "%s", md);
    for (int s = 0; s < 2; s++) {
        const char *series = s ? "md.skin=2.0" : "md.skin=1.0";
        double p = summary_p(md, "pe_per_atom", series);
        cr_assert(fabs(p - 2) < 0.05, "pe_per_atom p = %g", p);
        p = summary_p(md, "energy_drift", series);
        cr_assert(fabs(p - 2) < 0.05, "energy_drift p = %g", p);
        p = summary_p(md, "temperature_mean", series);
        cr_assert(fabs(p - 1) < 0.1, "temperature_mean p = %g (rectangle-rule average)", p);
    }
    /* the energy error converges to zero: the band is given, not a relative GCI */
    cr_assert_not_null(strstr(md, "limit near 0"), "%s", md);
    cr_assert_not_null(strstr(md, "| pe_per_atom | eV/atom | md.skin=1.0 | 4 |"), "%s", md);
    cr_assert_not_null(strstr(md, "## Against the other swept values"), "%s", md);
    cr_assert_not_null(strstr(md, "### pe_per_atom against md.skin"), "%s", md);
    cr_assert_null(strstr(md, "## Failed and missing jobs"));
    const char *figs[] = {"fig-00-pe_per_atom-g0-value.svg", "fig-00-pe_per_atom-g1-value.svg",
                          "fig-00-pe_per_atom-g0-error.svg", "fig-x00-pe_per_atom-vs-md_skin.svg",
                          NULL};
    for (int i = 0; figs[i]; i++)
        cr_assert(exists(rdir, figs[i]), "%s missing", figs[i]);
    char *html = slurp(rdir, "report.html");
    cr_assert_eq(count(html, "<svg"), 12, "3 metrics x (2 value + 1 error + 1 skin figure)");
    free(html);
    free(md);
    ct_rmrf(dir);
}

/* A swept string that carries gnuplot commands after a newline (a shell
 * escape '!cmd', a system "cmd" call, a quote that tries to end the
 * string first) must stay text: the report is written and no command
 * runs (before the fix, the first payload created its file). */
Test(reports, swept_strings_never_run_as_gnuplot_commands, .timeout = 120)
{
    char dir[64], out[65536], study[2048];
    ct_mkdir(dir, sizeof dir);
    snprintf(study, sizeof study,
             "name: inj\n"
             "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
             "sweep:\n"
             "  grid:\n"
             "    title: [\"a\\n!touch %s/pwned1\\n\", \"b\\nsystem \\\"touch %s/pwned2\\\"\\nc\",\n"
             "            \"d'\\n!touch %s/pwned3\\n\", \"e\\r!touch %s/pwned4\\r\",\n"
             "            \"`touch %s/pwned5`\"]\n"
             "    fake.x: [0.1, 0.2, 0.4]\n"
             "metrics: [x_squared, sum]\n"
             "report: {resolution: fake.x}\n",
             dir, dir, dir, dir, dir);
    ct_write(0, dir, "inj.yaml", study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "inj.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "inj", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    char rdir[128];
    snprintf(rdir, sizeof rdir, "%s/reports/inj", dir);
    cr_assert(exists(rdir, "fig-00-x_squared-g0-value.svg"));
    cr_assert(exists(rdir, "fig-01-sum-g4-value.svg"));
    const char *names[] = {"pwned1", "pwned2", "pwned3", "pwned4", "pwned5"};
    for (int i = 0; i < 5; i++) {
        char p[160];
        struct stat sb;
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        cr_assert_neq(stat(p, &sb), 0, "%s was created: a plot ran a command", p);
    }
    ct_rmrf(dir);
}

/* Whether every row of every Markdown table has as many cell separators
 * (unescaped '|') as the table's header: a raw newline or pipe in a cell
 * would break a row. */
static int md_tables_well_formed(const char *md, char *bad, size_t len)
{
    int header = -1;
    for (const char *line = md; *line;) {
        const char *eol = strchr(line, '\n');
        size_t n = eol ? (size_t)(eol - line) : strlen(line);
        if (n > 0 && line[0] == '|') {
            int pipes = 0;
            for (size_t i = 0; i < n; i++)
                pipes += line[i] == '|' && (i == 0 || line[i - 1] != '\\');
            if (header < 0)
                header = pipes;
            else if (pipes != header) {
                snprintf(bad, len, "%.*s", (int)n, line);
                return 0;
            }
        } else {
            header = -1;
        }
        line += n + (eol ? 1 : 0);
    }
    return 1;
}

Test(reports, swept_strings_are_literal_in_markdown, .timeout = 120)
{
    char dir[64], out[65536], bad[1024] = "";
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "md.yaml",
             "name: mdinj\n"
             "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
             "sweep:\n"
             "  grid:\n"
             "    title: [\"<script>alert(1)</script>\", \"a|b\\nc\", \"`rm -rf x`\",\n"
             "            \"x&amp;y [l](javascript:alert(1))\"]\n"
             "    fake.x: [0.1, 0.2, 0.4]\n"
             "metrics: [x_squared]\n"
             "report: {resolution: fake.x}\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "md.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "mdinj", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    char rdir[128];
    snprintf(rdir, sizeof rdir, "%s/reports/mdinj", dir);
    char *md = slurp(rdir, "report.md");
    /* the values are there, as text */
    cr_assert_not_null(strstr(md, "&lt;script&gt;alert(1)&lt;/script&gt;"), "%s", md);
    cr_assert_not_null(strstr(md, "x&amp;amp;y \\[l\\](javascript:alert(1))"), "%s", md);
    cr_assert_not_null(strstr(md, "a\\|b c"), "%s", md);
    cr_assert_not_null(strstr(md, "\\`rm -rf x\\`"), "%s", md);
    /* and nothing of them is markup: no raw tag, link, code span or broken row */
    cr_assert_null(strstr(md, "<script"), "%s", md);
    cr_assert_null(strstr(md, "[l](javascript"), "%s", md);
    for (const char *p = strchr(md, '`'); p; p = strchr(p + 1, '`'))
        cr_assert(p > md && p[-1] == '\\', "a raw backtick: %.40s", p > md + 20 ? p - 20 : md);
    cr_assert(md_tables_well_formed(md, bad, sizeof bad), "a broken table row: %s", bad);
    /* a heading per series, each on one line */
    cr_assert_not_null(strstr(md, "#### title=a\\|b c\n"), "%s", md);
    char *html = slurp(rdir, "report.html");
    cr_assert_null(strstr(html, "<script"));
    cr_assert_not_null(strstr(html, "&lt;script&gt;"));
    free(md);
    free(html);
    ct_rmrf(dir);
}
