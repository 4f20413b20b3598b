/*
 * Output of a run: result.json metrics with units, HDF5 datasets with unit
 * attributes and the XDMF sidecar, extended XYZ that reads back, and the
 * "diverged" status with its exit code.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <string.h>

#include "helpers/th.h"
#include "input/config_read.h"

static json_t *run_case(const char *name, const char *yaml, int expect_rc, char *outdir, size_t len)
{
    const char *path = th_write_temp(5, name, yaml);
    snprintf(outdir, len, "%s/%s-out", th_temp_dir(), name);
    const char *argv[] = {th_solver(), "run", path, "--out", outdir, "--quiet", NULL};
    char out[8192];
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, expect_rc, "exit %d: %s", rc, out);
    char rpath[1024];
    snprintf(rpath, sizeof rpath, "%s/result.json", outdir);
    json_error_t je;
    json_t *r = json_load_file(rpath, 0, &je);
    cr_assert_not_null(r, "result.json: %s", je.text);
    return r;
}

static double metric(json_t *r, const char *name, const char *unit)
{
    json_t *m = json_object_get(json_object_get(r, "metrics"), name);
    cr_assert_not_null(m, "metric %s missing", name);
    cr_assert_str_eq(json_string_value(json_object_get(m, "unit")), unit);
    return json_real_value(json_object_get(m, "value"));
}

Test(output, zero_step_run_writes_energy_forces_pressure)
{
    char dir[1024];
    json_t *r = run_case("zero.yaml",
                         "system:\n  lattice: {style: fcc, a: 3.5, cells: [3, 3, 3]}\n"
                         "  element: Cu\n  displace: 0.05\npotential: {style: eam/alloy, file: "
                         "Cu_mishin1.eam.alloy}\nmd: {steps: 0}\noutput: {xyz_every: 1}\n",
                         0, dir, sizeof dir);
    cr_assert_str_eq(json_string_value(json_object_get(r, "status")), "ok");
    double pe = metric(r, "pe_per_atom", "eV/atom");
    cr_assert(pe < -3.3 && pe > -3.6, "pe/atom %g", pe);
    double pxx = metric(r, "pxx", "GPa"), pyy = metric(r, "pyy", "GPa");
    cr_assert(pxx > 5 && pyy > 5, "compressed crystal must be under pressure (%g, %g GPa)", pxx, pyy);
    metric(r, "pxy", "GPa");
    json_decref(r);
    /* HDF5: forces at step 0 with a unit attribute */
    char h5[1100];
    snprintf(h5, sizeof h5, "%s/fields.h5", dir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    hid_t ds = H5Dopen2(f, "/particles/00000000/force", H5P_DEFAULT);
    cr_assert(ds >= 0, "force dataset missing");
    hid_t sp = H5Dget_space(ds);
    hsize_t dims[2];
    H5Sget_simple_extent_dims(sp, dims, NULL);
    cr_assert_eq(dims[0], 108);
    cr_assert_eq(dims[1], 3);
    cr_assert(H5Aexists(ds, "unit") > 0);
    H5Sclose(sp);
    H5Dclose(ds);
    cr_assert(H5Lexists(f, "/series/pxx_GPa", H5P_DEFAULT) > 0);
    cr_assert(H5Aexists(f, "provenance") > 0);
    H5Fclose(f);
    /* XDMF sidecar references the HDF5 file */
    char xp[1100], buf[8192];
    snprintf(xp, sizeof xp, "%s/fields.xdmf", dir);
    FILE *x = fopen(xp, "r");
    cr_assert_not_null(x);
    size_t n = fread(buf, 1, sizeof buf - 1, x);
    buf[n] = '\0';
    fclose(x);
    cr_assert(strstr(buf, "fields.h5:/particles/00000000/position") && strstr(buf, "Polyvertex"));
    /* extended XYZ reads back with the same atoms */
    snprintf(xp, sizeof xp, "%s/snapshots.xyz", dir);
    struct particles *p = particles_create(200);
    struct box b = {0};
    int pbc[3];
    struct err e = {0};
    cr_assert_eq(config_read_extxyz(xp, NULL, p, &b, pbc, &e), 0, "%s", e.msg);
    cr_assert_eq(p->n_owned, 108);
    cr_assert(pbc[0] && pbc[1] && pbc[2]);
    cr_assert_lt(fabs(b.hi[0] - 10.5), 1e-9);
    particles_destroy(&p);
}

Test(output, diverged_run_is_recorded)
{
    char dir[1024];
    json_t *r = run_case("div.yaml",
                         "system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n"
                         "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                         "md: {steps: 200, temperature: 300, max_energy_change: 1e-9}\n",
                         4, dir, sizeof dir);
    cr_assert_str_eq(json_string_value(json_object_get(r, "status")), "diverged");
    cr_assert(strstr(json_string_value(json_object_get(r, "message")), "total energy changed"));
    json_decref(r);
}

Test(output, read_data_and_run)
{
    char yaml[1024], dir[1024];
    snprintf(yaml, sizeof yaml,
             "system:\n  read_data: %s/tests/data/cu256.data\npotential: {style: eam/alloy, "
             "file: Cu_mishin1.eam.alloy}\nmd: {steps: 20}\noutput: {hdf5: false}\n",
             th_root());
    json_t *r = run_case("data.yaml", yaml, 0, dir, sizeof dir);
    cr_assert_eq((int)metric(r, "atoms", "1"), 256);
    json_decref(r);
}

/* timing.cpu_seconds: the CPU seconds of the loop and of the whole run
 * (what the benchmarks compare on a loaded machine), beside the wall-clock
 * timer rows: present, positive, the loop's within the run's, and no more
 * than the two threads the run may use could spend in its wall time. */
Test(output, timing_has_loop_and_total_cpu_seconds)
{
    char dir[1024];
    json_t *r = run_case("cpu.yaml",
                         "system:\n  lattice: {style: fcc, a: 3.615, cells: [4, 4, 4]}\n"
                         "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                         "md: {steps: 200, temperature: 300}\noutput: {hdf5: false}\n",
                         0, dir, sizeof dir);
    json_t *timing = json_object_get(r, "timing");
    json_t *cpu = json_object_get(timing, "cpu_seconds");
    cr_assert_not_null(cpu, "timing.cpu_seconds missing");
    double loop = json_real_value(json_object_get(cpu, "loop"));
    double total = json_real_value(json_object_get(cpu, "total"));
    double wall = json_real_value(json_object_get(json_object_get(timing, "total"), "seconds"));
    cr_assert_gt(loop, 0, "loop CPU %g s", loop);
    cr_assert_leq(loop, total, "loop CPU %g s > run CPU %g s", loop, total);
    cr_assert_leq(total, 2.0 * wall + 0.05, "run CPU %g s against %g s wall", total, wall);
    /* the wall-clock rows keep their layout ("calls", "seconds") */
    cr_assert_not_null(json_object_get(json_object_get(timing, "loop"), "seconds"));
    json_decref(r);
}
