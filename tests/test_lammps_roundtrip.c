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
 * (as tests/test_lammps_ref.c), and so do the pressure tensors (1e-6 of
 * the largest component: LAMMPS' metal constants nktv2p and mvv2e are
 * rounded); lmp's energy of state.data equals its energy of its own file
 * to 1e-12 relative.
 *
 * The same with a tilted prism (xy xz yz = 0.5 0.25 -0.33 lattice units:
 * 1.8075, 0.90375, -1.19295 Å; core/box.h), once for 0 steps and once for
 * 50 NVE steps of 1 fs run by both codes from lmp's file: Cascade's state
 * after 50 steps, read back by lmp, has lmp's own energy after 50 steps
 * to 1e-8 relative and its positions and velocities to 1e-6 Å and 1e-5
 * Å/ps (LAMMPS' metal ftm2v is rounded to 8 digits, 6e-9 relative in the
 * accelerations: ~3e-6 Å/ps after 50 fs at ~1 eV/Å).  The tests stop with a message when lmp is missing.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"
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

/* The numbers of the line "<key> <n1> <n2> ..." the input printed into its
 * log (the last such line); returns how many were read. */
static int lmp_printed(const char *name, const char *key, double *v, int nmax)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/%s.log", th_temp_dir(), name);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s", path);
    char line[1024];
    size_t kl = strlen(key);
    int n = 0;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, kl) == 0 && line[kl] == ' ') {
            char *s = line + kl, *end;
            for (n = 0; n < nmax; n++, s = end) {
                v[n] = strtod(s, &end);
                if (end == s)
                    break;
            }
        }
    fclose(f);
    cr_assert_gt(n, 0, "no %s line in %s", key, path);
    return n;
}

static double lmp_pe(const char *name)
{
    double pe;
    lmp_printed(name, "PE", &pe, 1);
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


/* lmp writes a prism of tilt (lattice units) `tilt` with velocities;
 * Cascade runs `steps` steps from it and writes state.data; lmp reads that
 * back.  Files under the temporary directory carry the tag. */
static void roundtrip(const char *tag, const char *tilt, int steps)
{
    cr_assert(access(LMP, X_OK) == 0, LMP " missing: Debian package lammps (make deps)");
    const char *dir = th_temp_dir();
    char script[4096], name[64];
    snprintf(script, sizeof script,
             LMP_HEAD "lattice fcc 3.615\nregion box prism 0 4 0 4 0 4 %s units lattice\n"
                      "create_box 1 box\ncreate_atoms 1 box\nmass 1 63.546\n"
                      "displace_atoms all random 0.05 0.05 0.05 12345 units box\n"
                      "velocity all create 600 4928459 dist gaussian\n" LMP_PAIR
                      "thermo_style custom step pe pxx pyy pzz pxy pxz pyz\nrun 0\n"
                      "print \"PE $(pe:%%.15g)\"\n"
                      "print \"P $(pxx:%%.15g) $(pyy:%%.15g) $(pzz:%%.15g) $(pxy:%%.15g) "
                      "$(pxz:%%.15g) $(pyz:%%.15g)\"\n"
                      "write_data %s/%s-lmp.data\n"
                      "write_dump all custom %s/%s-lmp.forces id fx fy fz modify format float "
                      "%%.15g\n"
                      "timestep 0.001\nfix 1 all nve\nrun %d\nprint \"PEN $(pe:%%.15g)\"\n"
                      "write_data %s/%s-lmpN.data\n",
             tilt, dir, tag, dir, tag, steps, dir, tag);
    snprintf(name, sizeof name, "%s-write.in", tag);
    lmp_run(name, script);
    double pe_lmp = lmp_pe(name), pen_lmp, p_lmp[6];
    lmp_printed(name, "PEN", &pen_lmp, 1);
    cr_assert_eq(lmp_printed(name, "P", p_lmp, 6), 6);

    char yaml[2048], out[8192], outdir[1100];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s/%s-lmp.data, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: %d, timestep: 0.001}\noutput: {final_state: state.data}\n",
             dir, tag, steps);
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *cpath = th_write_temp(5, name, yaml);
    snprintf(outdir, sizeof outdir, "%s/%s-out", dir, tag);
    const char *argv[] = {th_solver(), "run", cpath, "--out", outdir, "--quiet", NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "cascade-solver: exit %d: %s", rc, out);

    snprintf(script, sizeof script,
             LMP_HEAD "read_data %s/state.data\n" LMP_PAIR
                      "thermo_style custom step pe\nrun 0\nprint \"PE $(pe:%%.15g)\"\n"
                      "write_data %s/%s-back.data\n",
             outdir, dir, tag);
    snprintf(name, sizeof name, "%s-read.in", tag);
    lmp_run(name, script);
    double pe_back = lmp_pe(name);
    /* after steps: LAMMPS' metal ftm2v is 1 / 1.0364269e-4, Cascade's
     * 1 / 1.0364269656e-4 (units.h): accelerations differ by 6e-9 */
    double pe_want = steps ? pen_lmp : pe_lmp, etol = steps ? 1e-8 : 1e-12;
    cr_assert_lt(fabs(pe_back - pe_want), etol * fabs(pe_want),
                 "%s: lmp pe %.15g after %d steps, of Cascade's state.data %.15g", tag, pe_want,
                 steps, pe_back);

    /* positions, velocities, box: lmp's file after the steps against back.data */
    struct box b0, b1;
    char fname[128];
    snprintf(fname, sizeof fname, "%s-lmpN.data", tag);
    struct particles *p0 = read_data(fname, &b0);
    snprintf(fname, sizeof fname, "%s-back.data", tag);
    struct particles *p1 = read_data(fname, &b1);
    cr_assert_eq(p0->n_owned, 256);
    cr_assert_eq(p1->n_owned, p0->n_owned);
    for (int d = 0; d < 3; d++) {
        cr_assert_lt(fabs(b1.lo[d] - b0.lo[d]), 1e-12, "lo %c", "xyz"[d]);
        cr_assert_lt(fabs(b1.hi[d] - b0.hi[d]), 1e-12, "hi %c", "xyz"[d]);
        cr_assert_lt(fabs(b1.tilt[d] - b0.tilt[d]), 1e-12, "tilt %d", d);
    }
    /* after steps: the 6e-9 in the accelerations (above) times forces of
     * ~1 eV/Å over 0.05 ps is ~3e-6 Å/ps and ~1e-7 Å */
    double xtol = steps ? 1e-6 : 1e-9, vtol = steps ? 1e-5 : 1e-9;
    double vmax = 0;
    for (long i = 0; i < p0->n_owned; i++) {
        long j = index_of(p1, p0->id[i]);
        double x0[3], x1[3];
        box_unwrap(&b0, p0, (int)i, x0);
        box_unwrap(&b1, p1, (int)j, x1);
        for (int d = 0; d < 3; d++) {
            cr_assert_lt(fabs(x1[d] - x0[d]), xtol, "%s: atom %lld %c: %.17g, back %.17g", tag,
                         (long long)p0->id[i], "xyz"[d], x0[d], x1[d]);
            cr_assert_lt(fabs(p1->v[3 * j + d] - p0->v[3 * i + d]), vtol, "%s: atom %lld v%c: "
                         "%.17g, back %.17g", tag, (long long)p0->id[i], "xyz"[d],
                         p0->v[3 * i + d], p1->v[3 * j + d]);
            vmax = fmax(vmax, fabs(p0->v[3 * i + d]));
        }
    }
    cr_assert_gt(vmax, 1.0, "600 K velocities (max %g Å/ps)", vmax);
    particles_destroy(&p1);
    particles_destroy(&p0);
    if (steps)
        return;

    /* Cascade's energy, forces and pressure of lmp.data against lmp's */
    char h5[1200];
    snprintf(h5, sizeof h5, "%s/fields.h5", outdir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    double *pe = h5_read(f, "/series/pe_eV", 1);
    double *force = h5_read(f, "/particles/00000000/force", 3 * 256);
    double *ids = h5_read(f, "/particles/00000000/id", 256);
    double *tilt_h5 = h5_read(f, "/particles/00000000/cell/tilt", 3);
    H5Fclose(f);
    cr_assert_lt(fabs(pe[0] - pe_lmp), 1e-9 * fabs(pe_lmp), "pe %.15g, lmp %.15g", pe[0],
                 pe_lmp);
    struct box bl;
    snprintf(fname, sizeof fname, "%s-lmp.data", tag);
    struct particles *pl = read_data(fname, &bl);
    for (int d = 0; d < 3; d++)
        cr_assert_eq(tilt_h5[d], bl.tilt[d], "fields.h5 cell/tilt %d: %.17g, file %.17g", d,
                     tilt_h5[d], bl.tilt[d]);
    particles_destroy(&pl);
    json_t *res = thb_result(outdir);
    static const char *const pn[6] = {"pxx", "pyy", "pzz", "pxy", "pxz", "pyz"};
    double pscale = 0;
    for (int c = 0; c < 6; c++)
        pscale = fmax(pscale, fabs(p_lmp[c]));
    for (int c = 0; c < 6; c++) {
        double pc = thb_metric(res, pn[c]) * 1e4;   /* GPa -> bar (LAMMPS metal) */
        /* 1e-6: LAMMPS' rounded nktv2p and mvv2e (as tests/test_lammps_ref.c) */
        cr_assert_lt(fabs(pc - p_lmp[c]), 1e-6 * pscale, "%s: %s %.12g bar, lmp %.12g",
                     tag, pn[c], pc, p_lmp[c]);
    }
    json_decref(res);
    char fpath[1100];
    snprintf(fpath, sizeof fpath, "%s/%s-lmp.forces", dir, tag);
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
            cr_assert_lt(fabs(force[3 * k + d] - fl[d]), 1e-9, "%s: atom %ld f%c %.15g, lmp %.15g",
                         tag, id, "xyz"[d], force[3 * k + d], fl[d]);
        nf++;
    }
    fclose(in);
    cr_assert_eq(nf, 256);
    free(pe);
    free(force);
    free(ids);
    free(tilt_h5);
}

Test(lammps_roundtrip, triclinic_data_with_velocities_through_cascade_and_back)
{
    roundtrip("zero", "0 0 0", 0);
}

Test(lammps_roundtrip, tilted_prism_through_cascade_and_back)
{
    roundtrip("tilted", "0.5 0.25 -0.33", 0);
}

Test(lammps_roundtrip, tilted_prism_50_nve_steps_in_both_codes)
{
    roundtrip("tilted50", "0.5 0.25 -0.33", 50);
}
