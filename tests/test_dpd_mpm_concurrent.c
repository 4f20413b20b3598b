/*
 * The concurrent DPD/MPM model (couple/dpd_mpm.h; Chen et al. 2014, Eqs.
 * (3.1)-(3.4)): DPD particles and material points in one block on one grid.
 * - A block compressed uniformly by 0.5 %, half DPD particles at 0 K, half
 *   material points with the cubic law whose constants cg_lattice computes
 *   from the same coarse-grained potential, stressed accordingly: the DPD
 *   particles near the interface feel no force (their partners complete
 *   the crystal), and the net nodal force across the interface is the
 *   difference between the DPD and the linear stress (5 %) of the
 *   traction a free end carries -- without the DPD particles' pair forces
 *   on the material points (Chen's Eq. (3.1) read one-sided) it is the
 *   whole traction.
 * - Total momentum of DPD particles and material points is conserved while
 *   thermal DPD particles push on the material points.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/lattice.h"
#include "core/units.h"
#include "core/velocity.h"
#include "couple/dpd_mpm.h"
#include "dpd/cg_lattice.h"
#include "helpers/th_dpd.h"

#define PARTNER_BIT (1u << 5)
#define ID0 1000000

struct concurrent {
    struct dpd d;
    struct dpd_mpm c;
    double a, L[3], c11, c12, c44;
};

/* nx x ny x nz fcc cells of edge a = (1 - strain) a0 (a0: the static
 * zero-pressure lattice constant); particles with x >= split L become
 * material points under the stress of that strain; partners when asked. */
static void build(struct concurrent *s, const long n[3], double strain, double split,
                  int partners, double T)
{
    struct cg_params prm;
    th_cg_params(&prm);
    double a0;
    cr_assert_eq(cg_lattice_solve_pressure(&prm.sc, 0, 0, 0.0, 6.5, 8.0, &a0), 0);
    cg_lattice_elastic(&prm.sc, a0, &s->c11, &s->c12, &s->c44);
    s->a = (1 - strain) * a0;
    struct lattice l = {LATTICE_FCC, s->a, {0, 0, 0}, {{0}}};
    struct particles *all = particles_create(64);
    int t = particles_type_index(all, "Cu", prm.mass);
    int64_t id = 1;
    struct err e = {0};
    cr_assert(lattice_fill(&l, n, NULL, all, t, &id, &e) > 0);
    struct box box = {0};
    for (int k = 0; k < 3; k++) {
        s->L[k] = n[k] * s->a;
        box.lo[k] = 0;
        box.hi[k] = s->L[k];
        box.bc[k] = BOUNDARY_FREE;
    }
    struct particles *p = particles_create(64);
    particles_type_index(p, "Cu", prm.mass);
    long np = 0;
    double *xp = malloc((size_t)3 * all->n_owned * sizeof *xp);
    int64_t *ip = malloc((size_t)all->n_owned * sizeof *ip);
    for (int i = 0; i < all->n_owned; i++) {
        if (all->x[3 * i] >= split * s->L[0]) {
            memcpy(xp + 3 * np, all->x + 3 * i, 3 * sizeof(double));
            ip[np++] = all->id[i];
        } else {
            static const double v0[3] = {0, 0, 0};
            cr_assert(particles_add(p, all->x + 3 * i, v0, 0, all->id[i]) >= 0);
        }
    }
    particles_destroy(&all);
    int nd = p->n_owned;
    long added = 0;
    if (partners)
        cr_assert_eq(dpd_mpm_partners_create(p, nd, np, xp, ip, 2 * prm.sc.rc + 1.0, PARTNER_BIT,
                                             ID0, &added, &e),
                     0, "%s", e.msg);
    /* at 0 K: no dissipative or random force, only the conservative one */
    struct dpd_settings set = T > 0 ? th_dpd_settings(DPD_ENERGY, 0.2, T)
                                    : th_dpd_settings(DPD_ISOTHERMAL, 0.0, 0.0);
    cr_assert_eq(dpd_init(&s->d, p, &box, &prm, &set, 0.005, 1.0, 1, 3, &e), 0, "%s", e.msg);
    s->d.passive_mask = PARTNER_BIT;
    if (T > 0) {
        /* thermal DPD particles only (partners keep their points' rest) */
        for (int i = 0; i < s->d.p->n_owned; i++)
            if (s->d.p->mask[i] & PARTNER_BIT)
                s->d.p->mask[i] &= ~1u;
        cr_assert_eq(velocity_maxwell(s->d.p, T, 9, 1u, &e), 0);
    }
    cr_assert_eq(dpd_mpm_order(&s->d, PARTNER_BIT, &e), 0, "%s", e.msg);
    /* cells of a/2 with the (100) planes at their centres: a free end's
     * nodal traction is then sigma A exactly (with cells of other sizes it
     * is sigma A times the share of the material in the last cell) */
    double h = 0.5 * s->a;
    struct dpd_mpm_grid g = {h, {0, 0, 0}, {0, 0, 0}, 1e-12};
    for (int k = 0; k < 3; k++) {
        g.lo[k] = -2.25 * h;
        g.ncell[k] = (long)ceil((s->L[k] + 5 * h) / g.cell);
    }
    cr_assert_eq(dpd_mpm_init(&s->c, &s->d, &g, PARTNER_BIT, ID0, &e), 0, "%s", e.msg);
    cr_assert_eq(s->c.npartner, added);
    double rho = prm.mass / (s->a * s->a * s->a / 4);
    struct mpm_material *mat = mpm_material_cubic_elastic("cg", rho, s->c11, s->c12, s->c44);
    cr_assert_eq(dpd_mpm_add_points(&s->c, mat, np, xp, NULL, prm.mass, s->a * s->a * s->a / 4,
                                    ip, &e),
                 0, "%s", e.msg);
    cr_assert_eq(dpd_mpm_prepare(&s->c, &e), 0, "%s", e.msg);
    /* hydrostatic strain -strain: sigma = (C11 + 2 C12) (-strain) on the diagonal */
    double sig = -(s->c11 + 2 * s->c12) * strain;
    for (long k = 0; k < s->c.m.pts.n; k++) {
        double *st = s->c.m.pts.stress + 6 * k;
        st[0] = st[1] = st[2] = sig;
        st[3] = st[4] = st[5] = 0;
    }
    free(xp);
    free(ip);
}

static void destroy(struct concurrent *s)
{
    dpd_mpm_free(&s->c);
    dpd_free(&s->d);
}

/* The nodal forces of the current state (one mapping: DPD forces N_i,
 * the points' stress, and -- with `reactions` -- the DPD particles' pair
 * forces on the material points at the points): the sum of f_x over the
 * interior (y, z) nodes within two cutoffs of the interface at xi, over
 * the same sum at the material's free end (its traction sigma_xx A). */
static double interface_net_force(struct concurrent *s, double xi, int reactions)
{
    struct dpd_mpm *c = &s->c;
    struct err e = {0};
    cr_assert_eq(dpd_pair_forces(&s->d, s->d.dt, c->f, &e), 0, "%s", e.msg);
    memset(c->m.pts.fext, 0, (size_t)c->m.pts.n * 3 * sizeof(double));
    for (long k = 0; reactions && k < c->npartner; k++)
        for (int q = 0; q < 3; q++)
            c->m.pts.fext[3 * c->partner_point[k] + q] += c->f[3 * (c->ncarried + k) + q];
    c->extra.force = c->f;
    c->extra.x = s->d.p->x;
    c->extra.v = s->d.p->v;
    mpm_points_moved(&c->m);
    cr_assert_eq(mpm_locate_particles(&c->m, &e), 0, "%s", e.msg);
    mpm_clear_grid(&c->m);
    mpm_map_to_grid(&c->m, MPM_MAP_ALL);
    const struct mpm_grid *g = &c->m.grid;
    double h = g->h, rc = s->d.prm.sc.rc, margin = rc + h;
    double zone = 0, end = 0, dpd_side = 0;
    for (long i = 0; i < g->nnodes; i++) {
        double x[3];
        mpm_grid_node_position(g, i, x);
        if (x[1] < margin || x[1] > s->L[1] - margin || x[2] < margin || x[2] > s->L[2] - margin)
            continue;
        double fx = g->node[i].f[0];
        if (fabs(x[0] - xi) < 2 * rc)
            zone += fx;
        if (x[0] > s->L[0] - 2 * h)
            end += fx;
        if (x[0] > xi - rc && x[0] < xi - h)
            dpd_side = fmax(dpd_side, fabs(fx));
    }
    cr_assert(fabs(end) > 1.0, "no traction at the free end (%g eV/Å)", end);
    /* DPD particles near the interface: the partners complete their crystal */
    cr_assert(dpd_side < 1e-9 * fabs(end), "force %g eV/Å on the DPD side", dpd_side);
    return zone / fabs(end);
}

Test(dpd_mpm_concurrent, uniform_compression_balances_at_the_interface)
{
    long n[3] = {8, 10, 10};
    struct concurrent s;
    build(&s, n, 0.005, 0.5, 1, 0);
    double with = interface_net_force(&s, 0.5 * s.L[0], 1);
    double without = interface_net_force(&s, 0.5 * s.L[0], 0);
    destroy(&s);
    /* the DPD stress at this strain exceeds the linear cubic law's by
     * 4.9 % (cg_lattice): that much is left */
    cr_assert(fabs(with) < 0.08, "net interface force %.3g of the traction sigma A", with);
    cr_assert(fabs(without) > 0.9, "without the reactions only %.3g", without);
}

Test(dpd_mpm_concurrent, total_momentum_is_conserved)
{
    long n[3] = {6, 4, 4};
    struct concurrent s;
    build(&s, n, 0.0, 0.5, 1, 298);
    struct err e = {0};
    double P0[3], P1[3], scale = 0;
    dpd_mpm_momentum(&s.c, P0);
    for (long i = 0; i < s.c.ncarried; i++)
        scale += s.d.p->mass[0] * fabs(s.d.p->v[3 * i]);
    for (int k = 0; k < 100; k++)
        cr_assert_eq(dpd_mpm_step(&s.c, &e), 0, "%s", e.msg);
    dpd_mpm_momentum(&s.c, P1);
    struct mpm_totals t;
    mpm_totals(&s.c.m, &t);
    cr_assert(t.kinetic > 1e-3, "the material points did not move (%g eV)", t.kinetic);
    for (int q = 0; q < 3; q++)
        cr_assert(fabs(P1[q] - P0[q]) < 1e-11 * scale, "momentum %d: %.15g -> %.15g", q, P0[q],
                  P1[q]);
    destroy(&s);
}
