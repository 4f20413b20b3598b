/*
 * cluster_impact with the handshake boundary and
 * `target.handshake.thermal.from_potential` (docs/impact.md, docs/handshake.md
 * "a(T) and the constants computed by the case"): the case computes a(T)
 * and the isothermal constants at the target temperature itself, by the
 * computation of type: elastic (scenarios/elastic_thermal.h), builds the
 * target at a(T) and gives the constants to the MPM.
 *
 * Stillinger-Weber silicon at 300 K, the short settings of
 * test_handshake_thermal_auto.c (216 atoms, 2 a(T) iterations, 1.5 ps
 * averages), a Si10 cluster at 4 km/s on the 6 x 6 x 5-cell target of
 * test_handshake_lattice_cases.c, 40 steps:
 *   - the values the case used are those of `type: elastic` with the same
 *     settings and seed, to round-off (one code path);
 *   - the run on them is the run with target.a and target.handshake.elastic
 *     given as those numbers (energies, bath heat, temperature to 1e-9);
 *   - they are physical: a(300 K) within 0.05 % of the 512-atom value
 *     5.43725 Å, C11, C12 within 6 % and C44 within 12 % of 149.11 / 76.42 /
 *     55.07 GPa (docs/handshake.md).
 * And `check` refuses conflicting and bad keys, naming file:line and key.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_case.h"

#define SETTINGS "strain: 0.01, timestep: 0.001, tau: 0.5, equilibrate: 500, sample: 1500, " \
                 "lattice_iterations: 2"
#define FROM_POTENTIAL "a_min: 5.2, a_max: 5.7, cells: 3, " SETTINGS

/* One key per line, so that the refusals' lines are known: the target's
 * temperature on line 7, a key of target.handshake on line 15, the
 * from_potential section on line 18, a key of target on line 19. */
static const char *impact_text(const char *temperature, const char *handshake_extra,
                               const char *from_potential, const char *target_extra)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: cluster_impact\n"
             "seed: 5\n"
             "target:\n"
             "  lattice: diamond\n"
             "  element: Si\n"
             "  cells: [6, 6, 5]\n"
             "  temperature: %s\n"
             "  boundary: handshake\n"
             "  handshake:\n"
             "    mpm: 4\n"
             "    regions: [2, 1, 1]\n"
             "    fine: 2\n"
             "    levels: 1\n"
             "    layer: 2\n"
             "    %s\n"
             "    thermal:\n"
             "      damping_time: 0.1\n"
             "      %s\n"
             "  %s\n"
             "cluster: {atoms: 10, speed: 4}\n"
             "potential: {style: sw, file: Si.sw, elements: [Si]}\n"
             "md: {timestep: 0.001, steps: 40}\n"
             "analysis: {every: 20, structure: {method: fixed}}\n"
             "output: {thermo_every: 20, snapshot_every: 0, hdf5: false}\n",
             temperature, handshake_extra, from_potential, target_extra);
    return buf;
}

Test(handshake_impact_auto, computes_the_constants_of_type_elastic, .timeout = 900)
{
    json_t *ra = th_run_case(0, "auto.yaml",
                             impact_text("300", "# no elastic",
                                         "from_potential: {" FROM_POTENTIAL "}", "# no a"));
    json_t *ma = json_object_get(ra, "metrics");
    double a = th_metric_value(ma, "lattice_constant_T");
    double c11 = th_metric_value(ma, "c11_mpm"), c12 = th_metric_value(ma, "c12_mpm"),
           c44 = th_metric_value(ma, "c44_mpm");
    cr_log_info("impact from_potential: a(300 K) %.6f Å, C11 %.2f +- %.2f, C12 %.2f +- %.2f, "
                "C44 %.2f +- %.2f GPa",
                a, c11, th_metric_value(ma, "c11_T_err"), c12, th_metric_value(ma, "c12_T_err"),
                c44, th_metric_value(ma, "c44_T_err"));
    cr_expect_eq(th_metric_value(ma, "from_potential"), 1);
    cr_expect_eq(th_metric_value(ma, "from_potential_md_steps"), (2 + 4) * 2000);
    cr_expect_eq(th_metric_value(ma, "target_atoms"), 1440);
    /* physical: SW at 300 K (docs/handshake.md) */
    cr_expect_lt(fabs(a / 5.43725 - 1), 5e-4, "a(300 K) %g Å", a);
    cr_expect_gt(th_metric_value(ma, "thermal_expansion"), 0.0008);
    cr_expect_lt(fabs(c11 / 149.11 - 1), 0.06, "C11 %g GPa", c11);
    cr_expect_lt(fabs(c12 / 76.42 - 1), 0.06, "C12 %g GPa", c12);
    cr_expect_lt(fabs(c44 / 55.07 - 1), 0.12, "C44 %g GPa", c44);
    /* diamond's internal shift at a(T), below the 0 K one (longer bonds) */
    cr_expect_lt(th_metric_value(ma, "kleinman_zeta_mpm"),
                 th_metric_value(ma, "kleinman_zeta") - 5e-4);

    /* type: elastic with the same settings and seed: the same numbers */
    th_expect_type_elastic(1, "{lattice: diamond, element: Si, a_min: 5.2, a_max: 5.7, cells: 3}",
                           "{style: sw, file: Si.sw, elements: [Si]}",
                           "{temperature: 300, " SETTINGS "}", ma);

    /* the same values given as inputs: the same run */
    char target_a[64], elastic[160];
    snprintf(target_a, sizeof target_a, "a: %.17g", a);
    snprintf(elastic, sizeof elastic, "elastic: {c11: %.17g, c12: %.17g, c44: %.17g}", c11, c12,
             c44);
    json_t *rx = th_run_case(2, "given.yaml", impact_text("300", elastic, "# none", target_a));
    json_t *mx = json_object_get(rx, "metrics");
    cr_expect_eq(th_metric_value(mx, "from_potential"), 0);
    const char *same[] = {"lattice_constant_T",     "kleinman_zeta_mpm",      "c44_mpm",
                          "atoms",                  "mpm_points",             "cluster_radius",
                          "energy_account_initial", "energy_account_final",   "mpm_energy",
                          "bath_heat",              "target_temperature_final"};
    for (size_t k = 0; k < sizeof same / sizeof same[0]; k++) {
        double x = th_metric_value(mx, same[k]), y = th_metric_value(ma, same[k]);
        cr_expect_float_eq(x, y, 1e-9 * fabs(y) + 1e-12, "%s: given %.12g, computed %.12g",
                           same[k], x, y);
    }
    json_decref(ra);
    json_decref(rx);
}

/* `check` exits 2 naming "file:line:" and the key. */
static void expect_refused(const char *name, const char *text, int line, const char *key,
                           const char *what)
{
    const char *path = th_write_temp(3, name, text);
    const char *argv[] = {th_solver(), "check", path, NULL};
    char out[4096], where[160];
    int st = th_run(argv, out, sizeof out);
    snprintf(where, sizeof where, "%s:%d:", name, line);
    cr_expect_eq(st, 2, "%s: exit %d, output: %s", name, st, out);
    cr_expect(strstr(out, where), "no '%s' in: %s", where, out);
    cr_expect(strstr(out, key), "no key '%s' in: %s", key, out);
    cr_expect(strstr(out, what), "no '%s' in: %s", what, out);
}

Test(handshake_impact_auto, refuses_conflicting_and_bad_keys, .timeout = 120)
{
    const char *fp = "from_potential: {" FROM_POTENTIAL "}";
    /* the case itself passes */
    const char *ok = th_write_temp(3, "ok.yaml", impact_text("300", "# -", fp, "# -"));
    const char *argv[] = {th_solver(), "check", ok, NULL};
    char out[4096];
    cr_expect_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    /* conflicting: the values it computes given as well, or no temperature */
    expect_refused("both_a.yaml", impact_text("300", "# -", fp, "a: 5.43725"), 19, "target.a",
                   "leave out target.a");
    expect_refused("both_c.yaml",
                   impact_text("300", "elastic: {c11: 149.11, c12: 76.42, c44: 55.07}", fp,
                               "# -"),
                   15, "target.handshake.elastic", "leave out c11, c12 and c44");
    expect_refused("cold.yaml", impact_text("0", "# -", fp, "# -"), 18,
                   "target.handshake.thermal.from_potential", "target.temperature > 0");
    /* bad values, on the from_potential line */
    static const struct {
        const char *name, *from_potential, *key, *what;
    } bad[] = {
        {"nan.yaml", "tau: .nan", "from_potential.tau", "must be a number"},
        {"huge.yaml", "strain: 1e300", "from_potential.strain", "must be in [1e-05, 0.05]"},
        {"negative.yaml", "cells: -3", "from_potential.cells", "must be in [2, 20]"},
        {"duplicate.yaml", "a_max: 5.8", "'a_max'", "duplicate key"},
        {"unknown.yaml", "seed: 3", "from_potential.seed", "unknown key"},
    };
    char line[256];
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(line, sizeof line, "from_potential: {a_min: 5.2, a_max: 5.7, %s}",
                 bad[k].from_potential);
        expect_refused(bad[k].name, impact_text("300", "# -", line, "# -"), 18, bad[k].key,
                       bad[k].what);
    }
    /* the bracket of the 0 K lattice constant */
    expect_refused("bracket.yaml",
                   impact_text("300", "# -", "from_potential: {a_min: 5.7, a_max: 5.2}", "# -"),
                   18, "target.handshake.thermal.from_potential.a_max", "must exceed a_min");
    expect_refused("no_min.yaml", impact_text("300", "# -", "from_potential: {a_max: 5.7}", "# -"),
                   18, "target.handshake.thermal.from_potential", "missing required key 'a_min'");
    expect_refused("no_minimum.yaml",
                   impact_text("300", "# -", "from_potential: {a_min: 4.0, a_max: 4.5}", "# -"),
                   18, "target.handshake.thermal.from_potential", "no energy minimum");
    /* without from_potential a hot target still needs both values (the
     * absent section is placed at its parent's first key) */
    expect_refused("no_c.yaml", impact_text("300", "# -", "# -", "a: 5.43725"), 10,
                   "target.handshake.elastic", "or thermal.from_potential");
}

/* The example of docs/impact.md checks (its run computes a(T) first: 25 s). */
Test(handshake_impact_auto, example_checks, .timeout = 120)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/docs/examples/si260_sw_impact_handshake_300K.yaml", th_root());
    const char *argv[] = {th_solver(), "check", path, NULL};
    char out[4096];
    cr_expect_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "45060 particles"), "%s", out);
}

/* `resolve` leaves out what depends on a(T) -- target.a, cluster.a and the
 * structure analysis' reference lattice constant (defaults to target.a) --
 * so that the resolved case reads again to the same case. */
Test(handshake_impact_auto, resolved_case_leaves_out_a_of_T, .timeout = 60)
{
    const char *path = th_write_temp(5, "resolve.yaml",
                                     impact_text("300", "# -",
                                                 "from_potential: {" FROM_POTENTIAL "}", "# -"));
    const char *argv[] = {th_solver(), "resolve", path, NULL};
    static char out[1 << 16], out2[1 << 16];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    json_error_t je;
    json_t *doc = json_loads(out, 0, &je);
    cr_assert_not_null(doc, "%s: %s", je.text, out);
    json_t *target = json_object_get(doc, "target");
    cr_expect_null(json_object_get(target, "a"));
    cr_expect_null(json_object_get(json_object_get(doc, "cluster"), "a"));
    cr_expect_null(json_object_get(json_object_get(json_object_get(doc, "analysis"), "structure"),
                                   "lattice_constant"));
    json_t *fp = json_object_get(json_object_get(json_object_get(target, "handshake"), "thermal"),
                                 "from_potential");
    cr_expect_eq(json_integer_value(json_object_get(fp, "cells")), 3);
    cr_expect_eq(json_integer_value(json_object_get(fp, "repeats")), 1);
    /* the resolved case resolves to itself */
    const char *again = th_write_temp(6, "resolved.json", out);
    const char *argv2[] = {th_solver(), "resolve", again, NULL};
    cr_assert_eq(th_run(argv2, out2, sizeof out2), 0, "%s", out2);
    json_t *doc2 = json_loads(out2, 0, &je);
    cr_expect(json_equal(doc, doc2), "%s\n%s", out, out2);
    json_decref(doc);
    json_decref(doc2);
}
