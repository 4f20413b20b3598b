/*
 * Cluster impacts, Hugoniot and isotherm cases (solver/scenarios/).
 *
 *   - spherical cuts: fcc clusters of exactly 14, 128 and 1052 atoms and a
 *     diamond cluster of 260, each a sphere (no kept site farther than the
 *     nearest left out), 14 around the cube centre; an impossible count
 *     (33) is refused naming the nearest possible counts;
 *   - bad input refused with file:line and key: a cluster wider than the
 *     target's free top face, an impact speed that moves atoms more than
 *     0.1 nearest-neighbour distances per step, a fixed layer thinner than
 *     the cutoff, the handshake boundary at a temperature, a Hugoniot piston
 *     velocity too fast for the time step;
 *   - a short Cu14 impact through cascade-solver: the displaced-atom count
 *     rises from zero, the per-atom structure field is in the snapshots and
 *     counts over time are in result.json;
 *   - a small Cu Hugoniot at 2 km/s: Us within 5 % of the experimental line
 *     and the pressure behind the front within 3 % of rho0 Us up.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "analysis/damage_shape.h"
#include "scenarios/cluster_build.h"

static void check_cut(enum lattice_style st, double a, long n)
{
    struct cluster_cut c;
    struct err e = {0};
    cr_assert_eq(cluster_cut_sphere(st, a, n, NULL, &c, &e), 0, "%s", e.msg);
    cr_assert_eq(c.n, n);
    double rmax = 0;
    for (long k = 0; k < n; k++)
        rmax = fmax(rmax, sqrt(c.pos[k][0] * c.pos[k][0] + c.pos[k][1] * c.pos[k][1] +
                               c.pos[k][2] * c.pos[k][2]));
    cr_assert_float_eq(rmax, c.extent, 1e-9);
    cr_assert_gt(c.radius, c.extent, "cut radius %g not beyond the outermost site %g", c.radius,
                 c.extent);
    /* a sphere: the lattice has exactly n sites within the cut radius */
    struct lattice l = {st, a, {0, 0, 0}, {{0}}};
    double basis[8][3];
    int nb = lattice_basis(&l, basis);
    int m = (int)ceil(c.radius / a) + 1;
    long inside = 0;
    for (int i = -m; i <= m; i++)
        for (int j = -m; j <= m; j++)
            for (int q = -m; q <= m; q++)
                for (int bb = 0; bb < nb; bb++) {
                    double d[3] = {(i + basis[bb][0] - c.center[0]) * a,
                                   (j + basis[bb][1] - c.center[1]) * a,
                                   (q + basis[bb][2] - c.center[2]) * a};
                    inside += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) < c.radius;
                }
    cr_assert_eq(inside, n, "%ld sites inside the cut radius, cluster has %ld", inside, n);
    cluster_cut_free(&c);
}

Test(cluster, spherical_cuts_with_exact_counts)
{
    check_cut(LATTICE_FCC, 3.615, 14);
    check_cut(LATTICE_FCC, 3.615, 128);
    check_cut(LATTICE_FCC, 3.615, 1052);
    check_cut(LATTICE_DIAMOND, 5.431, 260);
    struct cluster_cut c;
    struct err e = {0};
    cr_assert_eq(cluster_cut_sphere(LATTICE_FCC, 3.615, 14, NULL, &c, &e), 0);
    cr_assert_float_eq(c.center[0], 0.5, 1e-12, "14 atoms: centre %g %g %g", c.center[0],
                       c.center[1], c.center[2]);
    double com[3] = {0, 0, 0};
    for (long k = 0; k < c.n; k++)
        for (int d = 0; d < 3; d++)
            com[d] += c.pos[k][d] / c.n;
    cr_assert_lt(fabs(com[0]) + fabs(com[1]) + fabs(com[2]), 1e-12, "octahedral cut is symmetric");
    cluster_cut_free(&c);
    cr_assert_eq(cluster_cut_sphere(LATTICE_FCC, 3.615, 33, NULL, &c, &e), ERR_INPUT);
    cr_assert(strstr(e.msg, "exactly 33 atoms") && strstr(e.msg, "nearest possible counts"), "%s",
              e.msg);
}

static const char *impact_case(const char *target, const char *cluster, const char *md)
{
    static char buf[2048];
    snprintf(buf, sizeof buf,
             "type: cluster_impact\n"
             "target: {lattice: fcc, element: Cu, a: 3.615, %s}\n"
             "cluster: {%s}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {%s}\n"
             "output: {hdf5: false}\n",
             target, cluster, md);
    return buf;
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

Test(impact, bad_input_is_refused, .timeout = 60)
{
    expect_refused("big_cluster.yaml",
                   impact_case("cells: [12, 12, 10]", "atoms: 1052", "steps: 10"), "cluster.atoms",
                   "wider than the free part of the target");
    expect_refused("fast.yaml",
                   impact_case("cells: [12, 12, 10], damped_thickness: 4", "atoms: 14, speed: 40",
                               "timestep: 0.001, steps: 10"),
                   "md.timestep", "more than 0.1 of the nearest-neighbour distance");
    expect_refused("thin.yaml",
                   impact_case("cells: [12, 12, 10], fixed_thickness: 3", "atoms: 14", "steps: 10"),
                   "target.fixed_thickness", "thinner than the potential cutoff");
    expect_refused("handshake.yaml",
                   impact_case("cells: [12, 12, 10], boundary: handshake, temperature: 300",
                               "atoms: 14", "steps: 10"),
                   "target.temperature", "runs at 0 K only");
    expect_refused("odd.yaml", impact_case("cells: [12, 12, 10]", "atoms: 33", "steps: 10"),
                   "cluster.atoms", "nearest possible counts");
    expect_refused("piston.yaml",
                   "type: hugoniot\n"
                   "hugoniot: {element: Cu, a: 3.615, cells: [30, 4, 4], particle_velocities: [1, 20]}\n"
                   "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                   "md: {timestep: 0.002}\n",
                   "md.timestep", "piston");
}

/* A dataset of doubles with ncols columns; *n its rows. */
static double *read_field(hid_t f, const char *name, int ncols, size_t *n)
{
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert(ds >= 0, "no dataset %s", name);
    hid_t sp = H5Dget_space(ds);
    hssize_t total = H5Sget_simple_extent_npoints(sp);
    double *v = malloc((size_t)total * sizeof *v);
    cr_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Sclose(sp);
    H5Dclose(ds);
    *n = (size_t)total / (size_t)ncols;
    return v;
}

static json_t *series(json_t *res, const char *name)
{
    json_t *s = json_object_get(json_object_get(json_object_get(res, "series"), name), "values");
    cr_assert(json_is_array(s), "no series %s", name);
    return s;
}

static double metric(json_t *res, const char *name)
{
    json_t *m = json_object_get(json_object_get(json_object_get(res, "metrics"), name), "value");
    cr_assert(json_is_number(m), "no metric %s", name);
    return json_number_value(m);
}

Test(impact, short_cu14_impact_records_damage, .timeout = 120)
{
    const char *text =
        "type: cluster_impact\n"
        "target: {lattice: fcc, element: Cu, a: 3.615, cells: [10, 10, 8], damped_thickness: 4}\n"
        "cluster: {atoms: 14, speed: 10}\n"
        "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
        "md: {timestep: 0.001, steps: 200}\n"
        "analysis: {every: 50}\n"
        "output: {thermo_every: 50, snapshot_every: 100}\n";
    const char *path = th_write_temp(1, "cu14.yaml", text);
    char outdir[512], out[8192];
    snprintf(outdir, sizeof outdir, "%s/cu14-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", outdir, "--quiet", "--threads", "2", NULL};
    int st = th_run(argv, out, sizeof out);
    cr_assert_eq(st, 0, "exit %d: %s", st, out);
    char rpath[600];
    snprintf(rpath, sizeof rpath, "%s/result.json", outdir);
    json_error_t je;
    json_t *res = json_load_file(rpath, 0, &je);
    cr_assert_not_null(res, "%s", je.text);
    json_t *disp = series(res, "displaced");
    cr_assert_eq(json_array_size(disp), 5, "analyses at 0, 50, 100, 150, 200");
    cr_assert_eq(json_number_value(json_array_get(disp, 0)), 0.0, "damage before the impact");
    cr_assert_gt(json_number_value(json_array_get(disp, 4)), 20.0, "no damage after 0.2 ps");
    cr_assert_eq(metric(res, "cluster_atoms"), 14.0);
    cr_assert_float_eq(metric(res, "impact_energy_per_atom"), 0.5 * 63.546 * 1e4 * 1.0364269656262175e-4,
                       1e-3);
    cr_assert_gt(metric(res, "displaced_peak"), 20.0);
    cr_assert_eq(json_array_size(series(res, "n_fcc")), 5);
    cr_assert_eq(json_array_size(series(res, "crater_depth_A")), 5);
    /* the damage shape: counted below the surface, so never more than the
     * displaced atoms; the metrics read the series */
    json_t *dam = series(res, "damage_atoms"), *ratio = series(res, "damage_eig_ratio");
    cr_assert_eq(json_array_size(dam), 5);
    for (int k = 0; k < 5; k++)
        cr_assert_leq(json_number_value(json_array_get(dam, k)),
                      json_number_value(json_array_get(disp, k)));
    cr_assert_gt(json_number_value(json_array_get(dam, 4)), 10.0);
    double r_last = json_number_value(json_array_get(ratio, 4));
    cr_assert(r_last > 0 && r_last <= 1, "eigenvalue ratio %g", r_last);
    cr_assert_float_eq(metric(res, "damage_eig_ratio_final"), r_last, 1e-12);
    double x_last = json_number_value(json_array_get(series(res, "damage_extent_ratio"), 4));
    cr_assert_float_eq(metric(res, "damage_extent_ratio_final"), x_last, 1e-12);
    cr_assert_geq(metric(res, "hcp_peak"), metric(res, "hcp_final"));
    cr_assert_geq(metric(res, "crater_volume_peak"), metric(res, "crater_volume"));
    json_decref(res);
    /* the per-atom fields are datasets of every snapshot, with the
     * classes of the last analysis */
    char h5[600];
    snprintf(h5, sizeof h5, "%s/fields.h5", outdir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    const char *snaps[3] = {"00000000", "00000100", "00000200"};
    const char *fields[4] = {"structure", "displaced", "sputtered", "crater"};
    for (int k = 0; k < 3; k++)
        for (int q = 0; q < 4; q++) {
            char name[128];
            snprintf(name, sizeof name, "/particles/%s/%s", snaps[k], fields[q]);
            cr_assert(H5Lexists(f, name, H5P_DEFAULT) > 0, "no dataset %s", name);
        }
    hid_t ds = H5Dopen2(f, "/particles/00000000/structure", H5P_DEFAULT);
    hid_t sp = H5Dget_space(ds);
    hsize_t dims[2];
    H5Sget_simple_extent_dims(sp, dims, NULL);
    double *cls = malloc(dims[0] * sizeof *cls);
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, cls);
    long nfcc = 0;
    for (hsize_t i = 0; i < dims[0]; i++)
        nfcc += cls[i] == 1.0;
    cr_assert_gt(nfcc, dims[0] / 4, "only %ld of %llu atoms fcc before the impact", nfcc,
                 (unsigned long long)dims[0]);
    free(cls);
    H5Sclose(sp);
    H5Dclose(ds);
    /* the last snapshot's displaced atoms below the surface (top layer at
     * 7.5 a, half a layer spacing a/4) give the series' last shape again */
    size_t n;
    double *pos = read_field(f, "/particles/00000200/position", 3, &n);
    double *dflag = read_field(f, "/particles/00000200/displaced", 1, &n);
    unsigned char *use = malloc(n);
    for (size_t i = 0; i < n; i++)
        use[i] = dflag[i] == 1.0 && pos[3 * i + 2] < 7.5 * 3.615 - 0.25 * 3.615;
    struct damage_shape dsh;
    struct err e = {0};
    cr_assert_eq(damage_shape_measure(pos, (int)n, use, NULL, &dsh, &e), 0);
    size_t ns;
    double *h5ratio = read_field(f, "/series/damage_eig_ratio", 1, &ns);
    cr_assert_eq(ns, 5);
    cr_assert_float_eq(h5ratio[4], r_last, 1e-12, "fields.h5 and result.json");
    cr_assert_float_eq(dsh.eig_ratio, r_last, 1e-9, "from the snapshot %g, series %g", dsh.eig_ratio,
                       r_last);
    free(h5ratio);
    free(pos);
    free(dflag);
    free(use);
    H5Fclose(f);
}

Test(hugoniot, small_copper_shock_at_2_km_s, .timeout = 240)
{
    const char *text =
        "type: hugoniot\n"
        "hugoniot: {element: Cu, a: 3.63, temperature: 300, zero_pressure: false, cells: [30, 4, 4],\n"
        "           particle_velocities: [2.0], equilibrate: 0.3, sample_every: 0.02, fit_start: 0.3}\n"
        "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
        "analysis: {structure: {method: adaptive}}\n"
        "output: {hdf5: false}\n";
    const char *path = th_write_temp(2, "hug.yaml", text);
    char outdir[512], out[8192];
    snprintf(outdir, sizeof outdir, "%s/hug-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", outdir, "--quiet", "--threads", "2", NULL};
    int st = th_run(argv, out, sizeof out);
    cr_assert_eq(st, 0, "exit %d: %s", st, out);
    char rpath[600];
    snprintf(rpath, sizeof rpath, "%s/result.json", outdir);
    json_error_t je;
    json_t *res = json_load_file(rpath, 0, &je);
    cr_assert_not_null(res, "%s", je.text);
    double us = metric(res, "us"), line = 3.94 + 1.49 * 2.0;
    cr_assert_lt(fabs(us / line - 1), 0.05, "Us %g km/s vs the experimental line %g", us, line);
    double dp = metric(res, "p_rh_deviation");
    cr_assert_lt(fabs(dp), 0.03, "Pxx deviates from rho0 Us up by %g", dp);
    double comp = metric(res, "compression"), comp_rh = metric(res, "compression_rh");
    cr_assert_lt(fabs(comp / comp_rh - 1), 0.02, "rho/rho0 %g vs Us/(Us-up) %g", comp, comp_rh);
    json_decref(res);
}
