/*
 * MPM/MD handshake beyond fcc copper (Guo & Yang 2005, section 2.3: pair,
 * many-body and three-body potentials): diamond silicon with Stillinger-
 * Weber and with Lenosky's meam/spline, bcc iron with Mendelev's EAM, fcc
 * argon with Lennard-Jones.
 *
 * - Uniform strain: a crystal strained homogeneously across the handshake
 *   at 0 K puts less than 1e-6 eV/Å on every MD atom and on every grid
 *   node that moves a material point; with region II left 0.01 Å behind
 *   (no displacement coupling) the MD atoms feel more than 1e-4 eV/Å.
 * - Three-body terms across the band: the copies of regions II and III are
 *   ordinary particles of the MD force loop, frozen in the integrator, so
 *   a region I atom gets every pair, triplet and embedding term in which it
 *   takes part, also those centred on a region II copy whose other legs
 *   are region III copies.  With every particle displaced at random, the
 *   forces on all MD atoms equal those of a larger all-atom crystal to
 *   round-off; without region III they do not (for the many-body and
 *   three-body potentials), which is why region III is there.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "couple/handshake.h"
#include "helpers/th.h"
#include "helpers/th_handshake.h"

#define POT_SW "style: sw\nfile: Si.sw\nelements: [Si]\n"
#define POT_MEAMS "style: meam/spline\nfile: Si_1.meam.spline\nelements: [Si]\n"
#define POT_FE "style: eam/fs\nfile: Fe_mm.eam.fs\nelements: [Fe]\n"
#define POT_LJ "style: lj\nelements: [Ar]\nepsilon: 0.0104\nsigma: 3.405\ncutoff: 8.5125\n"

struct material {
    const char *name, *pot, *element;
    enum hs_lattice lattice;
    double a_min, a_max;
    double regions[3];   /* lattice constants, each at least one cutoff */
};

static const struct material si_sw = {"Si sw", POT_SW, "Si", HS_LATTICE_DIAMOND, 5.2, 5.7,
                                      {2, 1, 1}};
static const struct material si_meam = {"Si meam/spline", POT_MEAMS, "Si", HS_LATTICE_DIAMOND,
                                        5.2, 5.7, {2, 1, 1}};
static const struct material fe_eam = {"Fe eam/fs", POT_FE, "Fe", HS_LATTICE_BCC, 2.7, 3.0,
                                       {2, 2, 2}};
static const struct material ar_lj = {"Ar lj", POT_LJ, "Ar", HS_LATTICE_FCC, 5.0, 5.6, {2, 2, 2}};

struct bar {
    struct handshake hs;
    struct md md;
    double a, cutoff;
};

/* A bar along x: MPM [0, len) with MD [md0, md1) (lattice constants),
 * cross-section w x w, periodic in MD and sliding in MPM, free x_hi end. */
static void bar_build(struct bar *b, const struct material *m, double len, double md0, double md1,
                      double w, double cell, int levels, unsigned coarsen, double fine,
                      double layer)
{
    memset(b, 0, sizeof *b);
    struct potential *pot = th_potential(m->pot);
    struct handshake_crystal cr;
    struct err e = {0};
    cr_assert_eq(handshake_crystal_of_lattice(pot, m->lattice, m->element, m->a_min, m->a_max,
                                              &cr, &b->a, &e),
                 0, "%s", e.msg);
    double a = b->a;
    b->cutoff = pot->cutoff;
    struct handshake_layout L;
    memset(&L, 0, sizeof L);
    L.lattice = m->lattice;
    L.a = a;
    for (int d = 0; d < 3; d++) {
        L.lat_origin[d] = hs_lattice_offset(m->lattice) * a;
        L.dom_lo[d] = L.mat_lo[d] = 0;
        L.dom_hi[d] = L.mat_hi[d] = (d == 0 ? len : w) * a;
        L.md_lo[d] = d == 0 ? md0 * a : 0;
        L.md_hi[d] = d == 0 ? md1 * a : w * a;
        L.md_periodic[d] = d != 0;
        L.w[d] = m->regions[d] * a;
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

/* The strain is 0.5e-4 along x (and -0.3e-4, 0.15e-4 across): the MPM is
 * linear and the MD is not, so the stresses on the two sides of an
 * interface differ at second order (Fe at 1e-4: 1.4e-6 eV/Å on the
 * interface nodes, a quarter of that at half the strain).
 *
 * On a uniform grid every node is checked.  With a coarse level, the cells
 * change from lattice-site points to eight points per cell at the first
 * coarse plane.  Two bcc sites or eight diamond sites per cell integrate
 * the shape-function gradients exactly except for the product term yz
 * (fcc's four do it exactly), which cancels over the four cells around a
 * node of that plane but not on the bar's lateral edges, where one cell
 * meets two sliding faces: those nodes are reported and bounded, not held
 * to 1e-6 (docs/handshake.md, Limits). */
static void check_uniform_strain(const struct material *m, int levels, double edge_bound)
{
    struct bar b;
    bar_build(&b, m, 24, 8, 16, 4, 1.0, levels, 7, 4, 4);
    struct err e = {0};
    double eps[3] = {0.5e-4, -0.3e-4, 0.15e-4}, o[3] = {0, 0, 0};
    cr_assert_eq(handshake_apply_strain(&b.hs, eps, o, &e), 0, "%s", e.msg);
    cr_assert_eq(handshake_map_forces(&b.hs, &e), 0, "%s", e.msg);
    long nn;
    double fedge;
    double fmd = th_hs_md_fmax(b.md.p), fg = th_hs_grid_fmax(&b.hs, &nn, &fedge);
    cr_log_info("%s, %d levels: max |f| MD %.3g eV/Å, grid %.3g eV/Å over %ld nodes, lateral "
                "edges %.3g eV/Å",
                m->name, levels, fmd, fg, nn, fedge);
    cr_expect_lt(fmd, 1e-6, "%s: MD atoms %g eV/Å", m->name, fmd);
    cr_expect_lt(fg, 1e-6, "%s: grid nodes %g eV/Å", m->name, fg);
    cr_expect_lt(fedge, edge_bound, "%s: lateral edge nodes %g eV/Å", m->name, fedge);
    cr_expect_gt(nn, 50, "nodes checked: %ld", nn);
    /* control: region II's copies 0.01 Å behind their points */
    struct particles *p = b.md.p;
    for (int i = 0; i < p->n_owned; i++)
        if (p->mask[i] & HS_MASK_II)
            p->x[3 * i] += p->x[3 * i] < b.hs.lay.md_lo[0] ? 0.01 : -0.01;
    cr_assert_eq(md_compute_forces(&b.md, &e), 0, "%s", e.msg);
    double fmd2 = th_hs_md_fmax(b.md.p);
    cr_expect_gt(fmd2, 1e-4, "%s: MD with region II left behind: %g eV/Å", m->name, fmd2);
    bar_free(&b);
}

Test(handshake_lattice, uniform_strain_si_sw, .timeout = 120)
{
    check_uniform_strain(&si_sw, 0, 1e-6);
    check_uniform_strain(&si_sw, 1, 4e-5);   /* measured 1.85e-5 */
}

Test(handshake_lattice, uniform_strain_si_meam_spline, .timeout = 120)
{
    check_uniform_strain(&si_meam, 0, 1e-6);
    check_uniform_strain(&si_meam, 1, 4e-5);
}

Test(handshake_lattice, uniform_strain_fe_eam, .timeout = 120)
{
    check_uniform_strain(&fe_eam, 0, 1e-6);
    check_uniform_strain(&fe_eam, 1, 6e-5);   /* measured 3.2e-5 */
}

/* fcc: exact on the edges too */
Test(handshake_lattice, uniform_strain_ar_lj, .timeout = 120)
{
    check_uniform_strain(&ar_lj, 0, 1e-6);
    check_uniform_strain(&ar_lj, 1, 1e-6);
}

/* A smooth but irregular displacement field (Å), the same function of the
 * reference position in both models. */
static void displacement(const double X[3], double u[3])
{
    for (int d = 0; d < 3; d++)
        u[d] = 0.04 * sin(1.7 * X[0] + 2.3 * X[1] + 0.9 * X[2] + d) +
               0.03 * sin(3.1 * X[1] - 1.3 * X[0] + 2.9 * X[2] + 2 * d) +
               0.02 * cos(2.6 * X[2] + 1.1 * X[0] - 3.7 * X[1] + 3 * d);
}

/* The all-atom crystal over x in [x_lo, x_hi) with the bar's cross-section,
 * periodic across, displaced by displacement(). */
static void reference_crystal(struct md *md, const struct bar *b, const struct material *m,
                              double x_lo, double x_hi)
{
    const struct handshake_layout *L = &b->hs.lay;
    double basis[8][3];
    int nb = hs_lattice_basis(L->lattice, basis);
    struct particles *p = particles_create(1024);
    cr_assert(p);
    int t = particles_type_index(p, m->element, b->hs.cr.mass);
    int64_t id = 1;
    long n0 = (long)floor((x_lo - L->lat_origin[0]) / L->a) - 1;
    long n1 = (long)ceil((x_hi - L->lat_origin[0]) / L->a) + 1;
    long nw = lround(L->md_hi[1] / L->a);
    for (long k = 0; k < nw; k++)
        for (long j = 0; j < nw; j++)
            for (long i = n0; i < n1; i++)
                for (int q = 0; q < nb; q++) {
                    double X[3] = {L->lat_origin[0] + (i + basis[q][0]) * L->a,
                                   L->lat_origin[1] + (j + basis[q][1]) * L->a,
                                   L->lat_origin[2] + (k + basis[q][2]) * L->a};
                    if (X[0] < x_lo || X[0] >= x_hi || X[1] >= L->md_hi[1] ||
                        X[2] >= L->md_hi[2])
                        continue;
                    double u[3], x[3];
                    displacement(X, u);
                    for (int d = 0; d < 3; d++)
                        x[d] = X[d] + u[d];
                    cr_assert_geq(particles_add(p, x, NULL, t, id++), 0);
                }
    struct box box = {{x_lo - 10, 0, 0},
                      {x_hi + 10, L->md_hi[1], L->md_hi[2]},
                      {BOUNDARY_FREE, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    th_md(md, p, &box, th_potential(m->pot), 1);
}

/* Largest |f_handshake - f_reference| over the MD atoms (core and I),
 * matched by reference position. */
static double force_difference(const struct bar *b, const struct md *ref)
{
    const struct particles *p = b->md.p, *r = ref->p;
    const double *x0 = p->fields[b->hs.f_x0].data;
    double dmax = 0;
    long matched = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III))
            continue;
        double u[3], x[3];
        displacement(x0 + 3 * i, u);
        for (int d = 0; d < 3; d++)
            x[d] = x0[3 * i + d] + u[d];
        for (int j = 0; j < r->n_owned; j++) {
            const double *y = r->x + 3 * j;
            if (fabs(y[0] - x[0]) + fabs(y[1] - x[1]) + fabs(y[2] - x[2]) > 1e-9)
                continue;
            for (int d = 0; d < 3; d++)
                dmax = fmax(dmax, fabs(p->f[3 * i + d] - r->f[3 * j + d]));
            matched++;
            break;
        }
    }
    cr_assert_eq(matched, b->hs.natoms, "matched %ld of %ld atoms", matched, b->hs.natoms);
    return dmax;
}

/* Every MD particle (atoms and the copies of regions II and III) displaced
 * irregularly: the forces on the MD atoms equal those of an all-atom
 * crystal reaching two cutoffs beyond region III.  Control: the copies
 * farther than one cutoff from every MD atom taken away.  Pair forces do
 * not see them; three-body terms centred on a region II copy j with legs
 * to a region I atom i and to such a copy k do (and so do embedding terms
 * whose density at j they supply), so there the forces change. */
static void check_band_forces(const struct material *m, int far_matters)
{
    struct bar b;
    bar_build(&b, m, 14, 4, 10, 4, 1.0, 0, 7, 4, 4);
    struct particles *p = b.md.p;
    const double *x0 = p->fields[b.hs.f_x0].data;
    for (int i = 0; i < p->n_owned; i++) {
        double u[3];
        displacement(x0 + 3 * i, u);
        for (int d = 0; d < 3; d++)
            p->x[3 * i + d] = x0[3 * i + d] + u[d];
    }
    struct err e = {0};
    b.md.nl->nbuilds = 0;
    cr_assert_eq(md_compute_forces(&b.md, &e), 0, "%s", e.msg);
    const struct handshake_layout *L = &b.hs.lay;
    double reach = L->w[1] + L->w[2] + 2 * b.cutoff;
    struct md ref;
    reference_crystal(&ref, &b, m, L->md_lo[0] - reach, L->md_hi[0] + reach);
    double df = force_difference(&b, &ref);
    /* control: the copies out of every MD atom's reach go far away (the
     * bar is periodic across, so distances across are minimum images) */
    const double W = L->md_hi[1];
    long nfar = 0;
    for (int k = 0; k < p->n_owned; k++) {
        if (!(p->mask[k] & (HS_MASK_II | HS_MASK_III)))
            continue;
        double dmin = INFINITY;
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & (HS_MASK_II | HS_MASK_III))
                continue;
            double r2 = 0;
            for (int d = 0; d < 3; d++) {
                double dx = p->x[3 * k + d] - p->x[3 * i + d];
                if (d > 0)
                    dx -= W * round(dx / W);
                r2 += dx * dx;
            }
            dmin = fmin(dmin, r2);
        }
        if (sqrt(dmin) > b.cutoff) {
            p->x[3 * k] += p->x[3 * k] < L->md_lo[0] ? -50 : 50;
            nfar++;
        }
    }
    b.md.nl->nbuilds = 0;
    cr_assert_eq(md_compute_forces(&b.md, &e), 0, "%s", e.msg);
    double dfar = force_difference(&b, &ref);
    cr_log_info("%s: forces on the MD atoms against an all-atom crystal: %.3g eV/Å; without the "
                "%ld copies beyond one cutoff of every atom %.3g eV/Å",
                m->name, df, nfar, dfar);
    cr_expect_lt(df, 1e-9, "%s: %g eV/Å", m->name, df);
    cr_expect_gt(nfar, 0);
    if (far_matters)
        cr_expect_gt(dfar, 1e-3, "%s without the far copies: %g eV/Å", m->name, dfar);
    else
        cr_expect_lt(dfar, 1e-9, "%s without the far copies: %g eV/Å", m->name, dfar);
    md_free(&ref);
    bar_free(&b);
}

/* SW: the second neighbour shell (3.84 Å) lies beyond the cutoff (3.77 Å),
 * so a copy two bonds out is no neighbour of any atom, yet closes a triplet
 * centred on a copy one bond out: without it the forces change by 0.09
 * eV/Å. */
Test(handshake_lattice, three_body_terms_across_the_band_si_sw, .timeout = 120)
{
    check_band_forces(&si_sw, 1);
}

/* meam/spline (Si_1): the same equality to round-off.  Its three-body and
 * density functions end before the second shell, which its pair term
 * (cutoff 4.5 Å) reaches, so every leg of a term that acts on an MD atom
 * lies within one cutoff of one: the far copies change nothing. */
Test(handshake_lattice, three_body_terms_across_the_band_si_meam_spline, .timeout = 120)
{
    check_band_forces(&si_meam, 0);
}

/* EAM: the density at a region II copy includes copies beyond the cutoff
 * from every atom. */
Test(handshake_lattice, embedding_across_the_band_fe_eam, .timeout = 120)
{
    check_band_forces(&fe_eam, 1);
}

Test(handshake_lattice, pair_forces_across_the_band_ar_lj, .timeout = 120)
{
    check_band_forces(&ar_lj, 0);
}
