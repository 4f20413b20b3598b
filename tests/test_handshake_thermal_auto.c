/*
 * handshake_thermal with `thermal.from_potential` (docs/handshake.md, "a(T)
 * and the constants computed by the case"): the case computes a(T) and the
 * isothermal constants at T itself, by the computation of type: elastic
 * (scenarios/elastic_thermal.h), and runs on them.
 *
 * Stillinger-Weber silicon at 300 K, short settings (216 atoms, 2 a(T)
 * iterations, 1.5 ps averages), the quick [100] bar of
 * test_handshake_thermal_lattices.c run for 0.5 ps:
 *   - the values the case computed are those of `type: elastic` with the
 *     same settings and seed, to round-off (one code path);
 *   - the run on them is the run with the same values given as inputs
 *     (same MD temperatures to round-off);
 *   - and they are physical: a(300 K) within 0.05 % of the 512-atom,
 *     6 ps value 5.43725 Å (+0.12 % above a0: the thermal pressure of SW
 *     removed), C11, C12 within 6 % and C44 within 12 % of 149.11 / 76.42 /
 *     55.07 GPa (docs/handshake.md; a 216-atom crystal and 1.5 ps averages:
 *     errors of 1-3 GPa).
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

static const char *bar_text(const char *thermal_extra, const char *elastic)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: handshake_thermal\n"
             "seed: 5\n"
             "crystal: {lattice: diamond, element: Si, a_min: 5.2, a_max: 5.7}\n"
             "potential: {style: sw, file: Si.sw, elements: [Si]}\n"
             "%s"
             "thermal: {temperature: 300, damping_time: 0.1, equilibrate: 0.25, block: 0.25, %s}\n"
             "handshake: {regions: [2, 1, 1], levels: 0}\n"
             "bar: {mpm: [4, 4], md: 8, width: 3}\n"
             "md: {timestep: 0.001, steps: 500}\n"
             "output: {thermo_every: 100, snapshot_every: 0, hdf5: false}\n",
             elastic, thermal_extra);
    return buf;
}

Test(handshake_thermal_auto, computes_the_constants_of_type_elastic, .timeout = 600)
{
    json_t *ra = th_run_case(0, "auto.yaml",
                             bar_text("from_potential: {cells: 3, " SETTINGS "}", ""));
    json_t *ma = json_object_get(ra, "metrics");
    double a = th_metric_value(ma, "lattice_constant_T");
    double c11 = th_metric_value(ma, "c11_mpm"), c12 = th_metric_value(ma, "c12_mpm"),
           c44 = th_metric_value(ma, "c44_mpm");
    cr_log_info("from_potential: a(300 K) %.6f Å, C11 %.2f +- %.2f, C12 %.2f +- %.2f, C44 %.2f "
                "+- %.2f GPa, MD mean %.1f K",
                a, c11, th_metric_value(ma, "c11_T_err"), c12, th_metric_value(ma, "c12_T_err"),
                c44, th_metric_value(ma, "c44_T_err"), th_metric_value(ma, "temperature_md_mean"));
    cr_expect_eq(th_metric_value(ma, "from_potential"), 1);
    cr_expect_float_eq(th_metric_value(ma, "lattice_constant"), a, 1e-12);
    /* physical: SW at 300 K (docs/handshake.md) */
    cr_expect_lt(fabs(a / 5.43725 - 1), 5e-4, "a(300 K) %g Å", a);
    cr_expect_gt(th_metric_value(ma, "thermal_expansion"), 0.0008);
    cr_expect_lt(fabs(c11 / 149.11 - 1), 0.06, "C11 %g GPa", c11);
    cr_expect_lt(fabs(c12 / 76.42 - 1), 0.06, "C12 %g GPa", c12);
    cr_expect_lt(fabs(c44 / 55.07 - 1), 0.12, "C44 %g GPa", c44);
    /* the MD region at those values keeps 300 K over the short window */
    cr_expect_lt(fabs(th_metric_value(ma, "temperature_md_mean") / 300 - 1), 0.06);

    /* type: elastic with the same settings and seed: the same numbers */
    th_expect_type_elastic(1, "{lattice: diamond, element: Si, a_min: 5.2, a_max: 5.7, cells: 3}",
                           "{style: sw, file: Si.sw, elements: [Si]}",
                           "{temperature: 300, " SETTINGS "}", ma);

    /* the same values given as inputs: the same run */
    char thermal[256], elastic[256];
    snprintf(thermal, sizeof thermal, "lattice_constant: %.17g", a);
    snprintf(elastic, sizeof elastic, "elastic: {c11: %.17g, c12: %.17g, c44: %.17g}\n", c11, c12,
             c44);
    json_t *rx = th_run_case(2, "explicit.yaml", bar_text(thermal, elastic));
    json_t *mx = json_object_get(rx, "metrics");
    cr_expect_eq(th_metric_value(mx, "from_potential"), 0);
    const char *same[] = {"lattice_constant_T", "kleinman_zeta_mpm", "cl_mpm",
                          "temperature_md_mean", "temperature_region_II_mean", "bath_heat"};
    for (int k = 0; k < 6; k++) {
        double x = th_metric_value(mx, same[k]), y = th_metric_value(ma, same[k]);
        cr_expect_float_eq(x, y, 1e-9 * fabs(y) + 1e-12, "%s: explicit %.12g, computed %.12g",
                           same[k], x, y);
    }
    json_decref(ra);
    json_decref(rx);
}

Test(handshake_thermal_auto, refuses_given_values_beside_from_potential)
{
    const char *path = th_write_temp(3, "both.yaml",
                                     bar_text("lattice_constant: 5.43725, from_potential: {}", ""));
    const char *argv[] = {th_solver(), "check", path, NULL};
    char out[4096];
    cr_expect_neq(th_run(argv, out, sizeof out), 0);
    cr_expect(strstr(out, "thermal.lattice_constant") && strstr(out, "from_potential"), "%s", out);
}

/* Bad values in from_potential: `check` exits 2 naming file:line (the
 * thermal section is line 5 of bar_text) and the key. */
Test(handshake_thermal_auto, refuses_bad_from_potential_values, .timeout = 60)
{
    static const struct {
        const char *name, *from_potential, *key, *what;
    } bad[] = {
        {"nan.yaml", "from_potential: {tau: nan}", "thermal.from_potential.tau", "must be a number"},
        {"huge.yaml", "from_potential: {strain: 1e300}", "thermal.from_potential.strain",
         "must be in [1e-05, 0.05]"},
        {"negative.yaml", "from_potential: {cells: -3}", "thermal.from_potential.cells",
         "must be in [2, 20]"},
        {"short.yaml", "from_potential: {sample: 5}", "thermal.from_potential.sample",
         "must be >= 10"},
        {"duplicate.yaml", "from_potential: {cells: 3, cells: 4}", "'cells'", "duplicate key"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *path = th_write_temp(4, bad[k].name, bar_text(bad[k].from_potential, ""));
        const char *argv[] = {th_solver(), "check", path, NULL};
        char out[4096], where[96];
        snprintf(where, sizeof where, "%s:5:", bad[k].name);
        int st = th_run(argv, out, sizeof out);
        cr_expect_eq(st, 2, "%s: exit %d, output: %s", bad[k].name, st, out);
        cr_expect(strstr(out, where) && strstr(out, bad[k].key) && strstr(out, bad[k].what),
                  "%s: expected '%s', '%s', '%s' in: %s", bad[k].name, where, bad[k].key,
                  bad[k].what, out);
    }
}

/* cascade-solver info lists the keys of thermal.from_potential with their
 * defaults (type: elastic's), though the section is optional. */
Test(handshake_thermal_auto, info_lists_the_from_potential_keys, .timeout = 60)
{
    const char *argv[] = {th_solver(), "info", NULL};
    static char out[1 << 20];
    cr_assert_eq(th_run(argv, out, sizeof out), 0);
    json_error_t je;
    json_t *info = json_loads(out, 0, &je);
    cr_assert_not_null(info, "%s", je.text);
    json_t *fp = json_object_get(
        json_object_get(json_object_get(json_object_get(json_object_get(info, "keys"),
                                                        "case_types"),
                                        "handshake_thermal"),
                        "thermal"),
        "from_potential");
    cr_assert(json_is_object(fp), "no thermal.from_potential in the listing");
    cr_expect_eq(json_integer_value(json_object_get(fp, "cells")), 4);
    cr_expect_float_eq(json_real_value(json_object_get(fp, "strain")), 0.01, 1e-15);
    cr_expect_float_eq(json_real_value(json_object_get(fp, "timestep")), 0.002, 1e-15);
    cr_expect_eq(json_integer_value(json_object_get(fp, "sample")), 6000);
    cr_expect_eq(json_integer_value(json_object_get(fp, "lattice_iterations")), 3);
    cr_expect_null(json_object_get(fp, "temperature"), "the case's thermal.temperature");
    json_decref(info);
}
