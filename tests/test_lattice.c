/*
 * Lattice builders, regions and boundaries: site counts and nearest-
 * neighbour distances of the cubic and hcp builders, oriented crystals,
 * region cuts, free (shrink-wrapped) and fixed boundaries.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/box.h"
#include "core/lattice.h"
#include "helpers/th.h"

static struct particles *fill(struct lattice *l, long n, const struct region *r, long *count)
{
    struct particles *p = particles_create(64);
    particles_type_index(p, "X", 1.0);
    int64_t id = 1;
    long cells[3] = {n, n, n};
    struct err e = {0};
    *count = lattice_fill(l, cells, r, p, 0, &id, &e);
    cr_assert(*count >= 0, "%s", e.msg);
    return p;
}

/* smallest pair distance (brute force, no periodicity) */
static double min_distance(const struct particles *p)
{
    double best = INFINITY;
    for (int i = 0; i < p->n_owned; i++)
        for (int j = i + 1; j < p->n_owned; j++) {
            double r2 = 0;
            for (int d = 0; d < 3; d++) {
                double dd = p->x[3 * i + d] - p->x[3 * j + d];
                r2 += dd * dd;
            }
            best = fmin(best, r2);
        }
    return sqrt(best);
}

Test(lattice, counts_and_nearest_neighbours)
{
    struct {
        enum lattice_style s;
        int per_cell;
        double nn;   /* in units of a */
    } cases[] = {{LATTICE_SC, 1, 1.0},
                 {LATTICE_BCC, 2, 0.8660254037844386},
                 {LATTICE_FCC, 4, 0.7071067811865476},
                 {LATTICE_DIAMOND, 8, 0.4330127018922193},
                 {LATTICE_HCP, 4, 1.0}};
    for (int k = 0; k < 5; k++) {
        struct lattice l = {cases[k].s, 2.0, {0, 0, 0}, {{0}}};
        long count;
        struct particles *p = fill(&l, 3, NULL, &count);
        cr_assert_eq(count, 27L * cases[k].per_cell, "style %d", k);
        cr_assert_lt(fabs(min_distance(p) - 2.0 * cases[k].nn), 1e-12, "style %d nn %g", k,
                     min_distance(p));
        particles_destroy(&p);
    }
}

Test(lattice, oriented_fcc_110)
{
    struct lattice l = {LATTICE_FCC, 3.615, {0, 0, 0}, {{1, 1, 0}, {-1, 1, 0}, {0, 0, 1}}};
    char why[128];
    cr_assert_eq(lattice_check_orient(&l, why, sizeof why), 0, "%s", why);
    double cell[3];
    lattice_cell(&l, cell);
    cr_assert_lt(fabs(cell[0] - 3.615 * sqrt(2.0)), 1e-12);
    long count;
    struct particles *p = fill(&l, 2, NULL, &count);
    /* cell volume 2 a^3 holds 8 sites; 2x2x2 cells -> 64 */
    cr_assert_eq(count, 64);
    cr_assert_lt(fabs(min_distance(p) - 3.615 / sqrt(2.0)), 1e-9);
    particles_destroy(&p);
    struct lattice bad = {LATTICE_FCC, 3.615, {0, 0, 0}, {{1, 1, 0}, {1, 1, 0}, {0, 0, 1}}};
    cr_assert_neq(lattice_check_orient(&bad, why, sizeof why), 0);
}

Test(lattice, sphere_and_slab_regions)
{
    struct lattice l = {LATTICE_FCC, 1.0, {0, 0, 0}, {{0}}};
    /* a sphere of radius 0.75 a around a site holds it and its 12 neighbours */
    struct region s = {.shape = REGION_SPHERE, .center = {2, 2, 2}, .radius = 0.75};
    long count;
    struct particles *p = fill(&l, 4, &s, &count);
    cr_assert_eq(count, 13);
    particles_destroy(&p);
    struct region slab = {.shape = REGION_SLAB, .axis = 2, .lo = {0, 0, 1.0}, .hi = {0, 0, 2.0}};
    p = fill(&l, 4, &slab, &count);
    cr_assert_eq(count, 4 * 4 * 4);   /* two (001) planes of 2 sites per cell each */
    particles_destroy(&p);
}

Test(lattice, free_boundary_shrink_wraps_and_fixed_boundary_loses_atoms)
{
    struct particles *p = particles_create(8);
    particles_type_index(p, "X", 1.0);
    double a[3] = {1, 1, 1}, b[3] = {4, 5, 6};
    particles_add(p, a, NULL, 0, 1);
    particles_add(p, b, NULL, 0, 2);
    struct box box = {{0, 0, 0}, {10, 10, 10}, {BOUNDARY_FREE, BOUNDARY_PERIODIC, BOUNDARY_FIXED}, {0, 0, 0}};
    struct err e = {0};
    cr_assert_eq(box_remap(&box, p, 0.0, &e), 0);
    cr_assert_float_eq(box.lo[0], 1.0, 1e-12);
    cr_assert_float_eq(box.hi[0], 4.0, 1e-12);
    p->x[3 * 1 + 1] = 12.5;   /* periodic y wraps with an image count */
    cr_assert_eq(box_remap(&box, p, 0.0, &e), 0);
    cr_assert_float_eq(p->x[4], 2.5, 1e-12);
    cr_assert_eq(p->image[4], 1);
    /* a hair below the lower face: wrapped onto lo, and the unwrapped
     * position x + image L stays where the atom is (it was lo - L) */
    p->x[4] = -1e-17;
    p->image[4] = 0;
    cr_assert_eq(box_remap(&box, p, 0.0, &e), 0);
    cr_assert_eq(p->x[4], 0.0);
    cr_assert_eq(p->image[4], 0);
    p->x[4] = 20.0 - 1e-15;   /* two boxes up, a hair below: image 1, x near 10 */
    cr_assert_eq(box_remap(&box, p, 0.0, &e), 0);
    cr_assert(p->x[4] < 10.0 && p->x[4] + 10.0 * p->image[4] > 19.9, "x %g image %d", p->x[4],
              p->image[4]);
    p->x[3 * 1 + 2] = 10.5;   /* through the fixed z face */
    cr_assert_eq(box_remap(&box, p, 0.0, &e), ERR_RUNTIME);
    cr_assert(strstr(e.msg, "particle 2 left the box through the fixed z boundary"), "%s", e.msg);
    particles_destroy(&p);
}
