/*
 * Convergence results as data: reference values brought in with `cascade
 * import` (CSV and JSON), analysed alone with `cascade report --format
 * json`, every number compared with an independent calculation to 1e-6
 * relative, and the same numbers in the database's convergence table.
 *
 * Cases: the three worked examples of Celik et al., J. Fluids Eng. 130,
 * 078001 (2008), Table 1 (2-D grids given as cell counts, h = (1/N)^(1/2);
 * the published rounded numbers of the first -- p = 1.53, phi_ext =
 * 6.1685, e_a21 = 1.5 %, GCI_fine = 2.17 % -- are checked at their stated
 * precision), and the NPARC Alliance grid-convergence example with
 * constant ratio r = 2 (f = 0.970500, 0.968540, 0.961780 on h = 1, 2, 4;
 * published p = 1.78617, f_ext = 0.971300, GCI_12 = 0.103 %, GCI_23 =
 * 0.356 %), where the order has the closed form ln(eps32/eps21) / ln 2.
 * The independent calculation solves Celik's Eq. 5 for p by bisection
 * (not the fixed-point iteration of campaign/convergence.c).
 *
 * Then the checks of bad files (unknown parameter or metric, missing unit,
 * duplicate rows: file:line, nothing written), and reference rows of a
 * campaign study shown beside the campaign's values.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "helpers/ct.h"

#define REL 1e-6

struct ref {
    double p, phi_ext, e_a21, e_ext21, gci_fine, gci_medium, asymptotic, band, r21, r32;
};

/* Celik Eqs. 5-8 by bisection on g(p) = p ln r21 - |ln|e32/e21| + q(p)|. */
static double g_of(double p, double r21, double r32, double lr, double s)
{
    return p * log(r21) - fabs(lr + log((pow(r21, p) - s) / (pow(r32, p) - s)));
}

static struct ref reference(const double h[3], const double phi[3])
{
    struct ref r;
    r.r21 = h[1] / h[0];
    r.r32 = h[2] / h[1];
    double e21 = phi[1] - phi[0], e32 = phi[2] - phi[1], s = e32 / e21 > 0 ? 1 : -1;
    double lr = log(fabs(e32 / e21)), lo = 1e-9, hi = 30;
    cr_assert(g_of(lo, r.r21, r.r32, lr, s) < 0 && g_of(hi, r.r21, r.r32, lr, s) > 0);
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (g_of(mid, r.r21, r.r32, lr, s) < 0)
            lo = mid;
        else
            hi = mid;
    }
    r.p = 0.5 * (lo + hi);
    double r21p = pow(r.r21, r.p), r32p = pow(r.r32, r.p);
    r.phi_ext = (r21p * phi[0] - phi[1]) / (r21p - 1);
    r.e_a21 = fabs((phi[0] - phi[1]) / phi[0]);
    r.e_ext21 = fabs((r.phi_ext - phi[0]) / r.phi_ext);
    r.gci_fine = 1.25 * r.e_a21 / (r21p - 1);
    r.gci_medium = 1.25 * fabs((phi[1] - phi[2]) / phi[1]) / (r32p - 1);
    r.asymptotic = r.gci_medium / (r21p * r.gci_fine);
    r.band = 1.25 * fabs(phi[1] - phi[0]) / (r21p - 1);
    return r;
}

static void near(double got, double want, const char *what, const char *series)
{
    cr_assert(fabs(got - want) <= REL * fabs(want), "%s of %s: %.15g, want %.15g (rel %.2g)", what,
              series, got, want, fabs(got - want) / fabs(want));
}

static json_t *load_json(const char *dir, const char *rel)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    json_error_t je;
    json_t *j = json_load_file(path, 0, &je);
    cr_assert_not_null(j, "%s: %s", path, je.text);
    return j;
}

static double num(const json_t *o, const char *key)
{
    const json_t *v = json_object_get(o, key);
    cr_assert(json_is_number(v), "%s is not a number", key);
    return json_number_value(v);
}

/* The series of `metric` whose series parameter `key` is `value` (key NULL: the only one). */
static const json_t *series_of(const json_t *doc, const char *metric, const char *key,
                               const char *value)
{
    size_t i;
    json_t *s;
    json_array_foreach(json_object_get(doc, "series"), i, s)
    {
        if (strcmp(json_string_value(json_object_get(s, "metric")), metric))
            continue;
        const json_t *v = key ? json_object_get(json_object_get(s, "series"), key) : NULL;
        if (!key || (json_is_string(v) && strcmp(json_string_value(v), value) == 0))
            return s;
    }
    cr_assert_fail("no series %s %s=%s", metric, key ? key : "", value ? value : "");
    return NULL;
}

static void check_celik(const json_t *s, const double h[3], const double phi[3], const char *name,
                        const char *kind)
{
    const json_t *c = json_object_get(s, "celik");
    cr_assert(json_is_object(c), "%s: no analysis (%s)", name,
              json_string_value(json_object_get(s, "note")));
    cr_assert_str_eq(json_string_value(json_object_get(c, "kind")), kind, "%s", name);
    struct ref r = reference(h, phi);
    for (int k = 0; k < 3; k++) {
        near(json_number_value(json_array_get(json_object_get(c, "h"), (size_t)k)), h[k], "h", name);
        near(json_number_value(json_array_get(json_object_get(c, "phi"), (size_t)k)), phi[k], "phi",
             name);
    }
    near(num(c, "r21"), r.r21, "r21", name);
    near(num(c, "r32"), r.r32, "r32", name);
    near(num(c, "p"), r.p, "p", name);
    near(num(c, "phi_ext"), r.phi_ext, "phi_ext", name);
    near(num(c, "e_a21"), r.e_a21, "e_a21", name);
    near(num(c, "e_ext21"), r.e_ext21, "e_ext21", name);
    near(num(c, "gci_fine"), r.gci_fine, "gci_fine", name);
    near(num(c, "gci_medium"), r.gci_medium, "gci_medium", name);
    near(num(c, "asymptotic"), r.asymptotic, "asymptotic", name);
    near(num(c, "band"), r.band, "band", name);
}

static const char *celik_csv =
    "# source: Celik et al. 2008, Table 1\n"
    "case,cells,phi [1]\n"
    "reattachment,18000,6.063\n"
    "reattachment,8000,5.972\n"
    "reattachment,4500,5.863\n"
    "velocity_y0.0526,18000,10.7880\n"
    "velocity_y0.0526,8000,10.7250\n"
    "velocity_y0.0526,4500,10.6050\n"
    "velocity_y0.8,18000,6.0042\n"
    "velocity_y0.8,4500,5.9624\n"
    "velocity_y0.8,980,6.0909\n";

Test(convergence_data, celik_table1_through_import_and_report_json, .timeout = 60)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "celik.csv", celik_csv);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "import", "celik", "celik.csv",
                        "--resolution", "cells", "--h", "cells", "--dim", "2", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "imported 9 rows"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "celik", "--format", "json", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_eq(out[0], '{', "--format json prints the document and nothing else: %.200s", out);
    json_t *doc = load_json(dir, "reports/celik/report.json");
    cr_assert_str_eq(json_string_value(json_object_get(doc, "source")),
                     "Celik et al. 2008, Table 1");
    static const struct {
        const char *name, *kind;
        double N[3], phi[3];
    } cases[3] = {
        {"reattachment", "monotone", {18000, 8000, 4500}, {6.063, 5.972, 5.863}},
        {"velocity_y0.0526", "monotone", {18000, 8000, 4500}, {10.7880, 10.7250, 10.6050}},
        {"velocity_y0.8", "oscillatory", {18000, 4500, 980}, {6.0042, 5.9624, 6.0909}},
    };
    for (int i = 0; i < 3; i++) {
        double h[3];
        for (int k = 0; k < 3; k++)
            h[k] = sqrt(1.0 / cases[i].N[k]);
        const json_t *s = series_of(doc, "phi", "case", cases[i].name);
        check_celik(s, h, cases[i].phi, cases[i].name, cases[i].kind);
    }
    /* the published, rounded numbers of the first case */
    const json_t *c = json_object_get(series_of(doc, "phi", "case", "reattachment"), "celik");
    cr_assert_lt(fabs(num(c, "p") - 1.53), 0.005);
    cr_assert_lt(fabs(num(c, "phi_ext") - 6.1685), 5e-5);
    cr_assert_lt(fabs(100 * num(c, "e_a21") - 1.5), 0.05);
    cr_assert_lt(fabs(100 * num(c, "gci_fine") - 2.17), 0.005);
    /* the convergence table holds the same numbers (REAL: doubles) */
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM convergence"), 3);
    double p = ct_real(db, "SELECT p FROM convergence WHERE series = '{\"case\":\"reattachment\"}'");
    cr_assert_eq(p, num(c, "p"), "the table keeps full precision: %.17g vs %.17g", p, num(c, "p"));
    cr_assert_eq(ct_int(db, "SELECT oscillatory FROM convergence WHERE series LIKE '%y0.8%'"), 1);
    sqlite3_close(db);
    json_decref(doc);
    ct_rmrf(dir);
}

/* NPARC Alliance, "Examining spatial (grid) convergence": r = 2, in JSON. */
static const char *nparc_json =
    "{\"source\": \"NPARC\", \"rows\": [\n"
    "  {\"params\": {\"h\": 1}, \"metrics\": {\"f\": {\"value\": 0.970500, \"unit\": \"1\"}}},\n"
    "  {\"params\": {\"h\": 2}, \"metrics\": {\"f\": {\"value\": 0.968540, \"unit\": \"1\"}}},\n"
    "  {\"params\": {\"h\": 4}, \"metrics\": {\"f\": {\"value\": 0.961780, \"unit\": \"1\"}}}\n"
    "]}\n";

Test(convergence_data, nparc_r2_example_closed_form, .timeout = 60)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "nparc.json", nparc_json);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "import", "nparc", "nparc.json", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "nparc", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *doc = load_json(dir, "reports/nparc/report.json");
    const json_t *s = series_of(doc, "f", NULL, NULL);
    double h[3] = {1, 2, 4}, f[3] = {0.970500, 0.968540, 0.961780};
    check_celik(s, h, f, "nparc", "monotone");
    const json_t *c = json_object_get(s, "celik");
    /* r = 2: p = ln(eps32 / eps21) / ln 2 exactly */
    near(num(c, "p"), log((f[2] - f[1]) / (f[1] - f[0])) / log(2.0), "closed-form p", "nparc");
    cr_assert_lt(fabs(num(c, "p") - 1.78617), 5e-6);
    cr_assert_lt(fabs(num(c, "phi_ext") - 0.971300), 5e-7);
    cr_assert_lt(fabs(100 * num(c, "gci_fine") - 0.103), 5e-4);
    cr_assert_lt(fabs(100 * num(c, "gci_medium") - 0.356), 5e-4);
    json_decref(doc);
    /* Markdown shows 4 significant digits */
    char path[512];
    snprintf(path, sizeof path, "%s/reports/nparc/report.md", dir);
    FILE *fp = fopen(path, "r");
    cr_assert_not_null(fp);
    static char md[200000];
    md[fread(md, 1, sizeof md - 1, fp)] = '\0';
    fclose(fp);
    cr_assert_not_null(strstr(md, "| GCI fine (GCI_21) | 0.1031 % |"), "%s", md);
    cr_assert_not_null(strstr(md, "± 0.001000"), "the band to 4 digits");
    ct_rmrf(dir);
}

static int exists(const char *dir, const char *name)
{
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &sb) == 0;
}

Test(convergence_data, bad_imports_name_file_and_line_and_write_nothing, .timeout = 60)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    /* a duplicate row: nothing written, not even a database */
    ct_write(0, dir, "dup.csv", "# source: x\nh,f [1]\n1,0.5\n2,0.6\n1,0.7\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "dup.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "dup.csv:5: duplicate row: the same parameters as line 3"), "%s",
                       out);
    cr_assert(!exists(dir, "cascade.db"), "a refused import creates no database");
    /* a metric without a unit (JSON: line and column) */
    ct_write(1, dir, "nounit.json",
             "source: x\nrows:\n  - params: {h: 1}\n    metrics: {f: {value: 1.0}}\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "nounit.json", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "nounit.json:4:15: rows[0].metrics.f: missing unit"), "%s", out);
    ct_write(2, dir, "nounit.csv", "# source: x\nh,f []\n1,0.5\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "nounit.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "nounit.csv:2: column 2 'f []': missing unit"), "%s", out);
    /* a good import, then one naming a parameter the study does not have */
    ct_write(3, dir, "good.csv", "# source: x\nh,f [1]\n1,0.5\n2,0.6\n4,0.9\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "good.csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    ct_write(4, dir, "other.csv", "# source: y\nh,f [1]\n1,0.5\n2,0.6\n");
    ct_write(5, dir, "badparam.csv", "# source: y\nh,dx,f [1]\n1,3,0.5\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "badparam.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "badparam.csv:3: dx: unknown parameter"), "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM imports"), 1, "the refused import wrote nothing");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM import_rows"), 3);
    sqlite3_close(db);
    /* no source named */
    ct_write(6, dir, "nosource.csv", "h,f [1]\n1,0.5\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "s", "nosource.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "say which source"), "%s", out);
    ct_rmrf(dir);
}

/* The stand-in solver's sum = x + y along fake.x, with references from
 * another "code" beside it; an unknown metric and a wrong unit are refused. */
static const char *fake_study =
    "name: withref\n"
    "base: {type: fake, fake: {x: 0.1, y: 1.0}}\n"
    "sweep:\n"
    "  grid:\n"
    "    fake.x: [0.1, 0.2, 0.4]\n"
    "metrics: [sum]\n"
    "report: {resolution: fake.x}\n";

Test(convergence_data, reference_rows_beside_the_campaign, .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml", fake_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    ct_write(1, dir, "bad.csv", "# source: lammps\nfake.x,pressure [GPa]\n0.1,1.0\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "withref", "bad.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "bad.csv:3: pressure: unknown metric"), "%s", out);
    ct_write(2, dir, "unit.csv", "# source: lammps\nfake.x,sum [eV]\n0.1,1.0\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "withref", "unit.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "unit 'eV' is not the study's '1'"), "%s", out);
    ct_write(3, dir, "ref.csv", "# source: lammps\nfake.x,sum [1]\n0.1,1.12\n0.2,1.25\n0.4,1.5\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "withref", "ref.csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "withref", "--csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "\n,reference,lammps,reference,4,,,,0.2,1.25\n"),
                       "export shows the reference rows: %s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "withref", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *doc = load_json(dir, "reports/withref/report.json");
    const json_t *refs = json_object_get(doc, "references");
    cr_assert_eq(json_array_size(refs), 3);
    const json_t *r0 = json_array_get(refs, 0);
    cr_assert_lt(fabs(num(r0, "campaign") - 1.1), 1e-12, "sum = 0.1 + 1.0 beside the reference");
    cr_assert_lt(fabs(num(r0, "diff") - (1.1 - 1.12)), 1e-12);
    json_decref(doc);
    /* the Celik procedure on the imported values alone */
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "withref", "--source", "lammps", "--out",
                    "refonly", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    doc = load_json(dir, "refonly/report.json");
    double h[3] = {0.1, 0.2, 0.4}, phi[3] = {1.12, 1.25, 1.5};
    check_celik(series_of(doc, "sum", NULL, NULL), h, phi, "lammps", "monotone");
    json_decref(doc);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM convergence WHERE source = 'campaign'"), 1);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM convergence WHERE source = 'lammps'"), 1);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* A study holding only references from two sources: the report asks which
 * one, and analyses each alone with --source. */
Test(convergence_data, two_sources_need_a_choice, .timeout = 60)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "a.csv", "# source: a\nh,f [1]\n1,0.970500\n2,0.968540\n4,0.961780\n");
    ct_write(1, dir, "b.csv", "# source: b\nh,f [1]\n1,2.0\n2,2.5\n4,4.5\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "import", "two", "a.csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "import", "two", "b.csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "two", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "2 imported sources [\"a\",\"b\"]: choose one with --source"),
                       "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "two", "--source", "b", "--format", "json",
                    NULL);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *doc = load_json(dir, "reports/two/report.json");
    const json_t *c = json_object_get(series_of(doc, "f", NULL, NULL), "celik");
    /* 2.0, 2.5, 4.5 on h = 1, 2, 4: eps32/eps21 = 4, so p = 2 and phi_ext = 2 - 0.5/3 */
    cr_assert_lt(fabs(num(c, "p") - 2.0), 1e-12);
    cr_assert_lt(fabs(num(c, "phi_ext") - (2.0 - 0.5 / 3.0)), 1e-12);
    json_decref(doc);
    rc = ct_cascade(dir, NULL, out, sizeof out, "report", "two", "--source", "c", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "no imported source 'c'"), "%s", out);
    ct_rmrf(dir);
}
