/*
 * Sputtered groups and crater measurement (solver/analysis/sputter.h,
 * crater.h) on hand-made configurations.
 *
 *   - an fcc(001) slab with, above it, a monomer and a dimer flying away, a
 *     monomer flying towards the surface (an incoming projectile), and a
 *     monomer leaving but still within the margin of the surface: 3
 *     sputtered atoms in 2 groups, the others not;
 *   - a square pit three layers deep dug into fcc(001), edges along [100]:
 *     depth 3 layer spacings, volume and widths as dug, and wider along
 *     [110] than [100] by sqrt 2; the same pit rotated by 45 degrees is
 *     wider along [100]; an undisturbed surface has no crater.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/crater.h"
#include "analysis/sputter.h"
#include "helpers/th.h"

static struct particles *slab(long n, long nz, struct box *b)
{
    struct lattice l = {LATTICE_FCC, 3.615, {0, 0, 0}, {{0}}};
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, "Cu", 63.546);
    int64_t id = 1;
    long cells[3] = {n, n, nz};
    struct err e = {0};
    cr_assert(lattice_fill(&l, cells, NULL, p, t, &id, &e) > 0);
    for (int d = 0; d < 3; d++) {
        b->lo[d] = 0;
        b->hi[d] = cells[d] * 3.615;
        b->bc[d] = d < 2 ? BOUNDARY_PERIODIC : BOUNDARY_FREE;
    }
    return p;
}

Test(sputter, groups_above_the_surface_moving_away)
{
    struct box b = {0};
    struct particles *p = slab(4, 3, &b);
    double top = 2.5 * 3.615;   /* highest layer */
    int t = 0;
    int64_t id = 10000;
    double up[3] = {0, 0, 20}, down[3] = {0, 0, -50};
    double m1[3] = {5, 5, top + 12};
    particles_add(p, m1, up, t, id++);                       /* monomer leaving */
    double d1[3] = {9, 9, top + 20}, d2[3] = {9, 9, top + 22.3};
    particles_add(p, d1, up, t, id++);                       /* dimer leaving */
    particles_add(p, d2, up, t, id++);
    double in[3] = {3, 9, top + 15};
    particles_add(p, in, down, t, id++);                     /* incoming */
    double near[3] = {11, 2, top + 3.5};
    particles_add(p, near, up, t, id++);                     /* within the margin */
    struct frame f = {0};
    struct err e = {0};
    cr_assert_eq(frame_build(&f, p->x, p->n_owned, &b, 3.086, 3.086, 1, &e), 0, "%s", e.msg);
    struct sputter_params sp = {2, top, 4.0, 3.086};
    unsigned char *flag = malloc((size_t)p->n_owned);
    struct sputter_stats st;
    cr_assert_eq(sputter_find(&f, p->v, NULL, &sp, flag, &st, &e), 0, "%s", e.msg);
    cr_assert_eq(st.atoms, 3, "sputtered atoms %ld", st.atoms);
    cr_assert_eq(st.clusters, 2);
    cr_assert_eq(st.monomers, 1);
    cr_assert_eq(st.largest, 2);
    cr_assert_eq(st.groups, 5, "groups %ld (target, monomer, dimer, incoming, near)", st.groups);
    int n = p->n_owned;
    cr_assert(flag[n - 5] == SPUTTER_LEFT && flag[n - 4] == SPUTTER_LEFT && flag[n - 3] == SPUTTER_LEFT);
    cr_assert(flag[n - 2] == SPUTTER_DETACHED && flag[n - 1] == SPUTTER_DETACHED);
    for (int i = 0; i < n - 5; i++)
        cr_assert(flag[i] == SPUTTER_TARGET);
    sp.cutoff = 5.0;   /* beyond the frame's range */
    cr_assert_eq(sputter_find(&f, p->v, NULL, &sp, flag, &st, &e), ERR_RUNTIME);
    frame_free(&f);
    free(flag);
    particles_destroy(&p);
}

/* Remove the atoms of the top `layers` (001) layers inside a square of
 * half-width h centred at c, rotated by `angle`. */
static void dig(struct particles *p, double top, int layers, const double c[2], double h,
                double angle)
{
    unsigned char *keep = malloc((size_t)p->n_owned);
    double ca = cos(angle), sa = sin(angle);
    for (int i = 0; i < p->n_owned; i++) {
        double dx = p->x[3 * i] - c[0], dy = p->x[3 * i + 1] - c[1];
        double u = ca * dx + sa * dy, v = -sa * dx + ca * dy;
        int in_layers = p->x[3 * i + 2] > top - layers * 0.5 * 3.615 + 0.1;
        keep[i] = !(in_layers && fabs(u) < h && fabs(v) < h);
    }
    particles_compact(p, keep);
    free(keep);
}

static struct crater_stats measure(struct particles *p, const struct box *b, double top,
                                   const double c[2], unsigned char **floor_atom)
{
    /* columns offset by a quarter cell from the lattice planes, so every
     * column holds two atoms of each (001) layer strictly inside */
    const double q = 0.25 * 3.615;
    struct crater_params cp = {top, {c[0], c[1]}, {b->lo[0] - q, b->lo[1] - q},
                               {b->hi[0] - q, b->hi[1] - q}, 3.615, 0.25 * 3.615};
    struct crater_stats st;
    struct err e = {0};
    *floor_atom = malloc((size_t)p->n_owned);
    cr_assert_eq(crater_measure(p->x, p->n_owned, NULL, &cp, *floor_atom, &st, &e), 0, "%s", e.msg);
    return st;
}

Test(crater, square_pit_depth_volume_and_shape)
{
    const double a = 3.615;
    struct box b = {0};
    struct particles *p = slab(16, 6, &b);
    double top = 5.5 * a, c[2] = {8 * a, 8 * a};
    unsigned char *fl;
    struct crater_stats st = measure(p, &b, top, c, &fl);
    cr_assert_eq(st.columns, 0, "flat surface has a crater of %ld columns", st.columns);
    cr_assert_float_eq(st.depth, 0.0, 1e-12);
    free(fl);

    /* pit: 3 layers (1.5 a) deep, the atoms of 6 x 6 columns */
    dig(p, top, 3, c, 3 * a + 0.01, 0.0);
    st = measure(p, &b, top, c, &fl);
    cr_assert_float_eq(st.depth, 1.5 * a, 1e-9, "depth %g", st.depth);
    cr_assert_eq(st.columns, 36, "columns %ld", st.columns);
    cr_assert_float_eq(st.volume, 36 * 1.5 * a * a * a, 1e-6);
    cr_assert_float_eq(st.extent[0], 6 * a, 1e-9, "[100] width %g", st.extent[0]);
    cr_assert_float_eq(st.extent[1], 6 * a, 1e-9);
    cr_assert_float_eq(st.extent[2], 6 * a * sqrt(2.0), 1e-9, "[110] width %g", st.extent[2]);
    long nfloor = 0;
    for (int i = 0; i < p->n_owned; i++)
        nfloor += fl[i];
    cr_assert_eq(nfloor, 36);
    free(fl);
    particles_destroy(&p);

    /* the same pit turned by 45 degrees: now wider along [100] */
    p = slab(16, 6, &b);
    dig(p, top, 3, c, 3 * a, M_PI / 4);
    st = measure(p, &b, top, c, &fl);
    cr_assert_float_eq(st.depth, 1.5 * a, 1e-9);
    double r100 = 0.5 * (st.extent[0] + st.extent[1]), r110 = 0.5 * (st.extent[2] + st.extent[3]);
    cr_assert_gt(r100, 1.15 * r110, "rotated pit: [100] %g vs [110] %g", r100, r110);
    free(fl);
    particles_destroy(&p);
}
