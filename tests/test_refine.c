/*
 * Adaptive refinement (`refine:`) end to end with the stand-in solver,
 * whose sum = x + y along fake.x (h = x) has order 1 and limit y: the
 * fine-grid GCI of three levels x1, 2 x1, 4 x1 is 1.25 x1 / (x1 + y)
 * exactly, so how many levels each series needs is known in advance.
 *
 *  - two series (y = 1 and y = 10) from x = 0.8, 0.4, 0.2 with until gci
 *    0.02: y = 10 converges at 4 levels (x = 0.1: GCI 1.238 %), y = 1 at 7
 *    (x = 0.0125: 1.543 %); 11 jobs, each an ordinary job; a rerun replays
 *    the decisions and runs nothing; `cascade status` and report.json show
 *    levels, GCI and state per series; a baseline holds the converged
 *    value and level and `cascade regress` flags a changed level;
 *  - max_levels stops a series and says so;
 *  - a budget the next level's predicted cost would break stops it before
 *    the level is started;
 *  - a key zipped with the axis follows it (inverse: x ratio per level);
 *    one without a follow rule is refused with file:line.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/ct.h"

static const char *two_series =
    "name: refsum\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
    "sweep:\n"
    "  grid:\n"
    "    fake.y: [1.0, 10.0]\n"
    "    fake.x: [0.8, 0.4, 0.2]\n"
    "metrics: [sum]\n"
    "report: {resolution: fake.x}\n"
    "refine:\n"
    "  metric: sum\n"
    "  ratio: 2\n"
    "  until: {gci: 0.02}\n"
    "  max_levels: %d\n"
    "regress:\n"
    "  tolerances: {default: {abs: 1.0e-12, rel: 0}}\n";

static void write_study(const char *dir, int max_levels)
{
    char text[2048];
    snprintf(text, sizeof text, two_series, max_levels);
    ct_write(0, dir, "s.yaml", text);
}

static const json_t *refine_row(const json_t *doc, double y)
{
    size_t i;
    json_t *r;
    json_array_foreach(json_object_get(doc, "refinement"), i, r)
    {
        if (json_number_value(json_object_get(json_object_get(r, "series"), "fake.y")) == y)
            return r;
    }
    cr_assert_fail("no refinement row for y = %g", y);
    return NULL;
}

Test(refine, series_refine_until_the_gci_is_met_and_rerun_resumes, .timeout = 180)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    write_study(dir, 8);
    const char *fake = ct_standin();
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", fake, "--quiet",
                        NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "[fake.y=10.0]: 4 levels, converged: sum: GCI 1.238 % <= 2.000 %"),
                       "%s", out);
    cr_assert_not_null(strstr(out, "[fake.y=1.0]: 7 levels, converged: sum: GCI 1.543 %"), "%s",
                       out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE active = 1"), 11);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 11, "every level ran once");
    cr_assert_eq(ct_int(db, "SELECT min(value) FROM job_params WHERE name = 'fake.x'") * 0, 0);
    double xmin = ct_real(db, "SELECT min(value) FROM job_params WHERE name = 'fake.x'");
    cr_assert_eq(xmin, 0.0125, "the finest level added: 0.2 / 2^4 = %g", xmin);
    /* the GCI of every level is kept in the convergence table */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM convergence WHERE series = '{\"fake.y\":1.0}'"), 5);
    double gci = ct_real(db, "SELECT gci_fine FROM refine_groups WHERE series = '{\"fake.y\":1.0}'");
    cr_assert_lt(fabs(gci - 1.25 * 0.0125 / 1.0125), 1e-12, "GCI = 1.25 x1 / (x1 + y): %.15g", gci);
    sqlite3_close(db);
    /* a rerun replays the decisions from the recorded results: nothing runs */
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", fake, "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "11 jobs: 11 done (11 earlier)"), "%s", out);
    db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 11, "a rerun repeats no work");
    sqlite3_close(db);
    rc = ct_cascade(dir, NULL, out, sizeof out, "status", "refsum", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "adaptive refinement along fake.x"), "%s", out);
    cr_assert_not_null(strstr(out, "converged"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "refsum", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    char path[512];
    snprintf(path, sizeof path, "%s/reports/refsum/report.json", dir);
    json_error_t je;
    json_t *doc = json_load_file(path, 0, &je);
    cr_assert_not_null(doc, "%s", je.text);
    const json_t *r1 = refine_row(doc, 1.0), *r10 = refine_row(doc, 10.0);
    cr_assert_eq(json_integer_value(json_object_get(r1, "levels")), 7);
    cr_assert_eq(json_integer_value(json_object_get(r10, "levels")), 4);
    cr_assert_str_eq(json_string_value(json_object_get(r10, "state")), "converged");
    cr_assert_eq(json_number_value(json_object_get(r10, "finest")), 0.1);
    json_decref(doc);
    /* the baseline holds the converged value and level; a changed level regresses */
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "s.yaml", "--solver", fake,
                    "--update-baseline", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "s.yaml", "--solver", fake, "--no-run",
                    NULL);
    cr_assert_eq(rc, 0, "%s", out);
    snprintf(path, sizeof path, "%s/baselines/refsum.json", dir);
    json_t *b = json_load_file(path, 0, &je);
    cr_assert_not_null(b, "%s", je.text);
    size_t i;
    json_t *v;
    int edited = 0;
    json_array_foreach(json_object_get(b, "converged"), i, v)
    {
        if (json_number_value(json_object_get(json_object_get(v, "group"), "fake.y")) == 10.0) {
            cr_assert_eq(json_integer_value(json_object_get(v, "levels")), 4);
            cr_assert_lt(fabs(json_number_value(json_object_get(v, "value")) - 10.1), 1e-12);
            json_object_set_new(v, "levels", json_integer(5));
            json_object_set_new(v, "finest", json_real(0.05));
            edited++;
        }
    }
    cr_assert_eq(edited, 1);
    cr_assert_eq(json_dump_file(b, path, JSON_INDENT(1)), 0);
    json_decref(b);
    rc = ct_cascade(dir, NULL, out, sizeof out, "regress", "s.yaml", "--solver", fake, "--no-run",
                    "--brief", NULL);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert_not_null(strstr(out, "(sum level)"), "%s", out);
    cr_assert_not_null(strstr(out, "baseline converged at 0.05 (5)"), "%s", out);
    ct_rmrf(dir);
}

Test(refine, max_levels_stops_a_series_and_says_so, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    write_study(dir, 5);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    char why[1024];
    ct_text(db, "SELECT state || ': ' || reason FROM refine_groups WHERE series = '{\"fake.y\":1.0}'",
            why, sizeof why);
    cr_assert_not_null(strstr(why, "stopped: max_levels 5 reached (sum: GCI 5.952 % > 2.000 %)"),
                       "%s", why);
    cr_assert_eq(ct_int(db, "SELECT levels FROM refine_groups WHERE series = '{\"fake.y\":1.0}'"), 5);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE active = 1"), 9);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* Each job sleeps 0.3 s: the three start levels cost at least 0.9
 * core-seconds, the next is predicted at 0.3 or more, so a budget of one
 * core-second stops the series before a fourth job is started. */
static const char *budget_study =
    "name: refbudget\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0, action: sleep, seconds: 0.3}}\n"
    "sweep:\n"
    "  grid:\n"
    "    fake.x: [0.8, 0.4, 0.2]\n"
    "metrics: [sum]\n"
    "report: {resolution: fake.x}\n"
    "refine: {metric: sum, until: {gci: 0.001}, budget: {core_seconds: 1.0}}\n";

Test(refine, a_level_that_would_break_the_budget_is_not_started, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "b.yaml", budget_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "b.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "stopped: budget: the next level (h = 0.1) is predicted to take"),
                       "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 3, "no fourth level");
    cr_assert_gt(ct_real(db, "SELECT next_core_s FROM refine_groups"), 0.29);
    cr_assert_gt(ct_real(db, "SELECT spent_core_s FROM refine_groups"), 0.89);
    sqlite3_close(db);
    ct_rmrf(dir);
}

static const char *zipped =
    "name: refzip\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
    "sweep:\n"
    "  zip:\n"
    "    fake.x: [0.8, 0.4, 0.2]\n"
    "    fake.steps: [1, 2, 4]\n"
    "metrics: [sum]\n"
    "report: {resolution: fake.x}\n"
    "refine:\n"
    "  metric: sum\n"
    "  until: {gci: 0.05}\n"
    "%s";

Test(refine, zipped_keys_follow_the_axis, .timeout = 120)
{
    char dir[64], out[65536], text[2048];
    ct_mkdir(dir, sizeof dir);
    snprintf(text, sizeof text, zipped, "");
    ct_write(0, dir, "z.yaml", text);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "z.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "z.yaml:9:1: refine: fake.steps is zipped with fake.x: say how "
                                   "it follows"),
                       "%s", out);
    snprintf(text, sizeof text, zipped, "  follow: {fake.steps: inverse}\n");
    ct_write(0, dir, "z.yaml", text);
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "z.yaml", "--solver", ct_standin(),
                    "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    /* GCI 1.25 x1/(x1 + 1) <= 5 %: x1 = 0.025 (3.05 %), three levels added */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 6);
    cr_assert_eq(ct_int(db, "SELECT max(value) FROM job_params WHERE name = 'fake.steps'"), 32);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* x_squared = x^2 has limit 0: a relative GCI cannot be met (the runner
 * stops and says to use the band); the band 1.25 x1^2 (order 2, ratio 2)
 * meets 0.002 at x1 = 0.025, three levels after 0.2. */
static const char *limit_zero =
    "name: refzero\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
    "sweep:\n"
    "  grid:\n"
    "    fake.x: [0.8, 0.4, 0.2]\n"
    "metrics: [x_squared]\n"
    "report: {resolution: fake.x}\n"
    "refine: {metric: x_squared, until: {%s}}\n";

Test(refine, a_limit_near_zero_needs_the_band, .timeout = 120)
{
    char dir[64], out[65536], text[1024];
    ct_mkdir(dir, sizeof dir);
    snprintf(text, sizeof text, limit_zero, "gci: 0.01");
    ct_write(0, dir, "z.yaml", text);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "z.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "stopped: x_squared: limit near 0, the relative GCI cannot meet "
                                   "1.000 % (use until.band)"),
                       "%s", out);
    snprintf(text, sizeof text, limit_zero, "band: 0.002");
    ct_write(0, dir, "z.yaml", text);
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "z.yaml", "--solver", ct_standin(),
                    "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "6 levels, converged: x_squared: band 0.0007813 <= 0.002"), "%s",
                       out);
    sqlite3 *db = ct_db(dir);
    cr_assert_lt(fabs(ct_real(db, "SELECT band FROM refine_groups") - 1.25 * 0.025 * 0.025), 1e-15);
    sqlite3_close(db);
    ct_rmrf(dir);
}
