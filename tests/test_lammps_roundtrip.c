/*
 * LAMMPS -> Cascade -> LAMMPS with Debian's lmp (package lammps, DEB_PKGS):
 *
 *   1. lmp builds a 4x4x4 fcc Cu crystal in a triclinic box (prism region
 *      of tilt 0 0 0), displaces the atoms by up to 0.05 Å, gives them
 *      600 K velocities, and writes the data file (write_data: "0 0 0 xy
 *      xz yz", image flags, Velocities), its energy and forces (Mishin
 *      EAM, run 0);
 *   2. cascade-solver reads that file, runs 0 steps and writes
 *      final_state state.data;
 *   3. lmp reads state.data, prints its energy and writes it again.
 *
 * Positions (unwrapped with the image flags), velocities and the box of
 * the file lmp wrote last agree with the first to 1e-9 Å, 1e-9 Å/ps and
 * 1e-12 Å (both writers print 17 digits); Cascade's energy and forces of
 * the lmp configuration agree with lmp's to 1e-9 relative and 1e-9 eV/Å
 * (as tests/test_lammps_ref.c); lmp's energy of state.data equals its
 * energy of its own file to 1e-12 relative.  A data file lmp writes for a
 * tilted prism is refused at its tilt line (the MD box is orthogonal).
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "helpers/th.h"
#include "input/config_read.h"

#define LMP "/usr/bin/lmp"
#define POTENTIAL "/usr/share/lammps/potentials/Cu_mishin1.eam.alloy"

static void lmp_run(const char *name, const char *script)
{
    const char *in = th_write_temp(4, name, script);
    char log[1100], out[4096];
    snprintf(log, sizeof log, "%s.log", in);
    const char *argv[] = {LMP, "-in", in, "-log", log, "-screen", "none", NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "lmp -in %s: exit %d: %s (log %s)", name, rc, out, log);
}

/* The value of the line "PE <number>" the input printed into its log. */
static double lmp_pe(const char *name)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/%s.log", th_temp_dir(), name);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s", path);
    char line[512];
    double pe = NAN;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "PE ", 3) == 0)
            pe = strtod(line + 3, NULL);
    fclose(f);
    cr_assert(isfinite(pe), "no PE line in %s", path);
    return pe;
}

static struct particles *read_data(const char *name, struct box *b)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/%s", th_temp_dir(), name);
    static const char *const cu[] = {"Cu"};
    struct particles *p = particles_create(300);
    struct err e = {0};
    cr_assert_eq(config_read_lammps_data(path, cu, 1, NULL, p, b, &e), 0, "%s", e.msg);
    return p;
}

static long index_of(const struct particles *p, int64_t id)
{
    for (long i = 0; i < p->n_owned; i++)
        if (p->id[i] == id)
            return i;
    cr_assert_fail("atom id %lld missing", (long long)id);
    return -1;
}

static double *h5_read(hid_t f, const char *path, long n)
{
    hid_t ds = H5Dopen2(f, path, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", path);
    double *v = malloc((size_t)n * sizeof *v);
    cr_assert_not_null(v);
    cr_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    return v;
}

#define LMP_HEAD "units metal\natom_style atomic\nboundary p p p\n"
#define LMP_PAIR "pair_style eam/alloy\npair_coeff * * " POTENTIAL " Cu\n"

Test(lammps_roundtrip, triclinic_data_with_velocities_through_cascade_and_back)
{
    cr_assert(access(LMP, X_OK) == 0, LMP " missing: Debian package lammps (make deps)");
    const char *dir = th_temp_dir();
    char script[4096];
    snprintf(script, sizeof script,
             LMP_HEAD "lattice fcc 3.615\nregion box prism 0 4 0 4 0 4 0 0 0 units lattice\n"
                      "create_box 1 box\ncreate_atoms 1 box\nmass 1 63.546\n"
                      "displace_atoms all random 0.05 0.05 0.05 12345 units box\n"
                      "velocity all create 600 4928459 dist gaussian\n" LMP_PAIR
                      "thermo_style custom step pe\nrun 0\nprint \"PE $(pe:%%.15g)\"\n"
                      "write_data %s/lmp.data\n"
                      "write_dump all custom %s/lmp.forces id fx fy fz modify format float "
                      "%%.15g\n",
             dir, dir);
    lmp_run("write.in", script);
    double pe_lmp = lmp_pe("write.in");

    char yaml[2048], out[8192], outdir[1100];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s/lmp.data, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\nmd: {steps: 0}\n"
             "output: {final_state: state.data}\n",
             dir);
    const char *cpath = th_write_temp(5, "rt.yaml", yaml);
    snprintf(outdir, sizeof outdir, "%s/rt-out", dir);
    const char *argv[] = {th_solver(), "run", cpath, "--out", outdir, "--quiet", NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "cascade-solver: exit %d: %s", rc, out);

    snprintf(script, sizeof script,
             LMP_HEAD "read_data %s/state.data\n" LMP_PAIR
                      "thermo_style custom step pe\nrun 0\nprint \"PE $(pe:%%.15g)\"\n"
                      "write_data %s/back.data\n",
             outdir, dir);
    lmp_run("read.in", script);
    double pe_back = lmp_pe("read.in");
    cr_assert_lt(fabs(pe_back - pe_lmp), 1e-12 * fabs(pe_lmp), "lmp pe %.15g, of state.data %.15g",
                 pe_lmp, pe_back);

    /* positions, velocities, box: lmp.data against back.data */
    struct box b0, b1;
    struct particles *p0 = read_data("lmp.data", &b0), *p1 = read_data("back.data", &b1);
    cr_assert_eq(p0->n_owned, 256);
    cr_assert_eq(p1->n_owned, p0->n_owned);
    for (int d = 0; d < 3; d++) {
        cr_assert_lt(fabs(b1.lo[d] - b0.lo[d]), 1e-12, "lo %c", "xyz"[d]);
        cr_assert_lt(fabs(b1.hi[d] - b0.hi[d]), 1e-12, "hi %c", "xyz"[d]);
    }
    double vmax = 0;
    for (long i = 0; i < p0->n_owned; i++) {
        long j = index_of(p1, p0->id[i]);
        for (int d = 0; d < 3; d++) {
            double L = b0.hi[d] - b0.lo[d];
            double x0 = p0->x[3 * i + d] + p0->image[3 * i + d] * L;
            double x1 = p1->x[3 * j + d] + p1->image[3 * j + d] * L;
            cr_assert_lt(fabs(x1 - x0), 1e-9, "atom %lld %c: %.17g, back %.17g",
                         (long long)p0->id[i], "xyz"[d], x0, x1);
            cr_assert_lt(fabs(p1->v[3 * j + d] - p0->v[3 * i + d]), 1e-9, "atom %lld v%c",
                         (long long)p0->id[i], "xyz"[d]);
            vmax = fmax(vmax, fabs(p0->v[3 * i + d]));
        }
    }
    cr_assert_gt(vmax, 1.0, "600 K velocities (max %g Å/ps)", vmax);
    particles_destroy(&p1);

    /* Cascade's energy and forces of lmp.data against lmp's */
    char h5[1200];
    snprintf(h5, sizeof h5, "%s/fields.h5", outdir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    double *pe = h5_read(f, "/series/pe_eV", 1);
    double *force = h5_read(f, "/particles/00000000/force", 3 * 256);
    double *ids = h5_read(f, "/particles/00000000/id", 256);
    H5Fclose(f);
    cr_assert_lt(fabs(pe[0] - pe_lmp), 1e-9 * fabs(pe_lmp), "pe %.15g, lmp %.15g", pe[0],
                 pe_lmp);
    char fpath[1100];
    snprintf(fpath, sizeof fpath, "%s/lmp.forces", dir);
    FILE *in = fopen(fpath, "r");
    cr_assert_not_null(in);
    char line[512];
    while (fgets(line, sizeof line, in) && strncmp(line, "ITEM: ATOMS", 11) != 0)
        ;
    int nf = 0;
    long id;
    double fl[3];
    while (fscanf(in, "%ld %lf %lf %lf", &id, &fl[0], &fl[1], &fl[2]) == 4) {
        long k = -1;
        for (long i = 0; i < 256; i++)
            if ((long)ids[i] == id)
                k = i;
        cr_assert_geq(k, 0, "id %ld", id);
        for (int d = 0; d < 3; d++)
            cr_assert_lt(fabs(force[3 * k + d] - fl[d]), 1e-9, "atom %ld f%c %.15g, lmp %.15g",
                         id, "xyz"[d], force[3 * k + d], fl[d]);
        nf++;
    }
    fclose(in);
    cr_assert_eq(nf, 256);
    free(pe);
    free(force);
    free(ids);
    particles_destroy(&p0);
}

Test(lammps_roundtrip, tilted_lmp_data_is_refused_at_its_tilt_line)
{
    cr_assert(access(LMP, X_OK) == 0, LMP " missing: Debian package lammps (make deps)");
    const char *dir = th_temp_dir();
    char script[2048];
    snprintf(script, sizeof script,
             LMP_HEAD "lattice fcc 3.615\nregion box prism 0 4 0 4 0 4 0.5 0 0 units lattice\n"
                      "create_box 1 box\ncreate_atoms 1 box\nmass 1 63.546\n"
                      "write_data %s/tilted.data\n",
             dir);
    lmp_run("tilted.in", script);
    char yaml[1024], out[4096];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s/tilted.data, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\nmd: {steps: 0}\n",
             dir);
    const char *cpath = th_write_temp(5, "tilted.yaml", yaml);
    const char *argv[] = {th_solver(), "check", cpath, NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 2, "exit %d: %s", rc, out);
    /* line 9: title, blank, 2 counts, blank, 3 bounds, then the tilt */
    cr_assert(strstr(out, "tilted.data:9: xy xz yz: tilt xy = 1.8075: only orthogonal boxes"),
              "%s", out);
}
