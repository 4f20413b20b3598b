/*
 * Extended XYZ as ASE reads it: Debian's python3-ase (a test dependency,
 * DEB_PKGS) reads snapshots.xyz with ase.io.read and no column mapping;
 * positions, cell, pbc, velocities (from ASE's momenta and masses),
 * forces, per-atom energies and the stress columns must equal the HDF5
 * snapshot of the same step.
 *
 * Tolerances: the XYZ columns have 10 significant digits (relative
 * 1e-9 after rounding); ASE's unit of time uses CODATA 2014 constants,
 * the solver CODATA 2018 (relative 4e-9 on velocities).
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "helpers/th.h"

#define ASE_PYTHON "/usr/bin/python3"

/* Prints what ASE makes of the last frame: cell, pbc, then per atom id,
 * position, velocity (Å/ps), force, energy and the 6 stress columns. */
static const char *const ase_script =
    "import sys\n"
    "import ase.io, ase.units\n"
    "frames = ase.io.read(sys.argv[1], index=':')\n"
    "a = frames[-1]\n"
    "out = open(sys.argv[2], 'w')\n"
    "print('frames', len(frames), file=out)\n"
    "print('cell', *['%.17g' % c for c in a.cell.array.ravel()], file=out)\n"
    "print('pbc', *[int(b) for b in a.pbc], file=out)\n"
    "v = a.get_velocities() * 1000.0 * ase.units.fs\n"
    "f = a.get_forces()\n"
    "e = a.get_potential_energies()\n"
    "s = a.arrays['stress']\n"
    "ids = a.arrays['id']\n"
    "for i in range(len(a)):\n"
    "    print('atom', ids[i], a.get_chemical_symbols()[i],\n"
    "          *['%.17g' % q for q in list(a.positions[i]) + list(v[i]) + list(f[i])\n"
    "            + [e[i]] + list(s[i])], file=out)\n"
    "out.close()\n";

static double *read_ds(hid_t f, const char *group, const char *name, long n, int ncomp)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", group, name);
    hid_t ds = H5Dopen2(f, path, H5P_DEFAULT);
    cr_assert(ds >= 0, "%s missing", path);
    double *v = malloc((size_t)n * ncomp * sizeof *v);
    cr_assert_not_null(v);
    cr_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    return v;
}

static void close_to(double got, double want, double rel, double abs_tol, const char *what,
                     long id)
{
    cr_assert_leq(fabs(got - want), abs_tol + rel * fabs(want),
                  "atom %ld %s: ASE %.12g, fields.h5 %.12g", id, what, got, want);
}

Test(output_extxyz, ase_reads_positions_cell_pbc_velocities_forces_as_written_to_hdf5)
{
    cr_assert(access(ASE_PYTHON, X_OK) == 0, ASE_PYTHON " missing (make deps)");
    const char *yaml = "system:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n"
                       "  element: Cu\n  displace: 0.05\n"
                       "  boundary: [periodic, periodic, free]\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {steps: 3, temperature: 600}\n"
                       "output: {xyz_every: 1, snapshot_every: 3}\n";
    const char *cpath = th_write_temp(1, "xyz.yaml", yaml);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/xyz-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", cpath, "--out", dir, "--quiet", NULL};
    char out[8192];
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "solver exit %d: %s", rc, out);

    char xyz[1100], res[1100];
    snprintf(xyz, sizeof xyz, "%s/snapshots.xyz", dir);
    snprintf(res, sizeof res, "%s/ase.txt", dir);
    const char *script = th_write_temp(2, "read_xyz.py", ase_script);
    const char *pargv[] = {ASE_PYTHON, script, xyz, res, NULL};
    rc = th_run(pargv, out, sizeof out);
    cr_assert_eq(rc, 0, "ase could not read %s (exit %d): %s", xyz, rc, out);

    char h5[1100];
    snprintf(h5, sizeof h5, "%s/fields.h5", dir);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert(f >= 0);
    const char *g = "/particles/00000003";
    const long n = 108;
    double *x = read_ds(f, g, "position", n, 3), *v = read_ds(f, g, "velocity", n, 3);
    double *fo = read_ds(f, g, "force", n, 3), *pe = read_ds(f, g, "pe", n, 1);
    double *st = read_ds(f, g, "stress", n, 6), *idd = read_ds(f, g, "id", n, 1);
    double lo[3], hi[3], pbc[3];
    double *clo = read_ds(f, g, "cell/lo", 3, 1), *chi = read_ds(f, g, "cell/hi", 3, 1);
    double *cpbc = read_ds(f, g, "cell/pbc", 3, 1);
    for (int d = 0; d < 3; d++) {
        lo[d] = clo[d];
        hi[d] = chi[d];
        pbc[d] = cpbc[d];
    }
    free(clo);
    free(chi);
    free(cpbc);
    H5Fclose(f);
    cr_assert_eq(pbc[2], 0.0, "z is free");

    FILE *in = fopen(res, "r");
    cr_assert_not_null(in);
    int nframes = 0;
    cr_assert_eq(fscanf(in, "frames %d\n", &nframes), 1);
    cr_assert_eq(nframes, 4, "frames of steps 0..3");
    double cell[9];
    cr_assert_eq(fscanf(in, "cell %lf %lf %lf %lf %lf %lf %lf %lf %lf\n", &cell[0], &cell[1],
                        &cell[2], &cell[3], &cell[4], &cell[5], &cell[6], &cell[7], &cell[8]),
                 9);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            if (r == c)
                cr_assert_lt(fabs(cell[3 * r + c] - (hi[r] - lo[r])), 1e-8 * (hi[r] - lo[r]),
                             "cell %d: ASE %.12g, fields.h5 %.12g", r, cell[4 * r],
                             hi[r] - lo[r]);
            else
                cr_assert_eq(cell[3 * r + c], 0.0);
    int ap[3];
    cr_assert_eq(fscanf(in, "pbc %d %d %d\n", &ap[0], &ap[1], &ap[2]), 3);
    for (int d = 0; d < 3; d++)
        cr_assert_eq(ap[d], (int)pbc[d], "pbc %c: ASE %d, fields.h5 %g", "xyz"[d], ap[d], pbc[d]);
    int seen = 0;
    double vmax = 0;
    for (long k = 0; k < n; k++) {
        long id;
        char sym[8];
        double q[16];
        int got = fscanf(in, "atom %ld %7s %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf "
                             "%lf %lf %lf\n",
                         &id, sym, &q[0], &q[1], &q[2], &q[3], &q[4], &q[5], &q[6], &q[7], &q[8],
                         &q[9], &q[10], &q[11], &q[12], &q[13], &q[14], &q[15]);
        cr_assert_eq(got, 18, "atom line %ld", k);
        cr_assert_str_eq(sym, "Cu");
        long i = -1;
        for (long j = 0; j < n; j++)
            if ((long)idd[j] == id)
                i = j;
        cr_assert_geq(i, 0, "id %ld not in fields.h5", id);
        seen++;
        for (int d = 0; d < 3; d++) {
            close_to(q[d], x[3 * i + d], 1e-9, 1e-9, "position", id);
            close_to(q[3 + d], v[3 * i + d], 1e-8, 1e-9, "velocity", id);
            close_to(q[6 + d], fo[3 * i + d], 1e-9, 1e-9, "force", id);
            vmax = fmax(vmax, fabs(v[3 * i + d]));
        }
        close_to(q[9], pe[i], 1e-9, 1e-9, "energy", id);
        for (int c = 0; c < 6; c++)
            close_to(q[10 + c], st[6 * i + c], 1e-9, 1e-9, "stress", id);
    }
    fclose(in);
    cr_assert_eq(seen, n);
    cr_assert_gt(vmax, 1.0, "velocities of a 600 K start are several Å/ps (max %g)", vmax);
    free(x);
    free(v);
    free(fo);
    free(pe);
    free(st);
    free(idd);
}
