/*
 * The DPD/MPM-grid and concurrent DPD/MPM case types through cascade-solver:
 * - bad input refused with file, line, column and key: a cell edge not
 *   smaller than the DPD cutoff, a missing parameter file, overlapping
 *   DPD and MPM ranges, a particle in neither range, a thermostat, a
 *   concurrent grid finer than the material points, an empty DPD range;
 * - a small flyer/target run, DPD-only and carried by grids of 8 and 2 Å:
 *   the grid's wave speed approaches the DPD-only one as the cells shrink,
 *   total momentum and DPDE energy are conserved;
 * - a small concurrent run: the wave crosses into the material points,
 *   momentum conserved, the reflection measured.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "core/sc_form.h"
#include "dpd/cg_lattice.h"
#include "helpers/th.h"

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

static int solver(const char *cmd, const char *yaml, char *out, size_t len, const char *outdir)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *path = th_write_temp(1, "case.yaml", yaml);
    const char *argv[] = {th_solver(), cmd, path, "--out", outdir, "--quiet", NULL};
    if (strcmp(cmd, "run") != 0)
        argv[3] = NULL;
    return th_run(argv, out, len);
}

/* The static zero-pressure lattice constant of PARAMS: a perfect crystal
 * there carries no force. */
static double lattice_a0(void)
{
    struct sc_params sc = {0.093945, 37.8271, 7.23, 9, 6, 10.845, 0, 0, 0, 0, 0, 0};
    sc_params_finish(&sc);
    double a0;
    cr_assert_eq(cg_lattice_solve_pressure(&sc, 0, 0, 0, 6.5, 8.0, &a0), 0);
    return a0;
}

/* A flyer/target case over a 12 x 3 x 3 cell bar at the static lattice
 * constant, periodic across (no surface relaxation) except for the
 * concurrent model; `grid` and `extra` are YAML appended as the grid
 * section and other sections. */
static void impact_case(char *buf, size_t len, const char *type, const char *grid,
                        const char *extra)
{
    /* the concurrent model's material points have free lateral faces: so
     * must its DPD part */
    const char *bc = strcmp(type, "dpd_mpm_impact") ? "periodic" : "free";
    snprintf(buf, len,
             "type: %s\nseed: 3\nsystem:\n"
             "  lattice: {style: fcc, a: %.8f, cells: [12, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, %s, %s]\n"
             "dpd:\n  parameters: cg.yaml\n  steps: 240\n"
             "impact:\n  regions: [25.0, 55.0]\n  sample_every: 1\n"
             "grid:\n%s%s",
             type, lattice_a0(), bc, bc, grid, extra);
}

static json_t *metrics(const char *dir)
{
    char path[600];
    snprintf(path, sizeof path, "%s/result.json", dir);
    json_t *r = json_load_file(path, 0, NULL);
    cr_assert(r, "no %s", path);
    return r;
}

static double metric(json_t *r, const char *name)
{
    json_t *m = json_object_get(json_object_get(json_object_get(r, "metrics"), name), "value");
    cr_assert(m, "metric %s missing", name);
    return json_number_value(m);
}

Test(dpd_mpm_cli, cell_not_smaller_than_cutoff_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_grid_impact", "  cell: 12.0\n", "");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:14:9: grid.cell: cell edge 12 Å is not smaller than the DPD "
                          "cutoff 10.845 Å"),
              "%s", out);
}

Test(dpd_mpm_cli, missing_parameter_file_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_grid_tensile", "  cell: 4.0\n", "");
    char *p = strstr(yaml, "cg.yaml");
    memcpy(p, "no.yaml", 7);
    char *imp = strstr(yaml, "impact:");
    snprintf(imp, (size_t)(yaml + sizeof yaml - imp), "grid: {cell: 4.0}\n");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:8:15: dpd.parameters: cannot read DPD parameter file "
                          "'no.yaml'"),
              "%s", out);
}

Test(dpd_mpm_cli, overlapping_dpd_and_mpm_ranges_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 40]\n  mpm: [35, 100]\n");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:17:8: concurrent.mpm: the MPM range [35, 100) overlaps the "
                          "DPD range [-10, 40)"),
              "%s", out);
}

Test(dpd_mpm_cli, particle_in_no_range_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 30]\n  mpm: [40, 100]\n");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:16:3: concurrent: particle") &&
                  strstr(out, "lies in neither concurrent.dpd [-10, 30) nor concurrent.mpm "
                              "[40, 100)"),
              "%s", out);
}

/* 2 Å cells hold 8 / 95 = 0.085 material points each: the points share no
 * grid node with their neighbours, and the run used to end "ok" with no
 * wave in the MPM part. */
Test(dpd_mpm_cli, concurrent_grid_finer_than_the_points_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 2.0\n",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:14:9: grid.cell: cell edge 2 Å gives 0.083") &&
                  strstr(out, "the concurrent model needs at least 0.5, i.e. a cell edge of "
                              "at least 3.64 Å"),
              "%s", out);
    /* 4 Å cells (0.67 points per cell) pass */
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n");
    rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 0, "%s", out);
}

/* No DPD particle in the target: used to pass check and fail in run with
 * "dpd_pair_heat needs the pair forces kept". */
Test(dpd_mpm_cli, concurrent_empty_dpd_range_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-30, -10]\n  mpm: [-10, 100]\n  monitor: -20\n");
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "case.yaml:16:8: concurrent.dpd: no particle of the target lies in "
                          "the DPD range [-30, -10)"),
              "%s", out);
}

Test(dpd_mpm_cli, thermostat_refused)
{
    char yaml[2048], out[4096];
    impact_case(yaml, sizeof yaml, "dpd_grid_impact", "  cell: 4.0\n", "");
    char *p = strstr(yaml, "  steps: 240\n");
    char rest[1024];
    snprintf(rest, sizeof rest, "%s", p + strlen("  steps: 240\n"));
    snprintf(p, (size_t)(yaml + sizeof yaml - p),
             "  steps: 240\n  thermostat: {style: berendsen, temperature: 298, tau: 1}\n%s", rest);
    int rc = solver("check", yaml, out, sizeof out, NULL);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert(strstr(out, "dpd.thermostat.style: the grid-carried models take no thermostat"),
              "%s", out);
}

/* Run a flyer/target case (type, grid section) into dir; returns result.json. */
static json_t *run_impact(const char *type, const char *grid, const char *name)
{
    char yaml[2048], out[8192], dir[512];
    snprintf(dir, sizeof dir, "%s/%s", th_temp_dir(), name);
    impact_case(yaml, sizeof yaml, type, grid, "output: {hdf5: false, thermo_every: 0}\n");
    char *p = strstr(yaml, "  steps: 240\n");
    char rest[1024];
    snprintf(rest, sizeof rest, "%s", p + strlen("  steps: 240\n"));
    snprintf(p, (size_t)(yaml + sizeof yaml - p), "  steps: 240\n  initial_temperature: 100\n%s",
             rest);
    if (!grid[0]) {   /* DPD-only: no grid section */
        char *g = strstr(yaml, "grid:\n");
        memmove(g, g + strlen("grid:\n"), strlen(g + strlen("grid:\n")) + 1);
    }
    int rc = solver("run", yaml, out, sizeof out, dir);
    cr_assert_eq(rc, 0, "%s", out);
    return metrics(dir);
}

/* The same impact, DPD-only and on grids of 8 and 2 Å: the grid-carried
 * wave speed approaches the DPD-only one as the cells shrink (fixed 0.01 Å
 * threshold: measured 4907, 5734, 4901 m/s; front fit 5337, 5750, 5355),
 * total momentum and DPDE energy are conserved,
 * and the grid's dissipation is accounted for as heat. */
Test(dpd_mpm_cli, grid_impact_approaches_dpd_only, .timeout = 600)
{
    json_t *r0 = run_impact("dpd_impact", "", "dpd-only");
    json_t *r8 = run_impact("dpd_grid_impact", "  cell: 8.0\n", "grid-8");
    json_t *r2 = run_impact("dpd_grid_impact", "  cell: 2.0\n", "grid-2");
    /* the fixed displacement threshold of the case (0.01 Å) */
    double v0 = metric(r0, "wave_speed_threshold"), v8 = metric(r8, "wave_speed_threshold"),
           v2 = metric(r2, "wave_speed_threshold");
    double f0 = metric(r0, "wave_speed_fit"), f8 = metric(r8, "wave_speed_fit"),
           f2 = metric(r2, "wave_speed_fit");
    cr_log_info("front fit: DPD-only %.0f, 8 Å %.0f, 2 Å %.0f m/s", f0, f8, f2);
    /* the threshold-free front fit approaches DPD-only too (measured 5337,
     * 5750, 5355 m/s: 2 Å within 0.4 %, 8 Å 7.7 % off) */
    cr_assert(fabs(f2 / f0 - 1) < 0.01, "front fit: 2 Å grid %g, DPD-only %g m/s", f2, f0);
    cr_assert(fabs(f8 - f0) > 3 * fabs(f2 - f0), "front fit: 8 Å %g, 2 Å %g, DPD-only %g", f8,
              f2, f0);
    cr_assert(v0 > 4000 && v0 < 6000, "DPD-only wave speed %g m/s", v0);
    cr_assert(fabs(v2 / v0 - 1) < 0.01, "2 Å grid: %g m/s, DPD-only %g m/s", v2, v0);
    cr_assert(fabs(v8 - v0) > 3 * fabs(v2 - v0), "8 Å grid %g, 2 Å grid %g, DPD-only %g m/s", v8,
              v2, v0);
    for (int k = 0; k < 3; k++) {
        /* the impact energy is the flyer's 1/2 M v^2 (5 Å/ps, particles of
         * 508.368 amu), the largest energy change is reported against it */
        json_t *r = k == 0 ? r0 : k == 1 ? r8 : r2;
        double ke = 0.5 * metric(r, "flyer_particles") * 508.368 * 25.0 * 1.0364269656262175e-4;
        cr_assert(fabs(metric(r, "impact_energy") / ke - 1) < 1e-12, "impact energy %.10g, "
                  "1/2 M v^2 %.10g eV", metric(r, "impact_energy"), ke);
        cr_assert(fabs(metric(r, "energy_error_impact_fraction") -
                       metric(r, "energy_deviation_max_abs") / ke) < 1e-12 * ke);
        cr_assert(metric(r, "energy_error_impact_fraction") < 0.01,
                  "energy excursion %g eV of an impact energy of %g eV",
                  metric(r, "energy_deviation_max_abs"), ke);
    }
    for (int k = 0; k < 2; k++) {
        json_t *r = k ? r8 : r2;
        cr_assert(metric(r, "momentum_change") < 1e-6, "momentum changed by %g",
                  metric(r, "momentum_change"));
        cr_assert(metric(r, "energy_deviation_max") < 1e-4, "energy deviation %g",
                  metric(r, "energy_deviation_max"));
        cr_assert(metric(r, "heat_grid") > 0, "the grid dissipated nothing");
    }
    json_decref(r0);
    json_decref(r2);
    json_decref(r8);
}

Test(dpd_mpm_cli, concurrent_impact_crosses_the_interface, .timeout = 300)
{
    char yaml[2048], out[8192], dir[512];
    snprintf(dir, sizeof dir, "%s/conc-impact", th_temp_dir());
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n"
                "output: {hdf5: false, thermo_every: 0}\n");
    int rc = solver("run", yaml, out, sizeof out, dir);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *r = metrics(dir);
    cr_assert(metric(r, "material_points") > 100);
    cr_assert(metric(r, "partners") > 50);
    /* the region beyond the interface (material points) moved as much as in
     * the all-DPD run, within 30 % */
    double tr = metric(r, "transmission_ratio");
    cr_assert(tr > 0.7 && tr < 1.3, "transmission ratio %g", tr);
    double rr = metric(r, "reflection_ratio");
    cr_assert(rr >= 0 && rr < 0.3, "reflection ratio %g", rr);
    cr_assert(metric(r, "momentum_change") < 1e-6, "momentum changed by %g",
              metric(r, "momentum_change"));
    /* the material points' state (cg_material_state.h): the zero-pressure
     * crystal at the target's temperature, here 0 K (no initial
     * temperature): the static lattice, C11 149.3 GPa (146.2 GPa at 298 K);
     * density and constants of the same lattice constant */
    cr_assert(metric(r, "material_temperature") < 1e-9, "T %g K",
              metric(r, "material_temperature"));
    cr_assert(fabs(metric(r, "c11") - 149.3) < 1.0, "C11 %g GPa", metric(r, "c11"));
    double a = metric(r, "material_lattice_constant");
    double rho = 4 * 508.368 / (a * a * a) * 1.6605390666;   /* g/cm^3 */
    cr_assert(fabs(metric(r, "density") / rho - 1) < 1e-9, "density %.10g, 4 m / a^3 %.10g",
              metric(r, "density"), rho);
    double cl = sqrt(metric(r, "c11") * 1e9 / (metric(r, "density") * 1e3));   /* m/s */
    /* the metal-unit constants round at 1e-8 */
    cr_assert(fabs(metric(r, "longitudinal_speed") / cl - 1) < 1e-6, "%.10g against %.10g",
              metric(r, "longitudinal_speed"), cl);
    json_t *src = json_object_get(json_object_get(json_object_get(r, "metrics"), "density"),
                                  "source");
    cr_assert(json_is_string(src) && strstr(json_string_value(src), "lattice: zero pressure"),
              "density source missing");
    /* the interface forces are conservative (partner embedding frozen):
     * total energy within 1 % of the impact energy, as the grid model */
    cr_assert(metric(r, "energy_error_impact_fraction") < 0.01,
              "energy excursion %g eV of an impact energy of %g eV",
              metric(r, "energy_deviation_max_abs"), metric(r, "impact_energy"));
    json_decref(r);
}

/* Open dataset `name` of fields.h5 in dir: its row count and unit. */
static long dataset_rows(hid_t f, const char *name, char unit[32])
{
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", name);
    hid_t sp = H5Dget_space(ds);
    hsize_t d[2] = {0, 0};
    H5Sget_simple_extent_dims(sp, d, NULL);
    H5Sclose(sp);
    hid_t a = H5Aopen(ds, "unit", H5P_DEFAULT);
    hid_t t = H5Aget_type(a);
    memset(unit, 0, 32);
    H5Aread(a, t, unit);
    H5Tclose(t);
    H5Aclose(a);
    H5Dclose(ds);
    return (long)d[0];
}

/* The concurrent model's snapshots hold its material points (collection
 * "points", one row per point, displacement zero at the start and not
 * after the run, stress in GPa) beside the DPD particles. */
Test(dpd_mpm_cli, concurrent_snapshots_hold_the_material_points, .timeout = 240)
{
    char yaml[2048], out[8192], dir[512];
    snprintf(dir, sizeof dir, "%s/conc-snap", th_temp_dir());
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n"
                "  compare: false\noutput: {thermo_every: 0, snapshot_every: 20}\n");
    char *p = strstr(yaml, "steps: 240");
    memcpy(p, "steps:  40", strlen("steps:  40"));
    int rc = solver("run", yaml, out, sizeof out, dir);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *r = metrics(dir);
    long np = (long)metric(r, "material_points");
    json_decref(r);
    char h5[600], unit[32];
    snprintf(h5, sizeof h5, "%s/fields.h5", dir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0, "no %s", h5);
    cr_assert_eq(dataset_rows(f, "/points/00000000/position", unit), np);
    cr_assert_str_eq(unit, "Å");
    cr_assert_eq(dataset_rows(f, "/points/00000040/stress", unit), np);
    cr_assert_str_eq(unit, "GPa");
    cr_assert(dataset_rows(f, "/particles/00000040/position", unit) > 0);
    double *u = malloc((size_t)3 * np * sizeof *u);
    double umax[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        hid_t ds = H5Dopen2(f, k ? "/points/00000040/displacement" : "/points/00000000/displacement",
                            H5P_DEFAULT);
        cr_assert(ds >= 0);
        H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u);
        H5Dclose(ds);
        for (long i = 0; i < 3 * np; i++)
            umax[k] = fmax(umax[k], fabs(u[i]));
    }
    free(u);
    H5Fclose(f);
    cr_assert(umax[0] == 0, "displacement %g Å at the start", umax[0]);
    cr_assert(umax[1] > 1e-4 && umax[1] < 1.0, "displacement %g Å after 0.2 ps", umax[1]);
}

/* Without a reference run the all-DPD comparison runs alone beside the
 * concurrent run (the run list has a gap where the reference was: it
 * crashed before the engine port). */
Test(dpd_mpm_cli, concurrent_compare_without_reference_runs, .timeout = 240)
{
    char yaml[2048], out[8192], dir[512];
    snprintf(dir, sizeof dir, "%s/conc-noref", th_temp_dir());
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "  cell: 4.0\n",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n"
                "output: {hdf5: false, thermo_every: 0}\n");
    char *p = strstr(yaml, "steps: 240");
    memcpy(p, "steps:  40", strlen("steps:  40"));
    p = strstr(yaml, "  sample_every: 1\n");
    char rest[2048];
    snprintf(rest, sizeof rest, "%s", p + strlen("  sample_every: 1\n"));
    snprintf(p, (size_t)(yaml + sizeof yaml - p), "  sample_every: 1\n  reference: false\n%s",
             rest);
    int rc = solver("run", yaml, out, sizeof out, dir);
    cr_assert_eq(rc, 0, "%s", out);
    json_t *r = metrics(dir);
    cr_assert(metric(r, "material_points") > 100);
    cr_assert(metric(r, "momentum_change") < 1e-6, "momentum changed by %g",
              metric(r, "momentum_change"));
    json_decref(r);
}

/* Common neighbour analysis of the DPD particles at the coarse lattice
 * constant (Chen 2014, Fig. 4): the 12 x 3 x 3 cell bar (432 particles),
 * periodic across, at 100 K is fcc except the (100) plane at its far free
 * end (18 particles, 8 neighbours each) -- at the impact face the flyer
 * continues the lattice -- in the DPD-only and the grid model alike; the
 * flyer is not counted; the classes are in the snapshots. */
Test(dpd_mpm_cli, cna_of_the_target, .timeout = 240)
{
    const char *types[2] = {"dpd_impact", "dpd_grid_impact"};
    for (int t = 0; t < 2; t++) {
        char yaml[2048], out[8192], dir[512];
        snprintf(dir, sizeof dir, "%s/cna-%d", th_temp_dir(), t);
        impact_case(yaml, sizeof yaml, types[t], t ? "  cell: 4.0\n" : "",
                    "output: {thermo_every: 0, snapshot_every: 20}\n");
        if (!t) {
            char *g = strstr(yaml, "grid:\n");
            memmove(g, g + strlen("grid:\n"), strlen(g + strlen("grid:\n")) + 1);
        }
        char *p = strstr(yaml, "  steps: 240\n");
        char rest[1024];
        snprintf(rest, sizeof rest, "%s", p + strlen("  steps: 240\n"));
        snprintf(p, (size_t)(yaml + sizeof yaml - p), "  steps: 40\n  initial_temperature: 100\n%s",
                 rest);
        int rc = solver("run", yaml, out, sizeof out, dir);
        cr_assert_eq(rc, 0, "%s", out);
        json_t *r = metrics(dir);
        cr_assert_eq(metric(r, "cna_fcc_start"), 432 - 18, "%s: fcc %g at the start",
                     types[t], metric(r, "cna_fcc_start"));
        cr_assert_eq(metric(r, "cna_hcp_start"), 0);
        cr_assert_eq(metric(r, "cna_fcc") + metric(r, "cna_hcp") + metric(r, "cna_other"), 432);
        cr_assert(fabs(metric(r, "cna_cutoff") - 0.5 * (1 + 1 / sqrt(2.0)) * 7.23) < 1e-9);
        json_decref(r);
        char h5[600], unit[32];
        snprintf(h5, sizeof h5, "%s/fields.h5", dir);
        hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
        cr_assert(f >= 0, "no %s", h5);
        long n = dataset_rows(f, "/particles/00000040/structure", unit);
        cr_assert(n >= 432, "%ld rows", n);
        H5Fclose(f);
    }
}
