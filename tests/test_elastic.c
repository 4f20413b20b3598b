/*
 * Elastic constants at a temperature (type: elastic, finite-strain
 * averages of Langevin MD).  At 0 K the thermostat only damps, the runs
 * relax to the static strained crystals and the constants must equal the
 * 0 K ones of type crystal (Mishin Cu: 169.9, 122.6, 76.2 GPa) within the
 * finite-strain error; at 300 K the crystal must expand (Mishin Cu about
 * 0.5 %) and soften, C44 most.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>

#include "helpers/th.h"

static json_t *run_elastic(const char *name, int cells, const char *elastic)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "type: elastic\n"
             "crystal: {lattice: fcc, element: Cu, a_min: 3.5, a_max: 3.7, cells: %d}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "elastic: %s\n",
             cells, elastic);
    const char *path = th_write_temp(4, name, yaml);
    char dir[1200];
    snprintf(dir, sizeof dir, "%s/%s-out", th_temp_dir(), name);
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    char out[8192];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char rp[1300];
    snprintf(rp, sizeof rp, "%s/result.json", dir);
    json_t *r = json_load_file(rp, 0, NULL);
    cr_assert_not_null(r);
    return r;
}

static double metric(json_t *r, const char *name)
{
    json_t *m = json_object_get(json_object_get(json_object_get(r, "metrics"), name), "value");
    cr_assert_not_null(m, "metric %s missing", name);
    return json_real_value(m);
}

Test(elastic, zero_kelvin_matches_static_constants, .timeout = 120)
{
    json_t *r = run_elastic("e0.yaml", 3, "{temperature: 0, strain: 0.002, timestep: 0.002, tau: "
                                       "0.05, equilibrate: 400, sample: 50}");
    const char *names[3] = {"c11", "c12", "c44"};
    for (int k = 0; k < 3; k++) {
        char ref[16];
        snprintf(ref, sizeof ref, "%s_0K", names[k]);
        double v = metric(r, names[k]), v0 = metric(r, ref);
        cr_expect_lt(fabs(v / v0 - 1), 0.005, "%s = %.3f GPa, static %.3f GPa", names[k], v, v0);
    }
    cr_expect_lt(fabs(metric(r, "c11_0K") / 169.9 - 1), 0.01);
    json_decref(r);
}

Test(elastic, room_temperature_expands_and_softens, .timeout = 240)
{
    json_t *r = run_elastic("e300.yaml", 4, "{temperature: 300, strain: 0.01, timestep: 0.002, tau: "
                                         "0.5, equilibrate: 1000, sample: 3000, "
                                         "lattice_iterations: 2}");
    double expand = metric(r, "thermal_expansion");
    double c44 = metric(r, "c44"), c44e = metric(r, "c44_err"), c440 = metric(r, "c44_0K");
    double c11 = metric(r, "c11"), c11e = metric(r, "c11_err"), c110 = metric(r, "c11_0K");
    cr_log_info("300 K: expansion %.4f, C11 %.1f +- %.1f (0 K %.1f), C44 %.1f +- %.1f (0 K %.1f)",
                expand, c11, c11e, c110, c44, c44e, c440);
    cr_expect(expand > 0.002 && expand < 0.008, "thermal expansion %g", expand);
    cr_expect_lt(c44, c440 - 2.0, "C44 %g GPa, 0 K %g GPa", c44, c440);
    cr_expect_lt(c11, c110 + 2 * c11e, "C11 %g +- %g GPa, 0 K %g GPa", c11, c11e, c110);
    cr_expect_lt(c44e, 3.0, "C44 error %g GPa", c44e);
    json_decref(r);
}
