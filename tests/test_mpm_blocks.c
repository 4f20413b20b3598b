/*
 * The colouring blocks of the uniform grid (mpm_grid.c): threads scatter
 * the points of the blocks of one colour into the nodes at the same time,
 * so no two blocks of a colour may reach a common node.  For linear shape
 * functions a block's points touch the nodes of their cells (key k: nodes
 * k, k + 1) and, in the fused update-and-map pass, of the cells one either
 * side of the block (points move less than a cell per step): nodes
 * [k0 - 1, k1 + 1] for keys [k0, k1).  For GIMP (key = base node + 1:
 * nodes key - 1 .. key + 1): nodes [k0 - 1, k1].  Checked node by node on
 * the reference grid (61 x 35 x 35 cells: cut across y and z only), on the
 * threads test's grid (40 x 12 x 10: too thin, cut along x too) and on
 * grids narrower than a block.  And the order of a colour's blocks for the
 * threads: most particles first, ties by block index.
 */
#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

#include "mpm/mpm_grid.h"

/* Every node of the (padded) lattice is reached by at most one block of
 * each colour, and every key lies in exactly one block. */
static void check_disjoint(const long nc[3], enum mpm_shape_kind shape)
{
    struct mpm_grid g;
    struct err e = {0};
    const double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_grid_init_uniform(&g, origin, 1.0, nc, shape, &e), 0, "%s", e.msg);
    long ext[3], total = 0;
    for (int d = 0; d < 3; d++)
        ext[d] = g.nkeys[d] + 3;   /* nodes -1 .. nkeys + 1 */
    long nlat = ext[0] * ext[1] * ext[2];
    int *owner = malloc((size_t)nlat * sizeof *owner);
    cr_assert_not_null(owner);
    for (int c = 0; c < MPM_COLOURS; c++) {
        for (long i = 0; i < nlat; i++)
            owner[i] = -1;
        total += g.ncolour[c];
        for (long bi = 0; bi < g.ncolour[c]; bi++) {
            long b = g.colour_block[c][bi], r = b, lo[3], hi[3];
            for (int d = 0; d < 3; d++) {
                long bc = r % g.nb[d];
                r /= g.nb[d];
                long k0 = bc * g.bw[d], k1 = (bc + 1) * g.bw[d];
                if (k1 > g.nkeys[d])
                    k1 = g.nkeys[d];
                cr_assert(k0 < k1, "empty block %ld along %d", b, d);
                lo[d] = k0 - 1;
                hi[d] = shape == MPM_SHAPE_LINEAR ? k1 + 1 : k1;
                cr_assert_eq(((bc & 1) << d), (long)(c & (1 << d)), "block %ld in colour %d", b, c);
            }
            for (long z = lo[2]; z <= hi[2]; z++)
                for (long y = lo[1]; y <= hi[1]; y++)
                    for (long x = lo[0]; x <= hi[0]; x++) {
                        long i = ((z + 1) * ext[1] + y + 1) * ext[0] + x + 1;
                        cr_assert(owner[i] < 0,
                                  "grid %ld x %ld x %ld: node (%ld %ld %ld) reached by blocks "
                                  "%d and %ld of colour %d",
                                  nc[0], nc[1], nc[2], x, y, z, owner[i], b, c);
                        owner[i] = (int)b;
                    }
        }
    }
    cr_assert_eq(total, g.nblocks);
    /* keys to blocks: the block the table gives holds the key */
    for (long z = 0; z < g.nkeys[2]; z++)
        for (long y = 0; y < g.nkeys[1]; y++)
            for (long x = 0; x < g.nkeys[0]; x++) {
                long key[3] = {x, y, z};
                long b = mpm_grid_key_block(&g, key);
                cr_assert(b >= 0 && b < g.nblocks);
                cr_assert_eq(b % g.nb[0], x / g.bw[0]);
                cr_assert_eq(b / g.nb[0] % g.nb[1], y / g.bw[1]);
                cr_assert_eq(b / (g.nb[0] * g.nb[1]), z / g.bw[2]);
            }
    free(owner);
    mpm_grid_free(&g);
}

Test(mpm_blocks, reference_grid_cut_across_y_and_z)
{
    long nc[3] = {61, 35, 35};
    check_disjoint(nc, MPM_SHAPE_LINEAR);
    struct mpm_grid g;
    struct err e = {0};
    const double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_grid_init_uniform(&g, origin, 1.0, nc, MPM_SHAPE_LINEAR, &e), 0);
    cr_assert_eq(g.nb[0], 1, "whole rows along x");
    cr_assert_eq(g.nb[1], 12);
    cr_assert_eq(g.nb[2], 12);
    mpm_grid_free(&g);
}

Test(mpm_blocks, thin_grids_cut_along_x_too)
{
    long thin[3] = {40, 12, 10};
    check_disjoint(thin, MPM_SHAPE_LINEAR);
    check_disjoint(thin, MPM_SHAPE_GIMP);
    struct mpm_grid g;
    struct err e = {0};
    const double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_grid_init_uniform(&g, origin, 1.0, thin, MPM_SHAPE_LINEAR, &e), 0);
    cr_assert_geq(g.nblocks, 64, "%ld blocks", g.nblocks);
    cr_assert_gt(g.nb[0], 1);
    mpm_grid_free(&g);
    long tiny[3] = {2, 1, 4}, bar[3] = {200, 3, 3};
    check_disjoint(tiny, MPM_SHAPE_LINEAR);
    check_disjoint(tiny, MPM_SHAPE_GIMP);
    check_disjoint(bar, MPM_SHAPE_LINEAR);
    check_disjoint(bar, MPM_SHAPE_GIMP);
}

Test(mpm_blocks, colours_take_the_largest_blocks_first)
{
    long nc[3] = {12, 12, 12};
    struct mpm_grid g;
    struct err e = {0};
    const double origin[3] = {0, 0, 0};
    cr_assert_eq(mpm_grid_init_uniform(&g, origin, 1.0, nc, MPM_SHAPE_LINEAR, &e), 0);
    /* two sets of particles; block b holds (b * 7) % 5 + (b % 3) of them */
    long *s0 = calloc((size_t)g.nblocks + 1, sizeof *s0), *s1 = calloc((size_t)g.nblocks + 1, sizeof *s1);
    cr_assert(s0 && s1);
    for (long b = 0; b < g.nblocks; b++) {
        s0[b + 1] = s0[b] + (b * 7) % 5;
        s1[b + 1] = s1[b] + b % 3;
    }
    const long *starts[2] = {s0, s1};
    mpm_grid_order_blocks(&g, starts, 2);
    long seen = 0;
    for (int c = 0; c < MPM_COLOURS; c++) {
        for (long i = 0; i < g.ncolour[c]; i++) {
            long b = g.colour_block[c][i];
            cr_assert_eq(b % g.nb[0] & 1, c & 1);
            seen++;
            if (i == 0)
                continue;
            long a = g.colour_block[c][i - 1];
            long wa = (a * 7) % 5 + a % 3, wb = (b * 7) % 5 + b % 3;
            cr_assert(wa > wb || (wa == wb && a < b), "colour %d: block %ld (%ld) before %ld (%ld)",
                      c, a, wa, b, wb);
        }
    }
    cr_assert_eq(seen, g.nblocks);
    free(s0);
    free(s1);
    mpm_grid_free(&g);
}
