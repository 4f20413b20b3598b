/*
 * Contact in one velocity field and free motion:
 *
 * - Two identical elastic cubes (a coarse version of the reference problem,
 *   SI case file through cascade-solver): they collide and separate, total
 *   momentum is conserved to round-off, the energy stays bounded (no
 *   growth beyond the coarse grid's few per cent), and after the impact each
 *   cube moves back with most of its speed.
 * - A body translating freely across many cells develops no stress (to
 *   round-off), keeps its velocity, moves by v t, and its mass is exactly
 *   conserved and mapped exactly to the grid.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_mpm.h"

static const char *coarse_cubes =
    "type: mpm\n"
    "mpm:\n"
    "  units: si\n"
    "  grid: {cell: 0.05, cells: [13, 7, 7]}\n"
    "  materials:\n"
    "    - {name: al, law: linear_elastic, density: 2700, E: 70.0e9, nu: 0.3}\n"
    "  bodies:\n"
    "    - {name: A, material: al, region: {shape: box, lo: [0.05, 0.05, 0.05], hi: [0.30, "
    "0.30, 0.30]}, velocity: [50, 0, 0]}\n"
    "    - {name: B, material: al, region: {shape: box, lo: [0.35, 0.05, 0.05], hi: [0.60, "
    "0.30, 0.30]}, velocity: [-50, 0, 0]}\n"
    "  steps: 200\n"
    "  report_steps: [40, 80, 200]\n"
    "output: {thermo_every: 0, hdf5: false}\n";

static double metric(json_t *r, const char *name, const char *unit)
{
    json_t *m = json_object_get(json_object_get(r, "metrics"), name);
    cr_assert_not_null(m, "metric %s missing", name);
    cr_assert_str_eq(json_string_value(json_object_get(m, "unit")), unit, "unit of %s", name);
    return json_real_value(json_object_get(m, "value"));
}

Test(mpm_impact, two_cubes_collide_and_separate)
{
    const char *path = th_write_temp(0, "cubes.yaml", coarse_cubes);
    char out[1024], log[8192];
    snprintf(out, sizeof out, "%s/cubes-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", out, "--quiet", NULL};
    cr_assert_eq(th_run(argv, log, sizeof log), 0, "%s", log);
    char rpath[1100];
    snprintf(rpath, sizeof rpath, "%s/result.json", out);
    json_t *r = json_load_file(rpath, 0, NULL);
    cr_assert_not_null(r);
    double ke0 = metric(r, "ke_initial", "J");
    /* 1/2 (2 x 2700 kg/m^3 x 0.25^3 m^3) (50 m/s)^2 */
    cr_assert(fabs(ke0 - 105468.75) < 1e-6 * ke0, "initial kinetic energy %g J", ke0);
    cr_assert(fabs(metric(r, "ke_step_40", "J") - ke0) < 1e-9 * ke0, "touched before step 40");
    double ke80 = metric(r, "ke_step_80", "J");
    cr_assert(ke80 < 0.7 * ke0, "no impact by step 80 (ke %g J)", ke80);
    /* total momentum (zero) conserved to round-off relative to sum m|v| */
    cr_assert(metric(r, "momentum_change", "1") < 1e-13, "momentum not conserved");
    /* bounded energy: the time-centred energy changes by ~5 % on this
     * 5-cell cube; a scheme that pumps energy would exceed it */
    double dec = metric(r, "energy_change_centred_max", "1");
    cr_assert(dec < 0.08, "time-centred energy changed by %.3g", dec);
    cr_assert(metric(r, "energy_change_max", "1") < 0.15);
    /* separated: the cubes move apart, each with most of its speed */
    double va = metric(r, "A_velocity_x", "m/s"), vb = metric(r, "B_velocity_x", "m/s");
    cr_assert(va < -30 && vb > 30, "cubes did not rebound: %g, %g m/s", va, vb);
    cr_assert(fabs(va + vb) < 1e-9, "asymmetric rebound %g vs %g m/s", va, vb);
    cr_assert(va > -52, "rebound faster than the impact: %g m/s", va);
    json_decref(r);
}

Test(mpm_impact, free_translation_has_no_spurious_stress_and_exact_mass)
{
    struct mpm m;
    long nc[3] = {24, 12, 12};
    th_mpm_uniform(&m, nc, 2.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", 5.0, 1.0, 0.3));
    double lo[3] = {2, 4, 6}, hi[3] = {10, 12, 14};
    /* not commensurate with the cells: points cross faces at many phases */
    double v[3] = {2.3, 1.1, 0.7};   /* Å/ps; c ~ 50 Å/ps */
    th_mpm_box(&m, "block", mat, lo, hi, 2, v, 0);
    long n = m.pts.n;
    double mass0 = 0;
    for (long p = 0; p < n; p++)
        mass0 += m.pts.mass[p];
    struct err e = {0};
    double t = 0;
    for (int s = 0; s < 400; s++) {
        double dt = 0.5 * mpm_stable_dt(&m);
        cr_assert_eq(mpm_step(&m, dt, &e), 0, "%s", e.msg);
        t += dt;
    }
    /* moved about 17 x 8 x 5 Å: several cells in each direction */
    cr_assert(v[0] * t > 6 * 2.0, "moved only %g Å", v[0] * t);
    double smax = 0, dv = 0, dx = 0, mass = 0;
    for (long p = 0; p < n; p++) {
        for (int k = 0; k < 6; k++)
            smax = fmax(smax, fabs(m.pts.stress[6 * p + k]));
        for (int d = 0; d < 3; d++) {
            dv = fmax(dv, fabs(m.pts.v[3 * p + d] - v[d]));
            dx = fmax(dx, fabs(m.pts.x[3 * p + d] - m.pts.x0[3 * p + d] - v[d] * t));
        }
        mass += m.pts.mass[p];
    }
    /* scale: rho c v ~ 5 x 50 x 1 amu/Å^3 Å/ps ~ 2.5e-2 eV/Å^3 for an impact */
    cr_assert(smax < 1e-12, "spurious stress %g eV/Å^3", smax);
    cr_assert(dv < 1e-12, "velocity changed by %g Å/ps", dv);
    cr_assert(dx < 1e-9, "position off by %g Å", dx);
    cr_assert(mass == mass0, "point mass changed: %.17g -> %.17g", mass0, mass);
    cr_assert(fabs(mpm_grid_mass(&m) - mass) < 1e-13 * mass, "grid mass %.17g vs %.17g",
              mpm_grid_mass(&m), mass);
    mpm_free(&m);
}
