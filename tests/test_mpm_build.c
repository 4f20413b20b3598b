/*
 * Making material points for one rank (mpm_build.h): with an owner filter
 * mpm_fill_region stores only the points the owner keeps, each with the id
 * and the data the unfiltered fill gives the same point, and still reports
 * the region's whole count -- so ranks that each keep their part hold
 * between them exactly the serial set, and none ever holds it whole.
 * Checked on a uniform grid (a sphere, 3^3 points per cell) and on a
 * hierarchical one (coarse cells' points are larger and heavier), with a
 * filter that splits the points at a plane through cells.
 */
#include <criterion/criterion.h>
#include <string.h>

#include "helpers/th_mpm.h"
#include "mpm/mpm_build.h"

struct half {
    double cut;   /* keep x < cut (lower) or x >= cut (upper) */
    int upper;
};

static int keep_half(const void *ctx, const double x[3])
{
    const struct half *h = ctx;
    return h->upper ? x[0] >= h->cut : x[0] < h->cut;
}

static void fill_sphere(struct mpm *m, const struct mpm_fill_owner *owner, int64_t first_id,
                        long *added, long *kept)
{
    struct err e = {0};
    int mat = th_mpm_material(m, mpm_material_linear_elastic("s", 0.05, 1.0, 0.3));
    struct mpm_body b = {.material = mat, .velocity = {0.25, 0, -0.5}};
    snprintf(b.name, sizeof b.name, "ball");
    int k = mpm_add_body(m, &b, &e);
    cr_assert(k >= 0, "%s", e.msg);
    struct region r = {.shape = REGION_SPHERE, .center = {7.3, 4.1, 3.9}, .radius = 3.7};
    cr_assert_eq(mpm_fill_region(m, &r, k, 3, owner, first_id, added, kept, &e), 0, "%s",
                 e.msg);
}

/* The points of `part` are, in order, the points of `all` the filter keeps,
 * field by field. */
static long check_subset(const struct mpm_points *all, const struct mpm_points *part,
                         const struct half *h)
{
    long j = 0;
    for (long i = 0; i < all->n; i++) {
        if (!keep_half(h, all->x + 3 * i))
            continue;
        cr_assert_lt(j, part->n, "the filtered fill kept fewer points than it should");
        cr_assert_eq(part->id[j], all->id[i], "point %ld: id %ld, serial %ld", j,
                     (long)part->id[j], (long)all->id[i]);
        cr_assert_eq(memcmp(part->x + 3 * j, all->x + 3 * i, 3 * sizeof(double)), 0);
        cr_assert_eq(memcmp(part->v + 3 * j, all->v + 3 * i, 3 * sizeof(double)), 0);
        cr_assert_eq(part->mass[j], all->mass[i]);
        cr_assert_eq(part->vol0[j], all->vol0[i]);
        cr_assert_eq(part->body[j], all->body[i]);
        j++;
    }
    cr_assert_eq(j, part->n, "the filtered fill kept %ld points, %ld expected", part->n, j);
    return j;
}

static void check_split(void (*make_grid)(struct mpm *))
{
    struct mpm all, lower, upper;
    make_grid(&all);
    make_grid(&lower);
    make_grid(&upper);
    long n_all, kept_all, n_lo, kept_lo, n_up, kept_up;
    fill_sphere(&all, NULL, 101, &n_all, &kept_all);
    cr_assert_eq(kept_all, n_all);
    cr_assert_gt(n_all, 1000, "the sphere holds %ld points", n_all);
    for (long i = 0; i < all.pts.n; i++)   /* ids from first_id on, in order */
        cr_assert_eq(all.pts.id[i], 101 + i);
    struct half lo = {7.0, 0}, hi = {7.0, 1};
    struct mpm_fill_owner own_lo = {keep_half, &lo}, own_up = {keep_half, &hi};
    fill_sphere(&lower, &own_lo, 101, &n_lo, &kept_lo);
    fill_sphere(&upper, &own_up, 101, &n_up, &kept_up);
    cr_assert_eq(n_lo, n_all, "every rank counts the region's points: %ld, %ld", n_lo, n_all);
    cr_assert_eq(n_up, n_all);
    cr_assert_eq(kept_lo, lower.pts.n);
    cr_assert_eq(kept_up, upper.pts.n);
    cr_assert(kept_lo > 0 && kept_up > 0, "the plane cuts the sphere: %ld | %ld", kept_lo,
              kept_up);
    cr_assert_eq(kept_lo + kept_up, n_all, "the two halves hold %ld + %ld of %ld points",
                 kept_lo, kept_up, n_all);
    check_subset(&all.pts, &lower.pts, &lo);
    check_subset(&all.pts, &upper.pts, &hi);
    for (int k = 0; k < 3; k++)   /* the GIMP half-width is set on every rank */
        cr_assert_eq(lower.body[0].lp[k], all.body[0].lp[k]);
    mpm_free(&all);
    mpm_free(&lower);
    mpm_free(&upper);
}

static void uniform_grid(struct mpm *m)
{
    const long nc[3] = {16, 10, 10};
    th_mpm_uniform(m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 1);
}

/* Level 1 (coarsened along x, y, z) from x = 8: the sphere spans both. */
static void hier_grid(struct mpm *m)
{
    struct mpm_hlevel lv[1] = {
        {7, {.shape = REGION_SLAB, .axis = 0, .lo = {8, 0, 0}, .hi = {100, 0, 0}}},
    };
    const long nc[3] = {16, 10, 10};
    th_mpm_hier(m, nc, 1.0, lv, 1, MPM_HANGING_MODIFIED, th_mpm_faces_free, 1);
}

Test(mpm_build, owner_keeps_its_part_of_the_serial_points_uniform)
{
    check_split(uniform_grid);
}

Test(mpm_build, owner_keeps_its_part_of_the_serial_points_hierarchical)
{
    check_split(hier_grid);
    /* coarse cells' points are 8 times the fine ones' volume */
    struct mpm m;
    hier_grid(&m);
    long n, kept;
    fill_sphere(&m, NULL, 1, &n, &kept);
    double vmin = 1e300, vmax = 0;
    for (long i = 0; i < m.pts.n; i++) {
        vmin = m.pts.vol0[i] < vmin ? m.pts.vol0[i] : vmin;
        vmax = m.pts.vol0[i] > vmax ? m.pts.vol0[i] : vmax;
    }
    cr_assert_float_eq(vmin, 1.0 / 27.0, 1e-15);
    cr_assert_float_eq(vmax, 8.0 / 27.0, 1e-15);
    mpm_free(&m);
}
