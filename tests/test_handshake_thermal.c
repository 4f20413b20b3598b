/*
 * The MPM/MD handshake at a finite temperature (couple/handshake_thermal.h,
 * docs/handshake.md "At a temperature").
 *
 * - A 300 K MD region (12 lattice constants of a 28-long bar, 768 atoms)
 *   in MPM on the lattice at a(300 K) with the constants at 300 K, region
 *   II under the Langevin bath: after 1 ps with a thermostat on all atoms,
 *   2 ps without one.  The MD region's mean temperature stays within 3 %
 *   of 300 K and every 0.5 ps block within 6 % (the quick size: 768 atoms
 *   fluctuate by sqrt(2 / 3N) = 3 % per sample; the 20 ps run of the study
 *   holds 2 %), and the bath holds region II within 5 % of 300 K.
 * - The cluster-impact boundary with the bath at 0 K (pure friction on
 *   region II's motion relative to its material points and on the band's
 *   points' motion relative to the coarse field, couple/handshake_thermal.h):
 *   beyond the control (the cluster at rest), the energy account -- MD
 *   atoms, MPM, region II's fine-scale energy and the bath's heat --
 *   changes by less than 4 % of the impact energy (measured -0.19 %;
 *   without the bath the same target loses 5.8 % of it,
 *   test_handshake_impact.c; with the earlier friction on the points'
 *   whole velocity, coarse_cell 0, it gained 1.6 %), the bath takes out
 *   more than 2 % of it beyond the control's (measured 7.0 %; coarse_cell
 *   0: 10.2 %), and the MPM receives more than 4.5 % of it beyond the
 *   control's (measured 5.8 %; coarse_cell 0: 3.3 %, no bath 6.4 %).
 * - Refused with file, line and key: a thermal bar without a(T) or
 *   without the elastic constants at T, a hot impact target without them.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_case.h"

static const char *bar_text(const char *thermal, const char *elastic)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: handshake_thermal\n"
             "seed: 3\n"
             "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "%s"
             "thermal: %s\n"
             "handshake: {levels: 0}\n"
             "bar: {mpm: [8, 8], md: 12, width: 4}\n"
             "md: {timestep: 0.002, steps: 1000}\n"
             "output: {thermo_every: 100, snapshot_every: 0, hdf5: false}\n",
             elastic, thermal);
    return buf;
}

static const char *const elastic_300K = "elastic: {c11: 164.20, c12: 119.25, c44: 68.27}\n";

Test(handshake_thermal, md_region_keeps_its_temperature, .timeout = 180)
{
    json_t *r = th_run_case(1, "thermal_bar.yaml",
                         bar_text("{temperature: 300, lattice_constant: 3.63176, damping_time: "
                                  "0.1, equilibrate: 1, block: 0.5}",
                                  elastic_300K));
    json_t *m = json_object_get(r, "metrics");
    cr_expect_eq(th_metric_value(m, "atoms"), 768);
    cr_expect_eq(th_metric_value(m, "temperature_blocks"), 4);
    double mean = th_metric_value(m, "temperature_md_mean");
    double dev = th_metric_value(m, "temperature_max_deviation");
    double t2 = th_metric_value(m, "temperature_region_II_mean");
    cr_log_info("300 K bar: MD mean %.1f K, largest block deviation %.3f, region II %.1f K, "
                "bath heat %.3f eV",
                mean, dev, t2, th_metric_value(m, "bath_heat"));
    cr_expect_lt(fabs(mean / 300 - 1), 0.03, "MD region at %g K", mean);
    cr_expect_lt(dev, 0.06, "a block deviates by %g", dev);
    cr_expect_lt(fabs(t2 / 300 - 1), 0.05, "region II at %g K", t2);
    /* the MPM stands on the lattice at a(T) with the constants at T */
    cr_expect_float_eq(th_metric_value(m, "lattice_constant"), 3.63176, 1e-9);
    cr_expect_float_eq(th_metric_value(m, "c11_mpm"), 164.20, 1e-6);
    json_decref(r);
}

static const char *impact_text(const char *handshake, double speed)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: cluster_impact\n"
             "seed: 1\n"
             "target:\n"
             "  lattice: fcc\n"
             "  element: Cu\n"
             "  a: 3.615\n"
             "  cells: [6, 6, 5]\n"
             "  boundary: handshake\n"
             "  handshake: {mpm: 6, fine: 4, levels: 1, layer: 4%s}\n"
             "cluster: {atoms: 14, speed: %g}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {timestep: 0.002, steps: 300}\n"
             "analysis: {every: 100, structure: {method: fixed}}\n"
             "output: {thermo_every: 100, snapshot_every: 0, hdf5: false}\n",
             handshake, speed);
    return buf;
}

Test(handshake_thermal, bath_reduces_the_impact_loss, .timeout = 240)
{
    const char *bath = ", thermal: {damping_time: 0.1}";
    json_t *r1 = th_run_case(2, "thermal_imp.yaml", impact_text(bath, 2.0));
    json_t *r0 = th_run_case(3, "thermal_ctl.yaml", impact_text(bath, 0.0));
    json_t *m1 = json_object_get(r1, "metrics"), *m0 = json_object_get(r0, "metrics");
    double eimp = th_metric_value(m1, "impact_energy") * 1e3;   /* keV -> eV */
    double d1 = th_metric_value(m1, "energy_account_final") - th_metric_value(m1, "energy_account_initial");
    double d0 = th_metric_value(m0, "energy_account_final") - th_metric_value(m0, "energy_account_initial");
    double loss = -(d1 - d0) / eimp;
    cr_log_info("impact %.3f eV: account change %.3f eV, control %.3f eV: loss %.2f %%, bath "
                "heat %.3f eV",
                eimp, d1, d0, 100 * loss, th_metric_value(m1, "bath_heat"));
    cr_expect_gt(eimp, 10);
    cr_expect_lt(fabs(loss), 0.04, "the account lost %g of the impact energy", loss);
    cr_expect_gt(th_metric_value(m1, "bath_heat") - th_metric_value(m0, "bath_heat"), 0.02 * eimp,
                 "the bath took %g eV", th_metric_value(m1, "bath_heat"));
    double mpm = (th_metric_value(m1, "mpm_energy") - th_metric_value(m0, "mpm_energy")) / eimp;
    cr_log_info("MPM beyond the control: %.2f %% of the impact", 100 * mpm);
    cr_expect_gt(mpm, 0.045, "the MPM received %g of the impact energy", mpm);
    json_decref(r1);
    json_decref(r0);
}

static void expect_refused(const char *name, const char *text, const char *key, const char *what)
{
    const char *path = th_write_temp(0, name, text);
    const char *argv[] = {th_solver(), "check", path, NULL};
    char out[4096];
    int st = th_run(argv, out, sizeof out);
    cr_assert_eq(st, 2, "exit %d, output: %s", st, out);
    cr_assert(strstr(out, name), "no file name in: %s", out);
    cr_assert(strstr(out, key), "no key '%s' in: %s", key, out);
    cr_assert(strstr(out, what), "no '%s' in: %s", what, out);
}

Test(handshake_thermal, missing_constants_at_temperature_are_refused, .timeout = 60)
{
    expect_refused("thermal_no_a.yaml", bar_text("{temperature: 300}", elastic_300K),
                   "thermal.lattice_constant", "lattice constant at 300 K");
    expect_refused("thermal_no_c.yaml",
                   bar_text("{temperature: 300, lattice_constant: 3.63176}", ""), "elastic",
                   "elastic constants at the MD temperature");
    expect_refused("thermal_imp_no_c.yaml",
                   "type: cluster_impact\n"
                   "target: {lattice: fcc, element: Cu, a: 3.63176, cells: [6, 6, 5], "
                   "temperature: 300, boundary: handshake, handshake: {mpm: 6, fine: 4, levels: "
                   "1, layer: 4, thermal: {}}}\n"
                   "cluster: {atoms: 14}\n"
                   "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n",
                   "target.handshake.elastic", "elastic constants at that temperature");
}
