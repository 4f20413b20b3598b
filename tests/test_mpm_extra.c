/*
 * Extra particle sets on the MPM grid -- the API the couplings build on:
 *
 * - particles carried by the grid with their own forces mapped with N_i
 *   (Chen 2014, Eq. (s3b), DPD particles on the MPM grid): a uniform force
 *   per unit mass accelerates every particle by exactly F / m, and the
 *   total momentum changes by exactly sum F dt;
 * - material points and such particles on one grid (Chen 2014, Eq. (3.1)):
 *   the particles are carried along with the material, and the total
 *   momentum of both sets is conserved;
 * - a set that does not follow the grid but carries a stress and volume
 *   (MD atoms of region I acting as material points, Guo & Yang 2005)
 *   gives the same nodal forces as the material points it replaces.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "helpers/th_mpm.h"

/* Particles at n^3 sub-positions of every cell of box [lo, hi). */
static long lattice_points(const double lo[3], const double hi[3], int n, double **x)
{
    long cnt = 0, cap = 4096;
    *x = malloc(cap * 3 * sizeof **x);
    for (double z = lo[2] + 0.5 / n; z < hi[2]; z += 1.0 / n)
        for (double y = lo[1] + 0.5 / n; y < hi[1]; y += 1.0 / n)
            for (double xx = lo[0] + 0.5 / n; xx < hi[0]; xx += 1.0 / n) {
                if (cnt == cap) {
                    cap *= 2;
                    *x = realloc(*x, cap * 3 * sizeof **x);
                }
                (*x)[3 * cnt] = xx, (*x)[3 * cnt + 1] = y, (*x)[3 * cnt + 2] = z;
                cnt++;
            }
    return cnt;
}

Test(mpm_extra, particle_forces_mapped_with_shape_functions)
{
    struct mpm m;
    long nc[3] = {12, 8, 8};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 1);
    double lo[3] = {3, 2, 2}, hi[3] = {7, 6, 6}, *x;
    long n = lattice_points(lo, hi, 2, &x);
    double *v = calloc(3 * n, sizeof *v), *f = calloc(3 * n, sizeof *f);
    int *types = calloc(n, sizeof *types);
    double type_mass[1] = {63.5};   /* amu: one DPD particle type */
    const double F[3] = {2e-3, -1e-3, 5e-4};   /* eV/Å on every particle */
    for (long i = 0; i < n; i++)
        for (int d = 0; d < 3; d++)
            f[3 * i + d] = F[d];
    double *x0 = malloc(3 * n * sizeof *x0);
    memcpy(x0, x, 3 * n * sizeof *x0);
    struct mpm_extra dpd = {.name = "dpd", .n = n, .x = x, .v = v, .type = types,
                            .type_mass = type_mass, .force = f, .follow_grid = 1};
    struct err e = {0};
    cr_assert_eq(mpm_attach(&m, &dpd, &e), 0);
    cr_assert_eq(mpm_prepare(&m, &e), 0);
    const double dt = 0.01;
    double xexp = 0;   /* sum over steps of v(t + dt) dt, per unit F/m */
    for (int s = 1; s <= 50; s++) {
        cr_assert_eq(mpm_step(&m, dt, &e), 0, "%s", e.msg);
        xexp += s * dt * dt;
    }
    double a[3];
    for (int d = 0; d < 3; d++)
        a[d] = F[d] / type_mass[0] * UNITS_FTM2V;
    double dv = 0, dx = 0;
    for (long i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            dv = fmax(dv, fabs(v[3 * i + d] - a[d] * 0.5));
            dx = fmax(dx, fabs(x[3 * i + d] - x0[3 * i + d] - a[d] * xexp));
        }
    cr_assert(dv < 1e-12 * fabs(a[0]) * 0.5 * 10, "velocity off by %g", dv);
    cr_assert(dx < 1e-10, "position off by %g Å", dx);
    mpm_detach(&m, &dpd);
    mpm_free(&m);
    free(x), free(x0), free(v), free(f), free(types);
}

Test(mpm_extra, material_points_and_particles_share_one_grid)
{
    struct mpm m;
    long nc[3] = {24, 8, 8};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", 5.0, 1.0, 0.3));
    double lo[3] = {2, 2, 2}, hi[3] = {10, 6, 6}, vb[3] = {3.0, 0, 0};
    th_mpm_box(&m, "block", mat, lo, hi, 2, vb, 0);
    /* light particles at rest at the cell centres of the same region */
    double *x;
    long n = lattice_points(lo, hi, 1, &x);
    double *v = calloc(3 * n, sizeof *v), *mass = malloc(n * sizeof *mass);
    double *x0 = malloc(3 * n * sizeof *x0);
    memcpy(x0, x, 3 * n * sizeof *x0);
    for (long i = 0; i < n; i++)
        mass[i] = 0.01;
    struct mpm_extra dpd = {.name = "dpd", .n = n, .x = x, .v = v, .mass = mass, .follow_grid = 1};
    struct err e = {0};
    cr_assert_eq(mpm_attach(&m, &dpd, &e), 0);
    cr_assert_eq(mpm_prepare(&m, &e), 0);
    double p0 = 0;
    for (long p = 0; p < m.pts.n; p++)
        p0 += m.pts.mass[p] * m.pts.v[3 * p];
    double t = 0;
    for (int s = 0; s < 100; s++) {
        double dt = 0.5 * mpm_stable_dt(&m);
        cr_assert_eq(mpm_step(&m, dt, &e), 0, "%s", e.msg);
        t += dt;
    }
    double p1 = 0, moved = 0;
    for (long p = 0; p < m.pts.n; p++)
        p1 += m.pts.mass[p] * m.pts.v[3 * p];
    for (long i = 0; i < n; i++) {
        p1 += mass[i] * v[3 * i];
        moved += (x[3 * i] - x0[3 * i]) / n;
    }
    /* carried by the material: the block moved 3 t, so did the particles */
    cr_assert(fabs(moved / (vb[0] * t) - 1) < 0.01, "particles moved %g of %g Å", moved,
              vb[0] * t);
    cr_assert(fabs(p1 - p0) < 1e-12 * p0, "momentum %.17g -> %.17g", p0, p1);
    mpm_detach(&m, &dpd);
    mpm_free(&m);
    free(x), free(x0), free(v), free(mass);
}

/* Nodal forces of a stressed block, either all material points or with
 * its right half handed over as a non-following extra set. */
static void stressed_block(int split, double **f_out, long *nn)
{
    struct mpm m;
    long nc[3] = {12, 6, 6};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", 5.0, 1.0, 0.3));
    double lo[3] = {2, 1, 1}, mid[3] = {6, 5, 5}, hi[3] = {10, 5, 5};
    double lo2[3] = {6, 1, 1};
    th_mpm_box(&m, "left", mat, lo, mid, 2, NULL, 0);
    struct mpm_extra atoms = {0};
    double *x = NULL, *v = NULL, *mass = NULL, *stress = NULL, *vol = NULL;
    if (!split) {
        th_mpm_box(&m, "right", mat, lo2, hi, 2, NULL, 0);
    } else {
        long n = lattice_points(lo2, hi, 2, &x);
        v = calloc(3 * n, sizeof *v);
        mass = malloc(n * sizeof *mass);
        vol = malloc(n * sizeof *vol);
        stress = malloc(6 * n * sizeof *stress);
        for (long i = 0; i < n; i++) {
            mass[i] = 5.0 * 0.125, vol[i] = 0.125;
            double s[6] = {1e-2, 2e-3, -3e-3, 1e-3, 0, 4e-4};
            memcpy(stress + 6 * i, s, sizeof s);
        }
        atoms = (struct mpm_extra){.name = "region I", .n = n, .x = x, .v = v, .mass = mass,
                                   .stress = stress, .volume = vol, .follow_grid = 0};
        struct err e = {0};
        cr_assert_eq(mpm_attach(&m, &atoms, &e), 0);
    }
    for (long p = 0; p < m.pts.n; p++) {
        double s[6] = {1e-2, 2e-3, -3e-3, 1e-3, 0, 4e-4};
        memcpy(m.pts.stress + 6 * p, s, sizeof s);
    }
    struct err e = {0};
    cr_assert_eq(mpm_locate_particles(&m, &e), 0, "%s", e.msg);
    mpm_clear_grid(&m);
    mpm_map_to_grid(&m, MPM_MAP_ALL);
    *nn = m.grid.nnodes;
    *f_out = malloc(4 * *nn * sizeof **f_out);
    for (long i = 0; i < *nn; i++) {
        (*f_out)[4 * i] = m.grid.node[i].m;
        for (int d = 0; d < 3; d++)
            (*f_out)[4 * i + 1 + d] = m.grid.node[i].f[d];
    }
    mpm_free(&m);
    free(x), free(v), free(mass), free(stress), free(vol);
}

Test(mpm_extra, stressed_non_following_set_acts_as_material_points)
{
    double *fa, *fb;
    long na, nb;
    stressed_block(0, &fa, &na);
    stressed_block(1, &fb, &nb);
    cr_assert_eq(na, nb);
    double big = 0, diff = 0;
    for (long k = 0; k < 4 * na; k++) {
        big = fmax(big, fabs(fa[k]));
        diff = fmax(diff, fabs(fa[k] - fb[k]));
    }
    cr_assert(big > 1e-3, "no force at all");
    cr_assert(diff < 1e-14 * big, "nodal mass/force differ by %g (scale %g)", diff, big);
    free(fa);
    free(fb);
}
