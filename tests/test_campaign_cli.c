/*
 * cascade's commands end to end with the real solver: --help on every
 * subcommand; a small molecular-dynamics study whose sweep reads the final
 * configuration a preparation job wrote (${prep.equil}/final.xyz), so the
 * sweep starts from the equilibrated temperature; the job key equals the
 * case_key the solver writes into result.json; status, show, export --csv
 * and query (with --param, as the saved queries in db/queries/ use) print
 * what the database holds.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/ct.h"

Test(campaign_cli, help_on_every_command)
{
    const char *cmds[] = {"plan",  "run",   "status", "query",  "show",
                          "export", "retry", "report", "regress", NULL};
    char out[8192];
    cr_assert_eq(ct_cascade("/tmp", NULL, out, sizeof out, "--help", NULL), 0);
    for (int i = 0; cmds[i]; i++) {
        cr_assert_not_null(strstr(out, cmds[i]), "main help lacks %s", cmds[i]);
        char sub[8192];
        int rc = ct_cascade("/tmp", NULL, sub, sizeof sub, cmds[i], "--help", NULL);
        cr_assert_eq(rc, 0, "%s --help exits %d", cmds[i], rc);
        char want[64];
        snprintf(want, sizeof want, "usage: cascade %s", cmds[i]);
        cr_assert_not_null(strstr(sub, want), "%s --help: %s", cmds[i], sub);
    }
    cr_assert_eq(ct_cascade("/tmp", NULL, out, sizeof out, "frobnicate", NULL), 2);
    cr_assert_eq(ct_cascade("/tmp", NULL, out, sizeof out, "run", NULL), 2);
}

static const char *md_study =
    "name: mdprep\n"
    "base:\n"
    "  system: {read_xyz: '${prep.equil}/final.xyz'}\n"
    "  potential: {style: sutton_chen}\n"
    "  md: {temperature: 0, steps: 40}\n"
    "  output: {hdf5: false, thermo_every: 20}\n"
    "prep:\n"
    "  equil:\n"
    "    base:\n"
    "      seed: 3\n"
    "      system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n"
    "      potential: {style: sutton_chen}\n"
    "      md: {timestep: 0.002, steps: 100, temperature: 400,\n"
    "           thermostat: {style: berendsen, temperature: 200, tau: 0.02}}\n"
    "      output: {hdf5: false, thermo_every: 50, xyz_every: 100}\n"
    "sweep:\n"
    "  grid:\n"
    "    md.timestep: [0.001, 0.002]\n"
    "metrics: [temperature_mean, energy_drift, atoms]\n";

Test(campaign_cli, md_study_with_preparation_job, .timeout = 120)
{
    char dir[64], out[32768];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "md.yaml", md_study);
    int rc = ct_cascade(dir, NULL, out, sizeof out, "plan", "md.yaml", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "3 jobs (1 preparation, 2 sweep)"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "run", "md.yaml", "--jobs", "2", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM job_deps"), 2);
    /* 108 atoms read back from the preparation job's final.xyz */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'atoms' AND value = 108"),
                 3);
    /* the sweep starts from the state the Berendsen thermostat made (near 200 K),
     * not from the 400 K the preparation job started with */
    double t_prep = ct_real(db, "SELECT value FROM results WHERE kind = 'prep' AND "
                                "metric = 'temperature_mean'");
    double t_sweep = ct_real(db, "SELECT avg(value) FROM results WHERE kind = 'sweep' AND "
                                 "metric = 'temperature_mean'");
    cr_assert_lt(t_sweep, 300.0, "sweep mean temperature %g K", t_sweep);
    cr_assert_gt(t_sweep, 100.0, "sweep mean temperature %g K", t_sweep);
    cr_assert_lt(t_prep, 320.0, "prep mean temperature %g K", t_prep);
    /* only the study's metrics are recorded */
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT name) FROM metrics"), 3);
    /* the job key is the solver's key of the case it ran (no prep reference) */
    char key[32], res[600];
    ct_text(db, "SELECT key FROM jobs WHERE kind = 'prep'", key, sizeof key);
    ct_text(db, "SELECT path FROM artifacts WHERE kind = 'result' AND run_id = "
                "(SELECT last_run_id FROM jobs WHERE kind = 'prep')", res, sizeof res);
    json_t *r = json_load_file(res, 0, NULL);
    cr_assert_not_null(r, "%s", res);
    cr_assert_str_eq(json_string_value(json_object_get(r, "case_key")), key);
    json_decref(r);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM artifacts WHERE path LIKE '%/final.xyz' AND "
                            "bytes > 1000"),
                 1);
    sqlite3_close(db);

    /* status, show, export, query */
    rc = ct_cascade(dir, NULL, out, sizeof out, "status", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "mdprep"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "status", "mdprep", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "3 jobs: 3 done, 0 failed"), "%s", out);
    char prefix[8];
    snprintf(prefix, sizeof prefix, "%.6s", key);
    rc = ct_cascade(dir, NULL, out, sizeof out, "show", prefix, "--case", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, key), "%s", out);
    cr_assert_not_null(strstr(out, "temperature_mean"), "%s", out);
    cr_assert_not_null(strstr(out, "berendsen"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "mdprep", "--csv", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert(strncmp(out, "key,kind,name,state,attempt,solver_version,solver_git,wall_s,"
                           "md.timestep,atoms [1],energy_drift [1],temperature_mean [K]\n",
                      strlen("key,kind,name,state,attempt,solver_version,solver_git,wall_s,"
                             "md.timestep,atoms [1],energy_drift [1],temperature_mean [K]\n")) == 0,
              "%s", out);
    int lines = 0;
    for (const char *c = out; *c; c++)
        lines += *c == '\n';
    cr_assert_eq(lines, 4, "%s", out);
    /* CSV is the default format; JSON lines hold the same table, typed */
    char csv[sizeof out];
    snprintf(csv, sizeof csv, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "mdprep", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_str_eq(out, csv);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "mdprep", "--format", "jsonl", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    int objects = 0;
    for (char *line = out, *nl; (nl = strchr(line, '\n')); line = nl + 1) {
        *nl = '\0';
        json_error_t je;
        json_t *o = json_loads(line, 0, &je);
        cr_assert_not_null(o, "line %d not JSON: %s: %s", objects + 1, je.text, line);
        if (json_is_string(json_object_get(o, "name")) &&
            strcmp(json_string_value(json_object_get(o, "kind")), "sweep") == 0) {
            cr_assert(json_is_real(json_object_get(o, "md.timestep")), "%s", line);
            cr_assert(json_is_real(json_object_get(o, "temperature_mean [K]")), "%s", line);
            cr_assert(json_is_integer(json_object_get(o, "attempt")), "%s", line);
        }
        cr_assert_eq(json_object_size(o), 12, "%s", line);
        json_decref(o);
        objects++;
    }
    cr_assert_eq(objects, 3, "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "mdprep", "--format", "parquet", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "give csv or jsonl"), "%s", out);
    /* error paths of export: each a message and exit 2, never a crash (both
     * were a double free of the finalized statement) */
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "nosuch", "--csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "no study named 'nosuch'"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "export", "mdprep", "--csv", "--out",
                    "/nonexistent/dir/x.csv", NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "/nonexistent/dir/x.csv"), "%s", out);
    char qfile[512];
    snprintf(qfile, sizeof qfile, "%s/db/queries/metric_vs_param.sql", getenv("CASCADE_ROOT"));
    rc = ct_cascade(dir, NULL, out, sizeof out, "query", "-f", qfile, "--csv", "--param",
                    "study=mdprep", "--param", "metric=temperature_mean", "--param",
                    "param=md.timestep", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    cr_assert_not_null(strstr(out, "\n0.001,"), "%s", out);
    cr_assert_not_null(strstr(out, "\n0.002,"), "%s", out);
    rc = ct_cascade(dir, NULL, out, sizeof out, "query", "-f", qfile, NULL);
    cr_assert_eq(rc, 2, "a missing --param must be an error: %s", out);
    cr_assert_not_null(strstr(out, "--param"), "%s", out);
    ct_rmrf(dir);
}
