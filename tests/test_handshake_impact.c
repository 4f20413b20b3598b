/*
 * The MPM/MD handshake as the boundary of a cluster-impact target
 * (`target.boundary: handshake`, Guo & Yang 2005, section 3.2, Fig. 12).
 *
 * - Layout: a 6 x 6 x 5 cell Cu target gets region I along its four sides
 *   and its bottom but not along its free top (672 of its 720 atoms), and
 *   MD copies of every lattice site of regions II and III (a 4-cell shell
 *   on five faces: (14 * 14 * 9 - 6 * 6 * 5) * 4 = 6336).
 * - A Cu14 cluster at 2 km/s against the same cluster at rest (the
 *   control: the target's free top relaxes in both, and the surface stress
 *   of region I's top atoms loads the MPM, which has no surface energy):
 *   the impact puts more than 3 % of its energy into the MPM within 0.6 ps
 *   (measured 6.4 %), and the coupled energy (MD atoms + MPM) changes by
 *   less than 10 % of the impact energy beyond the control's change
 *   (measured 5.8 %).
 * - Refused with file, line and key: a target not at the potential's
 *   lattice constant, a bcc target with cells of a/2, a region narrower than
 *   the cutoff.  (A target above 0 K is refused in test_impact.c.)
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"

static const char *impact_text(const char *target, double speed)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: cluster_impact\n"
             "seed: 1\n"
             "target:\n"
             "  lattice: fcc\n"
             "  element: Cu\n"
             "  cells: [6, 6, 5]\n"
             "  boundary: handshake\n"
             "  %s\n"
             "cluster: {atoms: 14, speed: %g}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {timestep: 0.002, steps: 300}\n"
             "analysis: {every: 100, structure: {method: fixed}}\n"
             "output: {thermo_every: 100, snapshot_every: 0, hdf5: false}\n",
             target, speed);
    return buf;
}

static double metric(json_t *m, const char *name)
{
    json_t *v = json_object_get(json_object_get(m, name), "value");
    cr_assert(json_is_number(v), "metric %s missing", name);
    return json_number_value(v);
}

static json_t *run_impact(int slot, double speed)
{
    char name[64], dir[1200];
    snprintf(name, sizeof name, "impact_%d.yaml", slot);
    const char *path = th_write_temp(
        slot, name,
        impact_text("a: 3.615\n  handshake: {mpm: 6, fine: 4, levels: 1, layer: 4}", speed));
    snprintf(dir, sizeof dir, "%s/impact-out-%d", th_temp_dir(), slot);
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    char out[8192];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char p[1400];
    snprintf(p, sizeof p, "%s/result.json", dir);
    json_t *r = json_load_file(p, 0, NULL);
    cr_assert_not_null(r);
    return r;
}

Test(handshake_impact, impact_energy_passes_into_the_mpm, .timeout = 240)
{
    json_t *r1 = run_impact(1, 2.0), *r0 = run_impact(2, 0.0);
    json_t *m1 = json_object_get(r1, "metrics"), *m0 = json_object_get(r0, "metrics");
    cr_expect_eq(metric(m1, "atoms_region_I"), 672);
    cr_expect_eq(metric(m1, "copies_region_II_III"), 6336);
    cr_expect_eq(metric(m1, "target_atoms"), 720);
    double eimp = metric(m1, "impact_energy") * 1e3;   /* keV -> eV */
    cr_assert_gt(eimp, 10);
    double mpm = metric(m1, "mpm_energy") - metric(m0, "mpm_energy");
    double d1 = metric(m1, "coupled_energy_final") - metric(m1, "coupled_energy_initial");
    double d0 = metric(m0, "coupled_energy_final") - metric(m0, "coupled_energy_initial");
    cr_log_info("impact %.3f eV: MPM gains %.3f eV over the control (%.1f %%); coupled energy "
                "change %.3f eV, control %.3f eV (difference %.1f %% of the impact)",
                eimp, mpm, 100 * mpm / eimp, d1, d0, 100 * (d1 - d0) / eimp);
    cr_expect_gt(mpm / eimp, 0.03, "MPM got %g of the impact energy", mpm / eimp);
    cr_expect_lt(fabs(d1 - d0) / eimp, 0.10, "coupled energy changed by %g of the impact energy",
                 (d1 - d0) / eimp);
    cr_expect_gt(metric(m1, "displaced_peak"), 0);
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

Test(handshake_impact, bad_targets_are_refused, .timeout = 60)
{
    expect_refused("hs_a.yaml", impact_text("a: 3.5", 2.0), "target.a",
                   "potential's 0 K lattice constant");
    expect_refused("hs_bcc.yaml",
                   "type: cluster_impact\n"
                   "target: {lattice: bcc, element: Fe, a: 2.8553, cells: [6, 6, 5], boundary: "
                   "handshake, handshake: {cell: 0.5}}\n"
                   "cluster: {atoms: 15}\n"
                   "potential: {style: eam/fs, file: Fe_mm.eam.fs, elements: [Fe]}\n",
                   "target.handshake.cell", "bcc crystal needs a finest cell of one lattice");
    expect_refused("hs_narrow.yaml",
                   impact_text("a: 3.615\n  handshake: {regions: [2, 1.5, 2]}", 2.0),
                   "target.handshake.regions", "narrower than the potential cutoff");
}
