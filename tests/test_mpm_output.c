/*
 * Output of an MPM run in the case's units: result.json metrics with units,
 * thermo.csv columns, HDF5 material-point fields (a point cloud) and grid
 * fields (a structured (nz, ny, nx) grid on a uniform grid, a point cloud of
 * the nodes on a hierarchical one), all referenced by the XDMF sidecar so
 * ParaView opens both; times in the case's time unit.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"

static void run_case(const char *name, const char *yaml, char *dir, size_t len)
{
    const char *path = th_write_temp(3, name, yaml);
    snprintf(dir, len, "%s/%s-out", th_temp_dir(), name);
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    char out[8192];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
}

static char *slurp(const char *dir, const char *name)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s missing", path);
    static char buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    return buf;
}

static void dims_of(hid_t f, const char *ds_name, int *rank, hsize_t dims[4], char *unit)
{
    hid_t ds = H5Dopen2(f, ds_name, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", ds_name);
    hid_t sp = H5Dget_space(ds);
    *rank = H5Sget_simple_extent_dims(sp, dims, NULL);
    H5Sclose(sp);
    hid_t a = H5Aopen(ds, "unit", H5P_DEFAULT);
    hid_t t = H5Aget_type(a);
    H5Aread(a, t, unit);
    H5Tclose(t);
    H5Aclose(a);
    H5Dclose(ds);
}

Test(mpm_output, si_case_writes_points_grid_and_xdmf)
{
    char dir[1024];
    run_case("two.yaml",
             "type: mpm\nmpm:\n  units: si\n  grid: {cell: 0.1, cells: [8, 4, 3]}\n"
             "  materials: [{name: al, law: linear_elastic, density: 2700, E: 70.0e9, nu: 0.3}]\n"
             "  bodies:\n"
             "    - {name: A, material: al, region: {shape: box, lo: [0.1, 0.1, 0.1], hi: [0.3, "
             "0.3, 0.2]}, velocity: [20, 0, 0]}\n"
             "  steps: 10\noutput: {thermo_every: 5, snapshot_every: 5}\n",
             dir, sizeof dir);
    /* result.json: SI units */
    char rpath[1100];
    snprintf(rpath, sizeof rpath, "%s/result.json", dir);
    json_t *r = json_load_file(rpath, 0, NULL);
    cr_assert_not_null(r);
    json_t *ke = json_object_get(json_object_get(r, "metrics"), "ke");
    cr_assert_str_eq(json_string_value(json_object_get(ke, "unit")), "J");
    /* 32 points of 1.25e-4 m^3 x 2700 kg/m^3 at 20 m/s */
    double ke0 = 0.5 * 32 * 1.25e-4 * 2700 * 400;
    cr_assert(fabs(json_real_value(json_object_get(ke, "value")) - ke0) < 1e-9 * ke0);
    json_t *ts = json_object_get(json_object_get(r, "metrics"), "timestep");
    cr_assert_str_eq(json_string_value(json_object_get(ts, "unit")), "s");
    cr_assert_eq(json_integer_value(json_object_get(r, "steps")), 10);
    json_decref(r);
    cr_assert(strstr(slurp(dir, "thermo.csv"), "step,time_s,dt_s,ke_J,strain_energy_J,etotal_J"));
    /* HDF5 */
    char h5[1100];
    snprintf(h5, sizeof h5, "%s/fields.h5", dir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    int rank;
    hsize_t d[4];
    char unit[32] = "";
    dims_of(f, "/points/00000005/position", &rank, d, unit);
    cr_assert(rank == 2 && d[0] == 32 && d[1] == 3 && strcmp(unit, "m") == 0);
    dims_of(f, "/points/00000010/stress", &rank, d, unit);
    cr_assert(rank == 2 && d[1] == 6 && strcmp(unit, "Pa") == 0, "stress unit %s", unit);
    dims_of(f, "/points/00000010/strain", &rank, d, unit);
    cr_assert(rank == 2 && d[1] == 6 && strcmp(unit, "1") == 0);
    dims_of(f, "/points/00000010/deformation_gradient", &rank, d, unit);
    cr_assert(rank == 2 && d[1] == 9);
    dims_of(f, "/grid/00000010/velocity", &rank, d, unit);
    cr_assert(rank == 4 && d[0] == 4 && d[1] == 5 && d[2] == 9 && d[3] == 3, "grid dims");
    cr_assert_str_eq(unit, "m/s");
    dims_of(f, "/grid/00000000/mass", &rank, d, unit);
    cr_assert(rank == 3 && strcmp(unit, "kg") == 0);
    /* the initial grid snapshot holds the mapped mass: the body's 10.8 kg */
    double mass[4 * 5 * 9], total = 0;
    hid_t ds = H5Dopen2(f, "/grid/00000000/mass", H5P_DEFAULT);
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, mass);
    H5Dclose(ds);
    for (int k = 0; k < 4 * 5 * 9; k++)
        total += mass[k];
    cr_assert(fabs(total - 32 * 1.25e-4 * 2700) < 1e-12, "grid mass %g kg", total);
    hid_t g = H5Gopen2(f, "/points/00000005", H5P_DEFAULT);
    cr_assert(H5Aexists(g, "time_s") > 0, "snapshot time not in seconds");
    H5Gclose(g);
    H5Fclose(f);
    /* XDMF: both collections */
    const char *x = slurp(dir, "fields.xdmf");
    cr_assert(strstr(x, "<Grid Name=\"points\" GridType=\"Collection\""), "%s", x);
    cr_assert(strstr(x, "<Grid Name=\"grid\" GridType=\"Collection\""));
    cr_assert(strstr(x, "TopologyType=\"3DCoRectMesh\" Dimensions=\"4 5 9\""));
    cr_assert(strstr(x, "ORIGIN_DXDYDZ") && strstr(x, "0.10000000000000001 0.10000000000000001"));
    cr_assert(strstr(x, "Polyvertex"));
    cr_assert(strstr(x, "Name=\"velocity [m/s]\" AttributeType=\"Vector\""));
}

Test(mpm_output, hierarchical_grid_nodes_as_points)
{
    char dir[1024];
    run_case("hier.yaml",
             "type: mpm\nmpm:\n  grid:\n    cell: 2.0\n    cells: [16, 4, 4]\n"
             "    levels: [{coarsen: xyz, region: {shape: slab, axis: x, lo: 16, hi: 100}}]\n"
             "  materials: [{name: cu, law: cubic_elastic, density: 8.96, C11: 170, C12: 122, "
             "C44: 75}]\n"
             "  bodies: [{name: A, material: cu, region: {shape: box, lo: [0, 0, 0], hi: [32, 8, "
             "8]}}]\n"
             "  loads: [{region: {shape: box, lo: [0, 0, 0], hi: [1, 8, 8]}, normal: x, "
             "traction: [1.0, 0, 0]}]\n"
             "  probes: [{name: mid, region: {shape: box, lo: [8, 0, 0], hi: [12, 8, 8]}}]\n"
             "  steps: 20\noutput: {snapshot_every: 10}\n",
             dir, sizeof dir);
    char h5[1100];
    snprintf(h5, sizeof h5, "%s/fields.h5", dir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    int rank;
    hsize_t d[4];
    char unit[32] = "";
    dims_of(f, "/grid/00000020/position", &rank, d, unit);
    cr_assert(rank == 2 && d[1] == 3 && strcmp(unit, "Å") == 0);
    H5Fclose(f);
    const char *x = slurp(dir, "fields.xdmf");
    cr_assert(!strstr(x, "3DCoRectMesh"), "hierarchical nodes are not a structured grid");
    /* the probe and the load are in result.json: compression arrived at x ~ 10 Å */
    char rpath[1100];
    snprintf(rpath, sizeof rpath, "%s/result.json", dir);
    json_t *r = json_load_file(rpath, 0, NULL);
    json_t *mid = json_object_get(json_object_get(r, "metrics"), "mid_sxx");
    cr_assert_str_eq(json_string_value(json_object_get(mid, "unit")), "GPa");
    double s = json_real_value(json_object_get(mid, "value"));
    cr_assert(s < -0.1 && s > -3.0, "mid-bar stress %g GPa (1 GPa load)", s);
    json_decref(r);
}

/* A closed system whose total energy moves beyond mpm.max_energy_change
 * has diverged (the engine's check on the mpm model's observe): status,
 * the step, the change and the limit in per cent of the initial energy,
 * and the metrics of the steps done. */
Test(mpm_output, energy_divergence_is_recorded)
{
    const char *path = th_write_temp(3, "div.yaml",
                                     "type: mpm\nmpm:\n  grid: {cell: 4.0, cells: [24, 6, 6]}\n"
                                     "  materials: [{name: al, law: linear_elastic, density: 2.7, "
                                     "E: 70, nu: 0.3}]\n"
                                     "  bodies:\n"
                                     "    - {name: A, material: al, velocity: [5, 0, 0], region: "
                                     "{shape: box, lo: [8, 4, 4], hi: [40, 20, 20]}}\n"
                                     "    - {name: B, material: al, velocity: [-5, 0, 0], region: "
                                     "{shape: box, lo: [44, 4, 4], hi: [80, 20, 20]}}\n"
                                     "  cfl: 0.9\n  max_energy_change: 0.001\n  steps: 200\n"
                                     "output: {hdf5: false}\n");
    char dir[1024], out[8192];
    snprintf(dir, sizeof dir, "%s/div-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    cr_assert_eq(th_run(argv, out, sizeof out), 4, "%s", out);
    char rpath[1100];
    snprintf(rpath, sizeof rpath, "%s/result.json", dir);
    json_t *r = json_load_file(rpath, 0, NULL);
    cr_assert_not_null(r);
    cr_assert_str_eq(json_string_value(json_object_get(r, "status")), "diverged");
    const char *msg = json_string_value(json_object_get(r, "message"));
    cr_assert(strstr(msg, "total energy changed by ") && strstr(msg, " % at step ") &&
                  strstr(msg, "(limit mpm.max_energy_change = 0.1 %)"),
              "%s", msg);
    json_t *sd = json_object_get(json_object_get(r, "metrics"), "steps_done");
    double steps = json_real_value(json_object_get(sd, "value"));
    cr_assert(steps >= 1 && steps < 200, "stopped at step %g", steps);
    json_t *de = json_object_get(json_object_get(r, "metrics"), "energy_change_max");
    cr_assert_gt(json_real_value(json_object_get(de, "value")), 0.001,
                 "the step that diverged is in energy_change_max");
    json_decref(r);
}
