/*
 * Hierarchical MPM grid (Guo & Yang 2005, section 2.1): cells coarsening by
 * 2 per level in 1, 2 or 3 directions, 2:1 balance, hanging nodes.
 *
 * - A uniform stress gives zero internal force on every interior node with
 *   the modified (|.|) shape functions of Eq. (11), and clearly non-zero
 *   forces on the hanging nodes with the standard functions of Eq. (9) --
 *   the paper's point.
 * - The shape functions form a partition of unity, reproduce linear fields
 *   and have gradients summing to zero in every cell.
 * - Five levels build, neighbouring cells differ by at most a factor two
 *   (levels asked to jump are refined), and mass maps exactly.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "helpers/th_mpm.h"
#include "mpm/mpm_shape.h"

/* Grid 16 x 8 x 8 with level 1 from x = 8 and level 2 from x = 12. */
static void two_level_model(struct mpm *m, unsigned coarsen, enum mpm_hanging hanging)
{
    struct mpm_hlevel lv[2] = {
        {coarsen, {.shape = REGION_SLAB, .axis = 0, .lo = {8, 0, 0}, .hi = {100, 0, 0}}},
        {coarsen, {.shape = REGION_SLAB, .axis = 0, .lo = {12, 0, 0}, .hi = {100, 0, 0}}},
    };
    long nc[3] = {16, 8, 8};
    th_mpm_hier(m, nc, 1.0, lv, 2, hanging, th_mpm_faces_free, 1);
    int mat = th_mpm_material(m, mpm_material_linear_elastic("s", 0.05, 1.0, 0.3));
    double lo[3] = {0, 0, 0}, hi[3] = {16, 8, 8};
    th_mpm_box(m, "block", mat, lo, hi, 2, NULL, 0);
}

/* Largest |f| over nodes off the domain boundary after mapping a uniform
 * stress; *nhang counts interior nodes that are hanging (mid-edge/face). */
static double interior_force(struct mpm *m, long *nhang)
{
    struct err e = {0};
    for (long p = 0; p < m->pts.n; p++) {
        double *s = m->pts.stress + 6 * p;
        s[0] = 1.0, s[1] = 0.5, s[2] = 0.3, s[3] = 0.2, s[4] = 0.1, s[5] = 0.05;
    }
    cr_assert_eq(mpm_locate_particles(m, &e), 0, "%s", e.msg);
    mpm_clear_grid(m);
    mpm_map_to_grid(m, MPM_MAP_ALL);
    struct mpm_hgrid *hg = m->grid.hg;
    double fbig = 0;
    for (long i = 0; i < m->grid.nnodes; i++) {
        const int32_t *ijk = hg->node_ijk + 3 * i;
        if (ijk[0] == 0 || ijk[0] == 16 || ijk[1] == 0 || ijk[1] == 8 || ijk[2] == 0 || ijk[2] == 8)
            continue;
        const double *f = m->grid.node[i].f;
        fbig = fmax(fbig, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    }
    /* hanging nodes: lie inside the closure of a coarser cell without being its corner */
    *nhang = 0;
    for (long c = 0; c < hg->ncell; c++)
        for (int q = 0; q < 27; q++) {
            int a = q % 3, b = (q / 3) % 3, cc = q / 9;
            if ((a == 1 || b == 1 || cc == 1) && mpm_hgrid_nodes(hg, c)[q] >= 0)
                (*nhang)++;
        }
    return fbig;
}

Test(mpm_hier, uniform_stress_gives_no_force_with_modified_functions)
{
    /* coarsening in 3 (Fig. 1c), 2 (Fig. 1b) and 1 direction(s) */
    const unsigned masks[3] = {7, 3, 6};
    for (int k = 0; k < 3; k++) {
        struct mpm m;
        two_level_model(&m, masks[k], MPM_HANGING_MODIFIED);
        long nhang;
        double f = interior_force(&m, &nhang);
        /* scale: sigma V / h of a fine point = 1 * 0.125 / 1 */
        cr_assert(nhang > 0, "coarsening %u made no hanging node", masks[k]);
        cr_assert(f < 1e-12, "coarsening %u: interior force %g with the modified functions",
                  masks[k], f);
        mpm_free(&m);
    }
}

Test(mpm_hier, uniform_stress_gives_artificial_force_with_standard_functions)
{
    const unsigned masks[3] = {7, 3, 6};
    for (int k = 0; k < 3; k++) {
        struct mpm m;
        two_level_model(&m, masks[k], MPM_HANGING_STANDARD);
        long nhang;
        double f = interior_force(&m, &nhang);
        /* Guo & Yang: the quadratic bubbles of Eq. (9) are not integrated
         * exactly by the points at +-1/2, leaving forces on hanging nodes of
         * the order of the stress times a coarse face area */
        cr_assert(f > 0.1, "coarsening %u: standard functions gave only %g", masks[k], f);
        mpm_free(&m);
    }
}

Test(mpm_hier, shape_functions_partition_of_unity_and_linear)
{
    struct mpm m;
    two_level_model(&m, 7, MPM_HANGING_MODIFIED);
    struct mpm_hgrid *hg = m.grid.hg;
    unsigned s = 12345;
    for (long c = 0; c < hg->ncell; c++) {
        const struct mpm_hcell *cl = &hg->cell[c];
        mpm_hgrid_nodes(hg, c);   /* the locate step makes the tables of its cells */
        for (int t = 0; t < 5; t++) {
            double x[3];
            for (int d = 0; d < 3; d++) {
                s = s * 1103515245u + 12345u;
                double u = (s >> 8) / 16777216.0;
                x[d] = cl->lo[d] + u * (1 << cl->lg[d]);
            }
            struct mpm_stencil st;
            mpm_stencil_hier(&m.grid, c, x, &st);
            double sum = 0, g[3] = {0}, lin[3] = {0}, dlin[3][3] = {{0}};
            for (int k = 0; k < st.n; k++) {
                double xi[3];
                mpm_grid_node_position(&m.grid, st.node[k], xi);
                sum += st.w[k];
                g[0] += st.gx[k], g[1] += st.gy[k], g[2] += st.gz[k];
                for (int d = 0; d < 3; d++) {
                    lin[d] += st.w[k] * xi[d];
                    dlin[d][0] += st.gx[k] * xi[d];
                    dlin[d][1] += st.gy[k] * xi[d];
                    dlin[d][2] += st.gz[k] * xi[d];
                }
            }
            cr_assert(fabs(sum - 1) < 1e-13, "cell %ld: sum N = %.17g", c, sum);
            for (int d = 0; d < 3; d++) {
                cr_assert(fabs(g[d]) < 1e-13, "cell %ld: sum G_%d = %g", c, d, g[d]);
                cr_assert(fabs(lin[d] - x[d]) < 1e-12, "cell %ld: x_%d not reproduced", c, d);
                for (int b = 0; b < 3; b++)
                    cr_assert(fabs(dlin[d][b] - (d == b)) < 1e-12, "cell %ld: grad x wrong", c);
            }
        }
    }
    mpm_free(&m);
}

/* Cells without hanging nodes (most of a graded grid) take a short path in
 * mpm_stencil_hier: there the stencil is the 8 corners in candidate order
 * with the trilinear weights and gradients of the cell, as the general
 * path gives; cells with hanging nodes keep their midpoint nodes. */
Test(mpm_hier, cells_without_hanging_nodes_give_the_trilinear_corners)
{
    struct mpm m;
    two_level_model(&m, 7, MPM_HANGING_MODIFIED);
    struct mpm_hgrid *hg = m.grid.hg;
    long plain = 0, hanging = 0;
    for (long c = 0; c < hg->ncell; c++) {
        const struct mpm_hcell *cl = &hg->cell[c];
        const int32_t *node = mpm_hgrid_nodes(hg, c);
        int nmid = 0;
        for (int q = 0; q < 27; q++)
            if ((q % 3 == 1 || (q / 3) % 3 == 1 || q / 9 == 1) && node[q] >= 0)
                nmid++;
        double x[3], t[3], size[3];
        for (int d = 0; d < 3; d++) {
            size[d] = (double)(1 << cl->lg[d]);
            t[d] = 0.3 + 0.2 * d;
            x[d] = cl->lo[d] + t[d] * size[d];
        }
        struct mpm_stencil st;
        mpm_stencil_hier(&m.grid, c, x, &st);
        if (nmid > 0) {
            hanging++;
            cr_assert_eq(st.n, 8 + nmid, "cell %ld: %d nodes for 8 corners and %d midpoints", c,
                         st.n, nmid);
            continue;
        }
        plain++;
        cr_assert_eq(st.n, 8, "cell %ld: %d nodes", c, st.n);
        for (int k = 0; k < 8; k++) {
            int a[3] = {k & 1, (k >> 1) & 1, k >> 2};
            cr_assert_eq(st.node[k], node[2 * a[0] + 6 * a[1] + 18 * a[2]], "cell %ld corner %d",
                         c, k);
            double w = 1, g[3] = {1, 1, 1};
            for (int d = 0; d < 3; d++) {
                double wd = a[d] ? t[d] : 1 - t[d], dd = (a[d] ? 1.0 : -1.0) / size[d];
                w *= wd;
                for (int e = 0; e < 3; e++)
                    g[e] *= e == d ? dd : wd;
            }
            cr_assert(fabs(st.w[k] - w) < 1e-14, "cell %ld corner %d: N = %.17g, not %.17g", c, k,
                      st.w[k], w);
            cr_assert(fabs(st.gx[k] - g[0]) < 1e-14 && fabs(st.gy[k] - g[1]) < 1e-14 &&
                          fabs(st.gz[k] - g[2]) < 1e-14,
                      "cell %ld corner %d: gradient (%g %g %g), not (%g %g %g)", c, k, st.gx[k],
                      st.gy[k], st.gz[k], g[0], g[1], g[2]);
        }
    }
    cr_assert(plain > 0 && hanging > 0, "%ld plain and %ld hanging cells: both paths wanted", plain,
              hanging);
    mpm_free(&m);
}

/* Every node on the closed boundary of a cell is a corner, an edge
 * midpoint or a face centre of that cell (brute force). */
static void assert_balanced(const struct mpm_hgrid *hg)
{
    for (long c = 0; c < hg->ncell; c++) {
        const struct mpm_hcell *cl = &hg->cell[c];
        long s[3] = {1L << cl->lg[0], 1L << cl->lg[1], 1L << cl->lg[2]};
        for (long i = 0; i < hg->nnodes; i++) {
            const int32_t *ijk = hg->node_ijk + 3 * i;
            int inside = 1, ok = 1;
            for (int d = 0; d < 3; d++) {
                long u = ijk[d] - cl->lo[d];
                if (u < 0 || u > s[d])
                    inside = 0;
                else if (!(u == 0 || u == s[d] || 2 * u == s[d]))
                    ok = 0;
            }
            cr_assert(!inside || ok, "node (%d %d %d) lies on cell %ld (lo %d %d %d, size %ld %ld %ld) "
                      "at a position the shape functions do not know",
                      ijk[0], ijk[1], ijk[2], c, cl->lo[0], cl->lo[1], cl->lo[2], s[0], s[1], s[2]);
        }
    }
}

Test(mpm_hier, five_levels_balanced_and_mass_exact)
{
    /* nested slabs 32 fine cells apart: levels 1..5 coarsening in x, y, z,
     * then x, y, then x only (cells 2x2x2, 4x4x4, 8x8x4, 16x8x4, 32x8x4) */
    const unsigned mask[5] = {7, 7, 3, 1, 1};
    struct mpm_hlevel lv[5];
    for (int l = 0; l < 5; l++) {
        lv[l].coarsen = mask[l];
        lv[l].region = (struct region){.shape = REGION_SLAB, .axis = 0,
                                       .lo = {16.0 + 32.0 * l, 0, 0}, .hi = {1e9, 0, 0}};
    }
    long nc[3] = {208, 16, 8};
    struct mpm m;
    th_mpm_hier(&m, nc, 1.0, lv, 5, MPM_HANGING_MODIFIED, th_mpm_faces_free, 1);
    const struct mpm_hgrid *hg = m.grid.hg;
    for (int l = 0; l <= 5; l++)
        cr_assert(hg->ncell_level[l] > 0, "no cell of level %d", l);
    assert_balanced(hg);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", 0.05, 1.0, 0.3));
    double lo[3] = {0, 0, 0}, hi[3] = {208, 16, 8}, v[3] = {1, -2, 0.5};
    th_mpm_box(&m, "block", mat, lo, hi, 2, v, 0);
    struct err e = {0};
    cr_assert_eq(mpm_locate_particles(&m, &e), 0, "%s", e.msg);
    mpm_clear_grid(&m);
    mpm_map_to_grid(&m, MPM_MAP_ALL);
    double mp = 0, mg = 0, pg[3] = {0};
    for (long p = 0; p < m.pts.n; p++)
        mp += m.pts.mass[p];
    for (long i = 0; i < m.grid.nnodes; i++) {
        mg += m.grid.node[i].m;
        for (int d = 0; d < 3; d++)
            pg[d] += m.grid.node[i].q[d];
    }
    /* total volume 208 x 16 x 8 at density 0.05 */
    cr_assert(fabs(mp - 0.05 * 208 * 16 * 8) < 1e-9 * mp, "point mass %g", mp);
    cr_assert(fabs(mg - mp) < 1e-13 * mp, "grid mass %.17g vs points %.17g", mg, mp);
    for (int d = 0; d < 3; d++)
        cr_assert(fabs(pg[d] - mp * v[d]) < 1e-13 * mp * 2, "momentum %d", d);
    mpm_free(&m);
}

Test(mpm_hier, unbalanced_levels_are_refined)
{
    /* levels 1 and 2 asked for the same region: level-2 cells would touch
     * finest cells directly, so the builder must put level-1 cells between */
    struct mpm_hlevel lv[2] = {
        {7, {.shape = REGION_SLAB, .axis = 0, .lo = {16, 0, 0}, .hi = {100, 0, 0}}},
        {7, {.shape = REGION_SLAB, .axis = 0, .lo = {16, 0, 0}, .hi = {100, 0, 0}}},
    };
    long nc[3] = {48, 16, 16};
    struct mpm m;
    th_mpm_hier(&m, nc, 1.0, lv, 2, MPM_HANGING_MODIFIED, th_mpm_faces_free, 1);
    const struct mpm_hgrid *hg = m.grid.hg;
    cr_assert(hg->ncell_level[1] > 0, "no transition cells were made");
    cr_assert(hg->ncell_level[2] > 0);
    assert_balanced(hg);
    mpm_free(&m);
}
