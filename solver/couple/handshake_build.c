/*
 * handshake_build: the MPM side of the handshake (hierarchical grid, cubic
 * elastic material, material points) and the MD particles (atoms of the MD
 * box with their regions, and the copies of regions II and III).
 *
 * Points: in cells of the finest level on the lattice sites outside the MD
 * box (Guo & Yang 2005, section 2.2: "in regions II and III, material
 * points are initially located at the ideal lattice sites"); in coarse
 * cells eight points at the reduced coordinates (+-1/2, +-1/2, +-1/2) with
 * mass density x cell volume / 8 ("material points are enlarged in
 * proportion to the background mesh", Fig. 1(c)).  The fcc lattice lies a
 * quarter lattice constant off the grid planes, so a cell of one lattice
 * constant holds four sites at four of those eight positions (atomic mass
 * and volume each), which integrate the gradients of the trilinear shape
 * functions over the cell exactly: a uniform stress puts no force on any
 * node, also on the bar's sliding faces.  bcc (a/4 off) and diamond (a/8
 * off, its sites being a/4 apart) put two and eight sites in every cell;
 * they integrate the gradients exactly up to the product term yz of the
 * face directions, which cancels around every node whose cells all hold
 * the same pattern, so only where the pattern changes (the first coarse
 * cells) on an edge of two sliding faces is a uniform stress not exactly
 * in balance (docs/handshake.md, Limits).  A cell of half a lattice
 * constant has one site at its centre in every other cell; sites alone
 * would be exact only in pairs of cells and leave forces on the nodes of a
 * sliding face, so such cells get a point at every centre (half an atomic
 * mass and volume), and the ones on sites carry the MD copies.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"
#include "couple/handshake.h"
#include "couple/handshake_bricks.h"
#include "mpm/mpm_hgrid.h"

/* Call fn for every lattice site in [lo, hi). */
typedef int (*site_fn)(void *ctx, const double x[3]);
static int for_sites(const struct handshake_layout *L, const double lo[3], const double hi[3],
                     site_fn fn, void *ctx)
{
    double basis[8][3], P[3];
    const int nb = hs_cell_basis(L->lattice, L->orient, basis, P);
    handshake_layout_period(L, P);
    long n0[3], n1[3];
    for (int d = 0; d < 3; d++) {
        n0[d] = (long)floor((lo[d] - L->lat_origin[d]) / P[d]) - 1;
        n1[d] = (long)ceil((hi[d] - L->lat_origin[d]) / P[d]) + 1;
    }
    /* x fastest within a (100) plane pair, so neighbours stay close in memory */
    for (long k = n0[2]; k < n1[2]; k++)
        for (long j = n0[1]; j < n1[1]; j++)
            for (long i = n0[0]; i < n1[0]; i++)
                for (int b = 0; b < nb; b++) {
                    double x[3] = {L->lat_origin[0] + (i + basis[b][0]) * P[0],
                                   L->lat_origin[1] + (j + basis[b][1]) * P[1],
                                   L->lat_origin[2] + (k + basis[b][2]) * P[2]};
                    int in = 1;
                    for (int d = 0; d < 3; d++)
                        in &= x[d] >= lo[d] && x[d] < hi[d];
                    if (in) {
                        int rc = fn(ctx, x);
                        if (rc)
                            return rc;
                    }
                }
    return 0;
}

/* The passes over the points, in the one order of the build (a point's
 * place in it, from 0, is its id less one on every rank count):
 *   FILL_COUNT  count them and their regions;
 *   FILL_DEAL   (bricks) the rank whose brick holds each (owner[]);
 *   FILL_ADD    add them: all, or (owner given) this rank's. */
enum fill_pass { FILL_COUNT, FILL_DEAL, FILL_ADD };

struct fill_ctx {
    struct handshake *hs;
    enum fill_pass pass;
    long n;                  /* points passed so far (all ranks') */
    const struct decomp *dc; /* bricks: the MD's decomposition */
    int32_t *owner;          /* bricks: per point, the rank whose brick holds it */
    int rank;
    long mine;               /* FILL_DEAL: this rank's points */
    struct err *e;
};

static int add_point(struct fill_ctx *c, const double x[3], double mass, double vol, uint32_t mask)
{
    struct handshake *hs = c->hs;
    const struct handshake_layout *L = &hs->lay;
    for (int d = 0; d < 3; d++)
        if (x[d] < L->mat_lo[d] || x[d] >= L->mat_hi[d])
            return 0;
    long q = c->n++;
    if (c->pass == FILL_COUNT) {
        hs->counts[mask & HS_MASK_II ? HS_II : mask & HS_MASK_III ? HS_III : HS_MPM]++;
        return 0;
    }
    if (c->pass == FILL_DEAL) {   /* the points with an MD copy: by its brick */
        int copy = (mask & (HS_MASK_II | HS_MASK_III)) && (mask & HS_MASK_SITE);
        c->owner[q] = copy ? decomp_owner(c->dc, x) : -1;
        return 0;
    }
    if (c->owner && c->owner[q] != c->rank)
        return 0;
    struct mpm_points *p = &hs->mpm.pts;
    static const double zero[3] = {0, 0, 0};
    long i = mpm_points_add(p, x, zero, mass, vol, hs->body, (int64_t)q + 1, c->e);
    if (i < 0)
        return ERR_RUNTIME;
    p->mask[i] = mask;
    return 0;
}

static uint32_t region_mask(enum hs_region r)
{
    return r == HS_II ? HS_MASK_II : r == HS_III ? HS_MASK_III : 0;
}

static int site_point(void *ctx, const double x[3])
{
    struct fill_ctx *c = ctx;
    const struct handshake *hs = c->hs;
    enum hs_region r = handshake_classify(&hs->lay, x);
    if (r == HS_CORE || r == HS_I)
        return 0;   /* an atom */
    return add_point(c, x, hs->cr.mass, hs->omega0, region_mask(r) | HS_MASK_SITE);
}

/* Whether x is a lattice site: its offset from the origin, in the cubic
 * cell, is one of the basis sites. */
static int on_site(const struct handshake_layout *L, const double x[3])
{
    double basis[8][3], P[3];
    const int nb = hs_cell_basis(L->lattice, L->orient, basis, P);
    handshake_layout_period(L, P);
    double u[3];
    for (int d = 0; d < 3; d++) {
        u[d] = (x[d] - L->lat_origin[d]) / P[d];
        u[d] -= floor(u[d] + 1e-9);
    }
    for (int b = 0; b < nb; b++) {
        int same = 1;
        for (int d = 0; d < 3; d++) {
            double t = fabs(u[d] - basis[b][d]);
            same &= t < 1e-6 || fabs(t - 1) < 1e-6;
        }
        if (same)
            return 1;
    }
    return 0;
}

/* Eight points at the reduced coordinates (+-1/2, +-1/2, +-1/2) of a cell,
 * each an eighth of its mass and volume: the two-point rule per axis,
 * exact for the trilinear shape functions' gradients. */
static int eight_points(struct fill_ctx *c, const double lo[3], const double size[3])
{
    const struct handshake *hs = c->hs;
    double vol = size[0] * size[1] * size[2] / 8.0;
    for (int k = 0; k < 8; k++) {
        double x[3];
        for (int d = 0; d < 3; d++)
            x[d] = lo[d] + (((k >> d) & 1) ? 0.75 : 0.25) * size[d];
        enum hs_region r = handshake_classify(&hs->lay, x);
        if (r != HS_MPM)
            return err_set(c->e, ERR_INPUT,
                           "a coarse cell at (%g, %g, %g) Å reaches into the MD region or its "
                           "regions II and III",
                           lo[0], lo[1], lo[2]);
        int rc = add_point(c, x, hs->rho * vol, vol, 0);
        if (rc)
            return rc;
    }
    return 0;
}

/* Points of one cell [lo, lo + size) of level `level`. */
static int fill_cell(struct fill_ctx *c, const double lo[3], const double size[3], int level)
{
    const struct handshake *hs = c->hs;
    double P[3];
    handshake_layout_period(&hs->lay, P);
    if (level == 0 && fabs(size[0] - P[0]) < 1e-9 * P[0]) {   /* one oriented cell */
        double hi[3] = {lo[0] + size[0], lo[1] + size[1], lo[2] + size[2]};
        return for_sites(&hs->lay, lo, hi, site_point, c);
    }
    if (level == 0) {   /* half a lattice constant: the centre */
        double x[3] = {lo[0] + 0.5 * size[0], lo[1] + 0.5 * size[1], lo[2] + 0.5 * size[2]};
        enum hs_region r = handshake_classify(&hs->lay, x);
        if (r == HS_CORE || r == HS_I)
            return 0;
        double vol = size[0] * size[1] * size[2];
        return add_point(c, x, hs->rho * vol, vol,
                         region_mask(r) | (on_site(&hs->lay, x) ? HS_MASK_SITE : 0));
    }
    return eight_points(c, lo, size);
}

static int fill_points(struct fill_ctx *c)
{
    const struct mpm_grid *g = &c->hs->mpm.grid;
    if (g->kind == MPM_GRID_HIER) {
        const struct mpm_hgrid *hg = g->hg;
        for (long k = 0; k < hg->ncell; k++) {
            const struct mpm_hcell *cl = &hg->cell[k];
            double lo[3], size[3];
            for (int d = 0; d < 3; d++) {
                lo[d] = g->origin[d] + cl->lo[d] * g->hd[d];
                size[d] = (double)(1L << cl->lg[d]) * g->hd[d];
            }
            int rc = fill_cell(c, lo, size, cl->level);
            if (rc)
                return rc;
        }
        return 0;
    }
    const double *size = g->hd;
    for (long kz = 0; kz < g->ncell[2]; kz++)
        for (long ky = 0; ky < g->ncell[1]; ky++)
            for (long kx = 0; kx < g->ncell[0]; kx++) {
                double lo[3] = {g->origin[0] + kx * g->hd[0], g->origin[1] + ky * g->hd[1],
                                g->origin[2] + kz * g->hd[2]};
                int rc = fill_cell(c, lo, size, 0);
                if (rc)
                    return rc;
            }
    return 0;
}

static int build_grid(struct handshake *hs, int nthreads, struct err *e)
{
    const struct handshake_layout *L = &hs->lay;
    long ncell[3];
    double h[3];
    handshake_layout_cell(L, h);
    for (int d = 0; d < 3; d++)
        ncell[d] = lround((L->dom_hi[d] - L->dom_lo[d]) / h[d]);
    struct mpm_grid grid;
    int rc;
    if (L->nlevels > 0) {
        /* level l wherever the Chebyshev distance from the MD box (across
         * its interfaces) exceeds fine + (l - 1) layer */
        struct mpm_hlevel lv[MPM_MAX_LEVELS];
        for (int l = 0; l < L->nlevels; l++) {
            double dist = L->fine + l * L->layer;
            lv[l].coarsen = L->coarsen;
            memset(&lv[l].region, 0, sizeof lv[l].region);
            lv[l].region.shape = REGION_BOX;
            lv[l].region.outside = 1;
            for (int d = 0; d < 3; d++) {
                lv[l].region.lo[d] = handshake_face_coupled(L, 2 * d) ? L->md_lo[d] - dist : -1e30;
                lv[l].region.hi[d] =
                    handshake_face_coupled(L, 2 * d + 1) ? L->md_hi[d] + dist : 1e30;
            }
        }
        struct mpm_hgrid *hg;
        rc = mpm_hgrid_build3(&hg, L->dom_lo, h, ncell, lv, L->nlevels, MPM_HANGING_MODIFIED, e);
        if (rc)
            return rc;
        rc = mpm_grid_init_hier(&grid, hg, e);
    } else {
        rc = mpm_grid_init_uniform3(&grid, L->dom_lo, h, ncell, MPM_SHAPE_LINEAR, e);
    }
    if (!rc)
        rc = mpm_grid_set_faces(&grid, L->face, e);
    if (!rc)
        rc = mpm_init(&hs->mpm, &grid, 0, nthreads, e);
    else
        mpm_grid_free(&grid);
    return rc;
}

/* --- MD particles --------------------------------------------------------- */

struct atom_ctx {
    struct handshake *hs;
    struct particles *p;
    int64_t next_id;
    struct err *e;
};

static int set_region(struct handshake *hs, struct particles *p, int i, enum hs_region r)
{
    p->fields[hs->f_region].data[i] = (double)r;
    for (int d = 0; d < 3; d++)
        p->fields[hs->f_x0].data[3 * i + d] = p->x[3 * i + d];
    if (r == HS_I)
        p->mask[i] |= HS_MASK_I;
    hs->counts[r]++;
    return 0;
}

static int site_atom(void *ctx, const double x[3])
{
    struct atom_ctx *c = ctx;
    enum hs_region r = handshake_classify(&c->hs->lay, x);
    if (r != HS_CORE && r != HS_I)
        return 0;
    int i = particles_add(c->p, x, NULL, c->hs->cr.type, c->next_id++);
    if (i < 0)
        return err_nomem(c->e, "handshake atoms");
    return set_region(c->hs, c->p, i, r);
}

/* The points without an MD copy (owner -1) dealt to the ranks in runs of
 * consecutive ids, so that every rank holds as many points as the others
 * (to one): the grid is whole on every rank, so any rank can map any
 * point, and consecutive ids are neighbouring cells (the build's order).
 * The same arithmetic on every rank.  Returns this rank's count. */
static long deal_the_rest(int32_t *owner, long n, int nranks, int rank, struct err *e)
{
    long *have = calloc((size_t)nranks, sizeof *have);
    if (!have)
        return err_nomem(e, "handshake points' owners"), -1;
    for (long q = 0; q < n; q++)
        if (owner[q] >= 0)
            have[owner[q]]++;
    int r = 0;
    for (long q = 0; q < n; q++) {
        if (owner[q] >= 0)
            continue;
        /* rank r's quota: n / nranks, the first n % nranks one more */
        while (r < nranks - 1 && have[r] >= n / nranks + (r < n % nranks))
            r++;
        owner[q] = r;
        have[r]++;
    }
    long mine = have[rank];
    free(have);
    return mine;
}

/* The material points: every one serially; on bricks (halo) this rank's
 * share -- the points with an MD copy (regions II and III) by the MD brick
 * that holds their initial position, so a copy starts where its point is,
 * the others dealt evenly (deal_the_rest) -- with the owners of all of
 * them kept for the exchanges (handshake_bricks.h).  Collective with a
 * halo. */
static int add_material_points(struct handshake *hs, const struct halo *halo, struct err *e)
{
    struct fill_ctx c = {.hs = hs, .pass = FILL_DEAL, .e = e};
    int rc = 0;
    long n = hs->npoints;
    if (halo) {
        c.dc = &halo->dc;
        c.rank = halo->dc.par ? halo->dc.par->rank : 0;
        c.owner = malloc((size_t)(n > 0 ? n : 1) * sizeof *c.owner);
        rc = c.owner ? fill_points(&c) : err_nomem(e, "handshake points' owners");
        if (!rc && c.n != n)
            rc = err_set(e, ERR_RUNTIME, "handshake: %ld points dealt, %ld counted", c.n, n);
        int nranks = halo->dc.par ? halo->dc.par->size : 1;
        if (!rc && (c.mine = deal_the_rest(c.owner, n, nranks, c.rank, e)) < 0)
            rc = ERR_RUNTIME;
        if ((rc = halo_agree(halo, rc, e))) {
            free(c.owner);
            return rc;
        }
        n = c.mine;
    }
    rc = mpm_points_reserve(&hs->mpm.pts, n > 0 ? n : 1, e);
    c.pass = FILL_ADD;
    c.n = 0;
    if (!rc)
        rc = fill_points(&c);
    if (halo && !(rc = halo_agree(halo, rc, e)))
        rc = hs_bricks_adopt(hs, halo, c.owner, hs->npoints, e);   /* takes owner */
    else if (halo)
        free(c.owner);
    return rc;
}

/* The atoms of B get their regions and the copies of regions II and III
 * join them.  On bricks (halo) p holds this rank's atoms: the copies whose
 * point lies in the rank's brick join (ids id_base + point index, as in a
 * serial build, id_base one past the largest id of all ranks), and the
 * counts of atoms and copies are summed over the ranks. */
static int add_md_particles(struct handshake *hs, struct particles **pp, const struct halo *halo,
                            struct err *e)
{
    const struct handshake_layout *L = &hs->lay;
    struct particles *p = *pp ? *pp : particles_create(1024);
    int fresh = p && p->n_owned == 0 && !halo;
    if (!p)
        return err_nomem(e, "handshake particles");
    *pp = p;
    particles_clear_ghosts(p);
    if ((hs->f_region = particles_add_field(p, "region", 1, 0, e)) < 0 ||
        (hs->f_x0 = particles_add_field(p, "reference_position", 3, 0, e)) < 0)
        return ERR_RUNTIME;
    int64_t next_id = 1;
    if (fresh) {
        struct atom_ctx c = {hs, p, 1, e};
        int rc = for_sites(L, L->md_lo, L->md_hi, site_atom, &c);
        if (rc)
            return rc;
        next_id = c.next_id;
    } else {
        /* the case's own atoms: their regions from where they sit now */
        int n = p->n_owned, rc = 0;
        for (int i = 0; i < n && !rc; i++) {
            if (p->id[i] >= next_id)
                next_id = p->id[i] + 1;
            const double *x = p->x + 3 * i;
            int in_material = 1;
            for (int d = 0; d < 3; d++)
                in_material &= x[d] >= L->mat_lo[d] && x[d] < L->mat_hi[d];
            /* atoms beyond the material (a projectile above a free face)
             * are plain MD atoms */
            enum hs_region r = in_material ? handshake_classify(L, x) : HS_CORE;
            if (r != HS_CORE && r != HS_I)
                rc = err_set(e, ERR_INPUT,
                             "atom %lld at (%g, %g, %g) Å lies outside the MD region of the "
                             "handshake",
                             (long long)p->id[i], p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
            else
                set_region(hs, p, i, r);
        }
        if (halo)   /* every rank stops together before the sums below */
            rc = halo_agree(halo, rc, e);
        if (rc)
            return rc;
    }
    if (halo) {   /* ids below 2^53 are exact as doubles */
        double top = (double)next_id;
        halo_max(halo, &top, 1);
        next_id = (int64_t)top;
    }
    hs->natoms = p->n_owned;
    /* the material points (on bricks this rank's share) */
    int rc = add_material_points(hs, halo, e);
    if (rc)
        return rc;
    /* copies of regions II and III: ids id_base + point index (id - 1); on
     * bricks those of this rank's points, dealt by the same bricks */
    hs->id_base = next_id;
    const struct mpm_points *pt = &hs->mpm.pts;
    for (long q = 0; q < pt->n; q++) {
        uint32_t m = pt->mask[q] & (HS_MASK_II | HS_MASK_III);
        if (!m || !(pt->mask[q] & HS_MASK_SITE))
            continue;
        hs->ncopies++;
        int i = particles_add(p, pt->x + 3 * q, NULL, hs->cr.type, hs->id_base + pt->id[q] - 1);
        if (i < 0) {
            rc = err_nomem(e, "handshake particles");
            return halo ? halo_agree(halo, rc, e) : rc;
        }
        p->mask[i] = m;   /* not in group "all": thermostats and velocities skip them */
        p->fields[hs->f_region].data[i] = m == HS_MASK_II ? HS_II : HS_III;
        for (int d = 0; d < 3; d++)
            p->fields[hs->f_x0].data[3 * i + d] = p->x[3 * i + d];
    }
    if (halo && halo_agree(halo, 0, e))
        return ERR_RUNTIME;
    if (halo) {   /* the atoms' counts over the ranks (the points' are global already) */
        double n[5] = {(double)hs->counts[HS_CORE], (double)hs->counts[HS_I],
                       (double)hs->counts[HS_FIXED], (double)hs->natoms, (double)hs->ncopies};
        halo_sum(halo, n, 5);
        hs->counts[HS_CORE] = (long)n[0];
        hs->counts[HS_I] = (long)n[1];
        hs->counts[HS_FIXED] = (long)n[2];
        hs->natoms = (long)n[3];
        hs->ncopies = (long)n[4];
    }
    return 0;
}

int handshake_build_mpm(struct handshake *hs, const struct handshake_layout *L,
                        const struct handshake_crystal *cr, int nthreads, struct err *e)
{
    memset(hs, 0, sizeof *hs);
    hs->lay = *L;
    hs->cr = *cr;
    hs_orientation_axes(L->orient, hs->axes);
    double basis[8][3], P[3];
    const int nb = hs_cell_basis(L->lattice, L->orient, basis, P);
    handshake_layout_period(L, P);
    hs->omega0 = P[0] * P[1] * P[2] / nb;
    hs->rho = cr->mass / hs->omega0;
    int rc = build_grid(hs, nthreads, e);
    if (rc)
        return rc;
    struct mpm *m = &hs->mpm;
    m->sort_every = 0;   /* point indices are the links of the MD copies */
    /* the cubic constants in the crystal's frame; turned, the orthotropic
     * stiffness of the rotated tensor */
    double R[3][3];
    hs_orientation_axes(L->orient, R);
    struct mpm_material *mat =
        L->orient == HS_ORIENT_100
            ? mpm_material_cubic_elastic("crystal", hs->rho, cr->c11, cr->c12, cr->c44)
            : mpm_material_cubic_elastic_rotated("crystal", hs->rho, cr->c11, cr->c12, cr->c44, R);
    if (!mat)
        return err_nomem(e, "handshake material");
    if (mpm_add_material(m, mat, e) < 0)
        return ERR_RUNTIME;
    struct mpm_body b;
    memset(&b, 0, sizeof b);
    snprintf(b.name, sizeof b.name, "crystal");
    for (int d = 0; d < 3; d++)
        b.lp[d] = 0.25;
    if ((hs->body = mpm_add_body(m, &b, e)) < 0)
        return ERR_RUNTIME;
    /* the points themselves come with the MD particles (add_md_particles),
     * when a run on bricks knows its brick */
    struct fill_ctx c = {.hs = hs, .pass = FILL_COUNT, .e = e};
    if ((rc = fill_points(&c)))
        return rc;
    hs->npoints = c.n;
    return 0;
}

int handshake_add_particles(struct handshake *hs, struct particles **p, const struct halo *halo,
                            struct err *e)
{
    return add_md_particles(hs, p, halo, e);
}

int handshake_create(struct handshake *hs, const struct handshake_layout *L,
                     const struct handshake_crystal *cr, struct particles **p, int nthreads,
                     struct err *e)
{
    int rc = handshake_build_mpm(hs, L, cr, nthreads, e);
    return rc ? rc : add_md_particles(hs, p, NULL, e);
}

void handshake_md_box(const struct handshake_layout *L, struct box *box)
{
    memset(box, 0, sizeof *box);
    for (int d = 0; d < 3; d++) {
        box->bc[d] = L->md_periodic[d] ? BOUNDARY_PERIODIC : BOUNDARY_FREE;
        box->lo[d] = L->md_periodic[d] ? L->md_lo[d] : L->md_lo[d] - L->w[1] - L->w[2];
        box->hi[d] = L->md_periodic[d] ? L->md_hi[d] : L->md_hi[d] + L->w[1] + L->w[2];
    }
}

/* The atoms of B whose sites lie in this rank's brick, with the ids of a
 * serial build: every rank runs over all of B's sites (no memory) and
 * counts each one, as site_atom numbers them. */
struct brick_atom_ctx {
    struct atom_ctx a;
    const struct decomp *dc;
};

static int brick_site_atom(void *ctx, const double x[3])
{
    struct brick_atom_ctx *c = ctx;
    enum hs_region r = handshake_classify(&c->a.hs->lay, x);
    if (r != HS_CORE && r != HS_I)
        return 0;
    int64_t id = c->a.next_id++;
    if (!decomp_owns(c->dc, x))
        return 0;
    return particles_add(c->a.p, x, NULL, c->a.hs->cr.type, id) < 0
               ? err_nomem(c->a.e, "handshake atoms")
               : 0;
}

int handshake_setup_bricks(struct handshake *hs, struct md *md, const struct handshake_layout *L,
                           const struct handshake_crystal *cr, struct potential *pot, double dt,
                           double skin, int nthreads, struct halo *halo, int balance,
                           struct err *e)
{
    struct particles *p = particles_create(1024);
    struct handshake_crystal c = *cr;
    int rc = p ? 0 : err_nomem(e, "handshake particles");
    if (!rc) {
        c.type = particles_type_index(p, cr->element, cr->mass);
        rc = handshake_build_mpm(hs, L, &c, nthreads, e);
    }
    if (!rc) {
        struct brick_atom_ctx bc = {{hs, p, 1, e}, &halo->dc};
        rc = for_sites(L, L->md_lo, L->md_hi, brick_site_atom, &bc);
    }
    /* the atoms' regions from their sites, the copies of the brick, the
     * counts over the ranks (collective: every rank gets here) */
    rc = halo_agree(halo, rc, e);
    if (!rc)
        rc = add_md_particles(hs, &p, halo, e);
    rc = halo_adopt(halo, p, rc, e);
    if (rc) {
        particles_destroy(&p);
        potential_destroy(&pot);
        halo_free(halo);
        free(halo);
        return rc;
    }
    struct box box;
    handshake_md_box(L, &box);
    md_adopt(md, p, halo);   /* the md owns the halo from here */
    /* the copies' shells make the bar's ends denser: move the cuts when
     * asked (parallel.balance: shift) */
    if (balance && (rc = halo_balance(halo, &box, p, pot->cutoff + skin, e))) {
        particles_destroy(&p);
        potential_destroy(&pot);
        return rc;
    }
    rc = md_init(md, p, &box, pot, dt, skin, nthreads, e);   /* owns p and pot */
    if (!rc)
        rc = handshake_connect(hs, md, e);
    return rc;
}

int handshake_setup(struct handshake *hs, struct md *md, const struct handshake_layout *L,
                    const struct handshake_crystal *cr, struct potential *pot, double dt,
                    double skin, int nthreads, struct err *e)
{
    struct particles *p = particles_create(1024);
    if (!p) {
        potential_destroy(&pot);
        return err_nomem(e, "handshake particles");
    }
    struct handshake_crystal c = *cr;
    c.type = particles_type_index(p, cr->element, cr->mass);
    int rc = handshake_create(hs, L, &c, &p, nthreads, e);
    if (rc) {
        particles_destroy(&p);
        potential_destroy(&pot);
        return rc;
    }
    struct box box;
    handshake_md_box(L, &box);
    rc = md_init(md, p, &box, pot, dt, skin, nthreads, e);
    if (!rc)
        rc = handshake_connect(hs, md, e);
    return rc;
}
