/*
 * What a user of the command line expects (issue 17): `cascade --version`;
 * swept values printed as written (7.22, not 7.2199999999999998) by
 * `cascade plan`, in the database and by `cascade query --json`; progress lines with the ETA in a log
 * file (stdout not a terminal), also while no job finishes; the regress
 * table's "where" column wrapped between words, never cut inside one.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "campaign/baseline.h"
#include "campaign/progress_view.h"
#include "helpers/ct.h"

Test(cli_conventions, cascade_version)
{
    char out[8192];
    cr_assert_eq(ct_cascade("/tmp", NULL, out, sizeof out, "--version", NULL), 0, "%s", out);
    cr_assert_eq(strncmp(out, "cascade 0.", 10), 0, "%s", out);
    cr_assert_not_null(strstr(out, " ("), "%s", out);
    cr_assert_null(strstr(out, "unknown command"), "%s", out);
    /* the usage names it */
    cr_assert_eq(ct_cascade("/tmp", NULL, out, sizeof out, "--help", NULL), 0);
    cr_assert_not_null(strstr(out, "--version"), "%s", out);
}

static const char *skin_study = "name: skins\n"
                                "base:\n"
                                "  system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                                "element: Cu}\n"
                                "  potential: {style: sutton_chen}\n"
                                "  md: {steps: 10}\n"
                                "  output: {hdf5: false}\n"
                                "sweep:\n"
                                "  grid:\n"
                                "    md.skin: [7.22, 0.3]\n"
                                "    md.timestep: [0.00722, 0.001]\n"
                                "metrics: [atoms]\n";

Test(cli_conventions, plan_prints_sweep_values_as_written, .timeout = 60)
{
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml", skin_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "plan", "s.yaml", "--register", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "axis md.skin (grid, factor 1): [7.22,0.3]"), "%s", out);
    cr_assert_not_null(strstr(out, "axis md.timestep (grid, factor 2): [0.00722,0.001]"), "%s",
                       out);
    cr_assert_null(strstr(out, "99999"), "%s", out);
    cr_assert_null(strstr(out, "00000"), "%s", out);
    /* the database keeps the list as written too, and it reads back exactly */
    sqlite3 *db = ct_db(dir);
    char vals[256];
    ct_text(db, "SELECT vals FROM study_axes WHERE name = 'md.skin'", vals, sizeof vals);
    cr_assert_str_eq(vals, "[7.22,0.3]");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM job_params WHERE name = 'md.skin' AND "
                            "value = 7.22"),
                 2);
    sqlite3_close(db);
    /* and cascade query's JSON lines print them so too */
    rc = ct_cascade(dir, NULL, out, sizeof out, "query",
                    "SELECT name, value FROM job_params WHERE name = 'md.skin' ORDER BY value DESC "
                    "LIMIT 1",
                    "--json", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_str_eq(out, "{\"name\":\"md.skin\",\"value\":7.22}\n");
    rc = ct_cascade(dir, NULL, out, sizeof out, "plan", "s.yaml", "--json", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "\"md.skin\":7.22"), "%s", out);
    cr_assert_null(strstr(out, "99999"), "%s", out);
    ct_rmrf(dir);
}

/* Read everything written to a memory stream so far. */
static const char *stream_text(FILE *f, char **buf)
{
    fflush(f);
    return *buf ? *buf : "";
}

Test(cli_conventions, progress_in_a_log_has_periodic_status_lines_with_eta)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    cr_assert_not_null(f);
    struct progress_view v;
    progress_view_init(&v, f, 0, 10);
    cr_assert_eq(v.tty, 0);
    cr_assert_float_eq(v.plain_every, 60.0, 0, "the default interval");
    v.plain_every = 0.05;
    /* nothing before the interval has passed */
    progress_view_tick(&v, 0);
    cr_assert_str_eq(stream_text(f, &buf), "");
    usleep(30000);
    v.done = 3;
    v.finished_here = 3;
    v.running = 2;
    progress_view_job(&v, "done", "0123456789abcdef", "md.timestep=0.001", 1.5, NULL);
    const char *t = stream_text(f, &buf);
    cr_assert_not_null(strstr(t, "3/10 done 0123456789abcdef (md.timestep=0.001) 1.5s (ETA "), "%s",
                       t);
    usleep(60000);
    progress_view_tick(&v, 0);
    t = stream_text(f, &buf);
    const char *line = strstr(t, "progress: done 3 | failed 0 | running 2 | total 10 | ETA ");
    cr_assert_not_null(line, "%s", t);
    /* 3 jobs in about 0.09 s leave 7: an ETA of a fraction of a second, not '?' */
    const char *eta = strstr(line, "ETA ") + 4;
    double s = strtod(eta, NULL);
    cr_assert(s > 0 && s < 5, "ETA '%s'", eta);
    cr_assert_null(strchr(t, '\r'), "no carriage returns in a log: %s", t);
    cr_assert_null(strchr(t, '\033'), "no escape sequences in a log: %s", t);
    /* the next one only after another interval */
    size_t before = strlen(t);
    progress_view_tick(&v, 0);
    cr_assert_eq(strlen(stream_text(f, &buf)), before);
    /* 0 turns the periodic lines off */
    v.plain_every = 0;
    usleep(60000);
    progress_view_tick(&v, 0);
    cr_assert_eq(strlen(stream_text(f, &buf)), before);
    fclose(f);
    free(buf);
}

Test(cli_conventions, regress_where_column_wraps_between_words)
{
    struct cmp_report r;
    memset(&r, 0, sizeof r);
    struct cmp_item items[2];
    memset(items, 0, sizeof items);
    r.it = items;
    r.n = 2;
    /* a long point label: 12 entries of about 22 characters */
    char where[SA_LABEL_MAX] = "";
    for (int i = 0; i < 12; i++) {
        char one[64];
        snprintf(one, sizeof one, "%ssection.key_%02d=%d.125", i ? " " : "", i, 1000 + i);
        strncat(where, one, sizeof where - strlen(where) - 1);
    }
    cr_assert_gt(strlen(where), 200);
    for (int i = 0; i < 2; i++) {
        items[i].verdict = i ? CMP_OK : CMP_REGRESSED;
        snprintf(items[i].metric, sizeof items[i].metric, "pe_per_atom");
        snprintf(items[i].what, sizeof items[i].what, "value");
        snprintf(items[i].where, sizeof items[i].where, "%s", i ? "short=1" : where);
        items[i].base = -3.5;
        items[i].now = -3.4;
        items[i].tol = 1e-9;
    }
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    cmp_print(&r, f, 1);
    fclose(f);
    /* every entry of the label appears whole, and no line is wider than the
     * other columns plus 80 characters of "where" and the rest */
    for (int i = 0; i < 12; i++) {
        char one[64];
        snprintf(one, sizeof one, "section.key_%02d=%d.125", i, 1000 + i);
        cr_assert_not_null(strstr(buf, one), "'%s' cut:\n%s", one, buf);
    }
    int lines = 0;
    for (const char *p = buf; *p; p++)
        lines += *p == '\n';
    cr_assert_geq(lines, 5, "header, a wrapped row of 3+ lines, the short row:\n%s", buf);
    for (char *l = buf, *nl; (nl = strchr(l, '\n')); l = nl + 1)
        cr_assert_leq(nl - l, 200, "line too wide:\n%s", buf);
    cr_assert_not_null(strstr(buf, "short=1"), "%s", buf);
    free(buf);
}

/* cascade-solver info: every registry, with the keys each entry takes. */
Test(cli_conventions, solver_info_lists_every_registry_with_its_keys, .timeout = 60)
{
    const char *solver = getenv("CASCADE_SOLVER");
    cr_assert_not_null(solver);
    static char out[1 << 20];
    const char *argv[] = {solver, "info", NULL};
    cr_assert_eq(ct_exec("/tmp", NULL, argv, out, sizeof out), 0, "%.2000s", out);
    json_error_t je;
    json_t *info = json_loads(out, 0, &je);
    cr_assert_not_null(info, "%s: %.500s", je.text, out);
    /* the MPM constitutive laws are a registry like the others */
    json_t *mats = json_object_get(info, "mpm_materials");
    cr_assert_eq(json_object_size(mats), 3);
    cr_assert(json_is_string(json_object_get(mats, "j2")));
    json_t *keys = json_object_get(info, "keys");
    cr_assert(json_is_object(keys));
    /* every entry of every registry has its keys */
    static const char *const regs[] = {"case_types", "potential_styles", "mpm_materials"};
    for (int r = 0; r < 3; r++) {
        json_t *names = json_object_get(info, regs[r]), *k = json_object_get(keys, regs[r]);
        cr_assert_gt(json_object_size(names), 2, "%s", regs[r]);
        cr_assert_eq(json_object_size(k), json_object_size(names), "%s", regs[r]);
        const char *name;
        json_t *v;
        json_object_foreach(names, name, v)
        {
            json_t *tree = json_object_get(k, name);
            cr_assert(json_is_object(tree) && json_object_size(tree) > 0, "%s %s", regs[r], name);
            cr_assert_null(json_object_get(tree, "(listing stopped)"), "%s %s: %s", regs[r], name,
                           json_string_value(json_object_get(tree, "(listing stopped)")));
        }
    }
    /* required keys are named so, defaults are the solver's own */
    json_t *le = json_object_get(json_object_get(keys, "mpm_materials"), "linear_elastic");
    cr_assert_str_eq(json_string_value(json_object_get(le, "E")), "(required)");
    cr_assert_str_eq(json_string_value(json_object_get(le, "nu")), "(required)");
    cr_assert_str_eq(json_string_value(json_object_get(le, "density")), "(required)");
    cr_assert_str_eq(json_string_value(json_object_get(le, "rate")), "jaumann");
    json_t *j2 = json_object_get(json_object_get(keys, "mpm_materials"), "j2");
    cr_assert_not_null(json_object_get(j2, "yield"));
    json_t *eam = json_object_get(json_object_get(keys, "potential_styles"), "eam/alloy");
    cr_assert_str_eq(json_string_value(json_object_get(eam, "file")), "(required)");
    json_t *md = json_object_get(json_object_get(keys, "case_types"), "md");
    cr_assert_float_eq(json_real_value(json_object_get(json_object_get(md, "md"), "timestep")),
                       0.001, 1e-15);
    cr_assert_eq(json_integer_value(json_object_get(json_object_get(keys, "common"), "seed")), 1);
    cr_assert_not_null(json_object_get(json_object_get(keys, "common"), "output"));
    json_decref(info);
}
