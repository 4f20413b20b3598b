/*
 * dpd_sweep_cells: the Shardlow pair sweep (dpd_sweep.c) in an order that
 * does not depend on how the box is cut into bricks, so that a run on any
 * number of MPI ranks makes the same pair updates as a serial one.
 *
 * The sweep is sequential: each pair's update sees the velocities the
 * pairs before it left, so its result depends on the order.  The list-
 * order sweep follows storage and list order, which a decomposition
 * changes.  Here the order is fixed by the particles' positions and ids
 * alone:
 *
 *   cells   along a periodic axis the box is cut into n cells at least
 *           r_d wide (n = floor(L / r_d) rounded down to a multiple of 3,
 *           at least 3); along a free or fixed axis the cells are r_d wide
 *           from the coordinate origin, whatever the box (a free axis'
 *           box follows the particles: fixed cells keep the order of a
 *           run and of its reference run without the flyer the same);
 *           a particle's cell is computed by its owner and copied to its
 *           ghosts, so every copy agrees;
 *   pairs   a pair (r < r_d) belongs to the cell of its lower-id particle
 *           (the anchor); its partner then lies in the anchor cell or one
 *           of the 26 around it;
 *   colours cell (cx, cy, cz) has colour (cx mod 3) + 3 (cy mod 3) +
 *           9 (cz mod 3): two cells of one colour are three cells apart
 *           along some axis, so the particles their pairs touch are
 *           disjoint and their pairs commute;
 *   order   colour 0, ..., 26 in turn; inside a cell the pairs in the
 *           order of (anchor id, partner id, periodic image) -- the same
 *           on any rank count.
 *
 * Under bricks a cell belongs to the rank whose brick holds its centre;
 * that rank sweeps all of its pairs, on its own copies of the particles
 * (owned or ghost: the ghost shell is widened by half a cell,
 * dpd_sweep_cells_range).  After each colour the new velocities (and DPDE
 * internal energies) go back to the owners -- exactly one copy of a
 * particle was touched, so a reverse sum of (value, 1) from touched copies
 * and zeros from the others hands the owner the new value bit for bit --
 * and forward to every ghost.  This is the idea of the stencil colouring
 * of LAMMPS' DPD-REACT (Larentzos et al., Comput. Phys. Commun. 185, 1987
 * (2014)), whose eight sub-domain regions per rank make its order depend
 * on the decomposition; a global 27-colour grid makes it not.
 * Rigid bodies: a prescribed body (grip, piston) keeps its velocity, so
 * its pairs commute within a colour like any other (its particles have
 * infinite mass in the pair; the impulses on it are summed over the
 * ranks).  A free body's one velocity couples its pairs in every cell:
 * they are swept apart, before the colours, in one global order on every
 * rank (dpd_sweep_bodies.h).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "core/halo.h"
#include "dpd/dpd_ou.h"
#include "dpd/dpd_pair.h"
#include "dpd/dpd_sweep_bodies.h"

#define NCOLOURS 27

struct cell_grid {
    int n[3];
    double lo[3], side[3], len[3];
    int periodic[3];
};

/* Cell coordinates along a free axis are offset by this into 17 bits of
 * the cell key (cells of r_d = 10 Å reach 650 µm from the origin). */
#define FREE_OFFSET 65536
#define FREE_MAX 65535

/* 0, or -1 when a periodic axis is shorter than three cells of r_d. */
static int grid_of(const struct box *box, double rd, struct cell_grid *g, int *bad_axis)
{
    for (int k = 0; k < 3; k++) {
        double L = box_length(box, k);
        g->periodic[k] = box->bc[k] == BOUNDARY_PERIODIC;
        if (!g->periodic[k]) {   /* fixed cells of r_d from the origin */
            g->lo[k] = 0;
            g->len[k] = L;
            g->n[k] = 0;
            g->side[k] = rd > 0 ? rd : (L > 0 ? L : 1.0);
            continue;
        }
        g->lo[k] = box->lo[k];
        g->len[k] = L;
        double q = rd > 0 ? floor(L / rd) : 1;
        int n = q >= 1 ? (q > 4096 ? 4096 : (int)q) : 1;
        n -= n % 3;
        if (n < 3) {
            *bad_axis = k;
            return -1;
        }
        g->n[k] = n;
        g->side[k] = L > 0 ? L / n : 1.0;
    }
    return 0;
}

double dpd_sweep_cells_range(const struct box *box, double rd, double skin)
{
    struct cell_grid g;
    int bad;
    if (grid_of(box, rd, &g, &bad) != 0)
        return 0;
    double s = fmax(g.side[0], fmax(g.side[1], g.side[2]));
    /* an anchor lies within half a cell (plus skin / 2 of drift) of a
     * centre in the brick, its partner within r_d of it, and both moved
     * up to skin / 2 since the ghosts were built */
    return 0.5 * s + rd + skin;
}

static int cell_coord(const struct cell_grid *g, int k, double x)
{
    double q = floor((x - g->lo[k]) / g->side[k]);
    if (!(q == q))
        return 0;
    if (g->periodic[k]) {
        double m = fmod(q, (double)g->n[k]);
        if (m < 0)
            m += g->n[k];
        return (int)m;
    }
    return q < -FREE_MAX ? -FREE_MAX : q > FREE_MAX ? FREE_MAX : (int)q;
}

/* The key of cell c (exact in a double: 3 x 17 bits) and back. */
static double cell_key(const int c[3])
{
    double key = 0;
    for (int k = 2; k >= 0; k--)
        key = key * 131072.0 + (double)(c[k] + FREE_OFFSET);
    return key;
}

static void cell_of_key(double key, int c[3])
{
    long v = (long)key;
    for (int k = 0; k < 3; k++) {
        c[k] = (int)(v % 131072) - FREE_OFFSET;
        v /= 131072;
    }
}

static int colour_of(const int c[3])
{
    int col = 0;
    for (int k = 2; k >= 0; k--)
        col = 3 * col + ((c[k] % 3) + 3) % 3;
    return col;
}

struct sweep_pair {
    int64_t ida, idb;
    double cell;      /* cell_key */
    int colour;       /* -1: a free body's pair (dpd_sweep_bodies.h) */
    uint32_t image;   /* the partner's periodic copy, as in the pair key */
    int a, b;         /* local indices */
};

static int cmp_pair(const void *x, const void *y)
{
    const struct sweep_pair *p = x, *q = y;
    if (p->colour != q->colour)
        return p->colour < q->colour ? -1 : 1;
    if (p->cell != q->cell)
        return p->cell < q->cell ? -1 : 1;
    if (p->ida != q->ida)
        return p->ida < q->ida ? -1 : 1;
    if (p->idb != q->idb)
        return p->idb < q->idb ? -1 : 1;
    return (p->image > q->image) - (p->image < q->image);
}

/* 1 when this rank sweeps cell c (its centre lies in the brick). */
static int cell_is_mine(const struct particles *p, const struct cell_grid *g, const int c[3])
{
    if (!p->halo)
        return 1;
    for (int k = 0; k < 3; k++) {
        double centre = g->lo[k] + (c[k] + 0.5) * g->side[k];
        if (decomp_coord(&p->halo->dc, k, centre) != p->halo->dc.coords[k])
            return 0;
    }
    return 1;
}

/* Local bins of width >= r_d over every copy (owned and ghost). */
struct bins {
    int n[3];
    double lo[3], w[3];
    int *head, *next;
};

static int bins_build(struct bins *b, const struct particles *p, int ntot, double rd,
                      struct err *e)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < ntot; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p->x[3 * i + k]);
            hi[k] = fmax(hi[k], p->x[3 * i + k]);
        }
    for (int k = 0; k < 3; k++) {
        double ext = ntot ? hi[k] - lo[k] : 0;
        double q = floor(ext / rd);
        b->n[k] = q >= 1 ? (q > 1024 ? 1024 : (int)q) : 1;
    }
    /* a sparse set (a slab in a tall box) needs no more bins than copies:
     * halve the longest axis' count (bins only get wider than r_d) */
    while ((long)b->n[0] * b->n[1] * b->n[2] > 4L * ntot + 64) {
        int k = b->n[0] >= b->n[1] && b->n[0] >= b->n[2] ? 0 : b->n[1] >= b->n[2] ? 1 : 2;
        b->n[k] = (b->n[k] + 1) / 2;
    }
    long total = 1;
    for (int k = 0; k < 3; k++) {
        double ext = ntot ? hi[k] - lo[k] : 0;
        b->lo[k] = ntot ? lo[k] : 0;
        b->w[k] = ext > 0 ? ext / b->n[k] * (1 + 1e-12) : 1.0;
        total *= b->n[k];
    }
    b->head = malloc((size_t)total * sizeof *b->head);
    b->next = malloc((size_t)(ntot ? ntot : 1) * sizeof *b->next);
    if (!b->head || !b->next)
        return err_nomem(e, "DPD sweep bins");
    for (long c = 0; c < total; c++)
        b->head[c] = -1;
    for (int i = ntot - 1; i >= 0; i--) {
        long c = 0;
        for (int k = 2; k >= 0; k--) {
            int q = (int)((p->x[3 * i + k] - b->lo[k]) / b->w[k]);
            q = q < 0 ? 0 : q >= b->n[k] ? b->n[k] - 1 : q;
            c = c * b->n[k] + q;
        }
        b->next[i] = b->head[c];
        b->head[c] = i;
    }
    return 0;
}

static void bins_free(struct bins *b)
{
    free(b->head);
    free(b->next);
}

/* The pairs this rank sweeps, in the sweep's order (colour, cell, anchor
 * id, partner id, image), without sorting the pairs themselves: the
 * anchors are sorted by (colour, cell, id) and each anchor's partners by
 * (id, image), which gives the same sequence, since all the pairs of an
 * anchor share its colour and cell and no two anchors of a cell share an
 * id.  A colour's pairs are pair[start[c] .. start[c + 1]) as local index
 * pairs (8 bytes a pair); the free bodies' pairs (colour -1) go whole into
 * body[], sorted by cmp_pair, for dpd_sweep_bodies. */
struct pair_list {
    int32_t (*pair)[2];
    long n, cap;
    long start[NCOLOURS + 1];
    struct sweep_pair *body;
    long nbody, cap_body;
};

static void pair_list_free(struct pair_list *l)
{
    free(l->pair);
    free(l->body);
    memset(l, 0, sizeof *l);
}

struct anchor {
    double cell;
    int64_t id;
    int colour, a;
};

static int cmp_anchor(const void *x, const void *y)
{
    const struct anchor *p = x, *q = y;
    if (p->colour != q->colour)
        return p->colour < q->colour ? -1 : 1;
    if (p->cell != q->cell)
        return p->cell < q->cell ? -1 : 1;
    return (p->id > q->id) - (p->id < q->id);
}

struct partner {
    int64_t id;
    uint32_t image;
    int b, body;   /* body: a free body's pair */
};

/* (id, image) order by insertion: an anchor has a few dozen partners. */
static void sort_partners(struct partner *q, int n)
{
    for (int i = 1; i < n; i++) {
        struct partner t = q[i];
        int j = i - 1;
        while (j >= 0 && (q[j].id > t.id || (q[j].id == t.id && q[j].image > t.image))) {
            q[j + 1] = q[j];
            j--;
        }
        q[j + 1] = t;
    }
}

static int grow_array(void **buf, long *cap, long need, size_t size)
{
    if (need <= *cap)
        return 0;
    long nc = *cap ? *cap : 1024;
    while (nc < need)
        nc *= 2;
    void *t = realloc(*buf, (size_t)nc * size);
    if (!t)
        return -1;
    *buf = t;
    *cap = nc;
    return 0;
}

static int collect_pairs(const struct dpd *d, const struct cell_grid *g, const double *cellf,
                         struct pair_list *out, struct err *e)
{
    const struct particles *p = d->p;
    const int ntot = p->n_owned + p->n_ghost;
    const double rd = d->set.cutoff, rd2 = rd * rd;
    memset(out, 0, sizeof *out);
    struct bins b = {0};
    int rc = bins_build(&b, p, ntot, rd, e);
    /* the anchors: the copies whose cell this rank sweeps, the one near it */
    struct anchor *anc = rc ? NULL : malloc((size_t)(ntot ? ntot : 1) * sizeof *anc);
    if (!rc && !anc)
        rc = err_nomem(e, "DPD sweep anchors");
    long nanc = 0;
    for (int a = 0; !rc && a < ntot; a++) {
        double cell = cellf[a];
        int c[3];
        cell_of_key(cell, c);
        if (!cell_is_mine(p, g, c))
            continue;
        /* the copy near the cell (periodic copies are three cells apart) */
        int near = 1;
        for (int k = 0; k < 3; k++)
            if (g->periodic[k] &&
                !(fabs(p->x[3 * a + k] - (g->lo[k] + (c[k] + 0.5) * g->side[k])) < g->side[k]))
                near = 0;
        if (near)
            anc[nanc++] = (struct anchor){cell, p->id[a], colour_of(c), a};
    }
    if (!rc && nanc > 1)
        qsort(anc, (size_t)nanc, sizeof *anc, cmp_anchor);
    struct partner *q = NULL;
    long qcap = 0;
    int colour = 0;
    for (long t = 0; !rc && t < nanc; t++) {
        const int a = anc[t].a, ba = dpd_body_of(d, a);
        const int fa = ba >= 0 && d->body[ba].kind == DPD_BODY_FREE;
        for (; colour <= anc[t].colour; colour++)
            out->start[colour] = out->n;
        int qq[3];
        for (int k = 0; k < 3; k++) {
            qq[k] = (int)((p->x[3 * a + k] - b.lo[k]) / b.w[k]);
            qq[k] = qq[k] < 0 ? 0 : qq[k] >= b.n[k] ? b.n[k] - 1 : qq[k];
        }
        int nq = 0;
        for (int dz = -1; dz <= 1 && !rc; dz++)
            for (int dy = -1; dy <= 1 && !rc; dy++)
                for (int dx = -1; dx <= 1 && !rc; dx++) {
                    int r[3] = {qq[0] + dx, qq[1] + dy, qq[2] + dz};
                    if (r[0] < 0 || r[1] < 0 || r[2] < 0 || r[0] >= b.n[0] || r[1] >= b.n[1] ||
                        r[2] >= b.n[2])
                        continue;
                    for (int j = b.head[(r[2] * b.n[1] + r[1]) * b.n[0] + r[0]]; j >= 0;
                         j = b.next[j]) {
                        if (p->id[j] <= p->id[a])
                            continue;   /* itself, or a pair anchored at j */
                        double ddx = p->x[3 * a] - p->x[3 * j], ddy = p->x[3 * a + 1] - p->x[3 * j + 1],
                               ddz = p->x[3 * a + 2] - p->x[3 * j + 2];
                        if (ddx * ddx + ddy * ddy + ddz * ddz >= rd2)
                            continue;
                        /* not inside one body, not between two prescribed ones */
                        int bb = dpd_body_of(d, j);
                        if (ba >= 0 && (bb == ba || (bb >= 0 && !fa &&
                                                     d->body[bb].kind != DPD_BODY_FREE)))
                            continue;
                        int fb = bb >= 0 && d->body[bb].kind == DPD_BODY_FREE;
                        if (grow_array((void **)&q, &qcap, nq + 1, sizeof *q)) {
                            rc = err_nomem(e, "DPD sweep pairs");
                            break;
                        }
                        uint32_t code = 0;
                        for (int k = 0; k < 3; k++)
                            code = (code << 10) |
                                   (uint32_t)(((dpd_copy_shift(p, j, k) - p->image[3 * j + k]) -
                                               (dpd_copy_shift(p, a, k) - p->image[3 * a + k]) +
                                               512) &
                                              1023);
                        q[nq++] = (struct partner){p->id[j], code, j, fa || fb};
                    }
                }
        if (rc)
            break;
        sort_partners(q, nq);
        for (int k = 0; k < nq; k++) {
            if (q[k].body) {
                if (grow_array((void **)&out->body, &out->cap_body, out->nbody + 1,
                               sizeof *out->body)) {
                    rc = err_nomem(e, "DPD sweep pairs");
                    break;
                }
                out->body[out->nbody++] = (struct sweep_pair){anc[t].id, q[k].id, anc[t].cell, -1,
                                                              q[k].image, a, q[k].b};
                continue;
            }
            if (grow_array((void **)&out->pair, &out->cap, out->n + 1, sizeof *out->pair)) {
                rc = err_nomem(e, "DPD sweep pairs");
                break;
            }
            out->pair[out->n][0] = a;
            out->pair[out->n][1] = q[k].b;
            out->n++;
        }
    }
    for (; colour <= NCOLOURS; colour++)
        out->start[colour] = out->n;
    free(q);
    free(anc);
    bins_free(&b);
    if (!rc && out->nbody > 1)
        qsort(out->body, (size_t)out->nbody, sizeof *out->body, cmp_pair);
    if (rc)
        pair_list_free(out);
    return rc;
}

/* The touched copies' velocities (and internal energies) to their owners,
 * then from the owners to every ghost. */
static void sync_colour(struct dpd *d, double *buf, const unsigned char *touched, double *u)
{
    struct particles *p = d->p;
    const int ntot = p->n_owned + p->n_ghost;
    for (int i = 0; i < ntot; i++) {
        double *r = buf + 5 * i;
        if (touched[i]) {
            r[0] = p->v[3 * i];
            r[1] = p->v[3 * i + 1];
            r[2] = p->v[3 * i + 2];
            r[3] = u ? u[i] : 0;
            r[4] = 1;
        } else {
            r[0] = r[1] = r[2] = r[3] = r[4] = 0;
        }
    }
    ghost_reverse_add(p, buf, 5);
    for (int i = 0; i < p->n_owned; i++) {
        const double *r = buf + 5 * i;
        if (r[4] > 0) {
            memcpy(p->v + 3 * i, r, 3 * sizeof(double));
            if (u)
                u[i] = r[3];
        }
    }
    /* owners to ghosts, velocity and energy in one message */
    for (int i = 0; i < p->n_owned; i++) {
        memcpy(buf + 4 * i, p->v + 3 * i, 3 * sizeof(double));
        buf[4 * i + 3] = u ? u[i] : 0;
    }
    ghost_forward(p, buf, 4);
    for (int g = p->n_owned; g < ntot; g++) {
        memcpy(p->v + 3 * g, buf + 4 * g, 3 * sizeof(double));
        if (u)
            u[g] = buf[4 * g + 3];
    }
}

/* The record of a free body's pair a-b for dpd_sweep_bodies. */
static void body_record(const struct dpd *d, const struct sweep_pair *sp, uint64_t prefix,
                        const double *u, struct dpd_body_pair *r)
{
    const struct particles *p = d->p;
    const int a = sp->a, b = sp->b, loc[2] = {a, b};
    memset(r, 0, sizeof *r);
    r->cell = sp->cell;
    r->id[0] = sp->ida;
    r->id[1] = sp->idb;
    r->image = sp->image;
    double dx[3], r2 = 0;
    for (int k = 0; k < 3; k++) {
        dx[k] = p->x[3 * a + k] - p->x[3 * b + k];
        r2 += dx[k] * dx[k];
    }
    double inv_r = 1.0 / sqrt(r2), rr = r2 * inv_r;
    for (int k = 0; k < 3; k++)
        r->e[k] = dx[k] * inv_r;
    r->wr = 1.0 - rr / d->set.cutoff;
    r->xi = dpd_normal(dpd_pair_key_ab_pre(p, prefix, a, b));
    for (int q = 0; q < 2; q++) {
        int i = loc[q], bi = dpd_body_of(d, i);
        r->body[q] = bi;
        r->winv[q] = bi < 0 ? 1.0 / p->mass[p->type[i]]
                            : d->body[bi].kind == DPD_BODY_FREE ? 1.0 / d->body[bi].mass : 0.0;
        memcpy(r->v[q], p->v + 3 * i, sizeof r->v[q]);
        r->u[q] = u ? u[i] : 0;
    }
}

/* Inverse mass of copy i in a pair of the colour sweep: 0 for a prescribed
 * body's particle (free bodies' pairs are not swept there). */
static double colour_inv_mass(const struct dpd *d, int i)
{
    return d->nbodies && dpd_body_of(d, i) >= 0 ? 0.0 : 1.0 / d->p->mass[d->p->type[i]];
}

int dpd_sweep_cells(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    struct cell_grid g;
    int bad = 0;
    if (grid_of(&d->box, d->set.cutoff, &g, &bad) != 0)
        return err_set(e, ERR_INPUT, "the cell-ordered DPD sweep needs the periodic box at least "
                                     "3 r_d = %g Å long along %c (it is %g Å)",
                       3 * d->set.cutoff, "xyz"[bad], box_length(&d->box, bad));
    const int ntot = p->n_owned + p->n_ghost;
    const double rd = d->set.cutoff, inv_rd = 1.0 / rd;
    const int dpde = d->set.variant == DPD_ENERGY;
    const int site = dpde ? RNG_SITE_DPDE_PAIR : RNG_SITE_DPD_PAIR;
    const uint64_t prefix = dpd_key_prefix(d, site);
    struct dpd_ou ou;
    dpd_ou_init(&ou, dpde, d->set.gamma, d->set.temperature, d->set.heat_capacity, d->dt);
    double *u = d->ufield >= 0 ? particles_field(p, d->ufield) : NULL;
    memset(d->body_impulse, 0, sizeof d->body_impulse);
    int free_bodies = 0;
    for (int b = 0; b < d->nbodies; b++)
        free_bodies |= d->body[b].kind == DPD_BODY_FREE;

    /* every copy's cell, from its owner; current velocities and energies */
    double *buf = malloc((size_t)5 * (ntot ? ntot : 1) * sizeof *buf);
    unsigned char *touched = calloc((size_t)(ntot ? ntot : 1), 1);
    if (!buf || !touched) {
        free(buf);
        free(touched);
        return err_nomem(e, "DPD sweep");
    }
    for (int i = 0; i < p->n_owned; i++) {
        int c[3];
        for (int k = 0; k < 3; k++)
            c[k] = cell_coord(&g, k, p->x[3 * i + k]);
        buf[i] = cell_key(c);
    }
    ghost_forward(p, buf, 1);
    ghost_update_velocities(p);
    if (u)
        ghost_forward(p, u, 1);
    struct pair_list pl;
    int rc = collect_pairs(d, &g, buf, &pl, e);
    /* a failure on one rank must not leave the others waiting in a sync */
    int failed = p->halo ? halo_any(p->halo, rc != 0) : rc != 0;
    if (failed) {
        free(buf);
        free(touched);
        pair_list_free(&pl);
        return rc ? rc : err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    }
    /* the free bodies' pairs, swept apart in one global order
     * (dpd_sweep_bodies.h) */
    double bimp[DPD_MAX_BODIES][3] = {{0}};
    if (free_bodies) {
        long nb = pl.nbody;
        struct dpd_body_pair *rec = malloc((size_t)(nb ? nb : 1) * sizeof *rec);
        rc = rec ? 0 : err_nomem(e, "DPD body pairs");
        if (p->halo && halo_any(p->halo, rc != 0) && !rc)
            rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
        for (long q = 0; !rc && q < nb; q++)
            body_record(d, pl.body + q, prefix, u, rec + q);
        if (!rc)
            rc = dpd_sweep_bodies(d, &ou, rec, nb, bimp, e);
        free(rec);
        if (rc) {
            free(buf);
            free(touched);
            pair_list_free(&pl);
            return rc;
        }
    }
    for (int colour = 0; colour < NCOLOURS; colour++) {
        for (long k = pl.start[colour]; k < pl.start[colour + 1]; k++) {
            if (rc)
                continue;
            int a = pl.pair[k][0], b = pl.pair[k][1];
            double dx = p->x[3 * a] - p->x[3 * b], dy = p->x[3 * a + 1] - p->x[3 * b + 1],
                   dz = p->x[3 * a + 2] - p->x[3 * b + 2];
            double r2 = dx * dx + dy * dy + dz * dz;
            double wa = colour_inv_mass(d, a), wb = colour_inv_mass(d, b);
            double invmu = wa + wb, mu = 1.0 / invmu;
            double inv_r = 1.0 / sqrt(r2), r = r2 * inv_r;
            double ex = dx * inv_r, ey = dy * inv_r, ez = dz * inv_r;
            struct dpd_ou_pair q;
            dpd_ou_pair_set(&ou, &q, 1.0 - r * inv_rd, invmu,
                            dpd_normal(dpd_pair_key_ab_pre(p, prefix, a, b)));
            double *va = p->v + 3 * a, *vb = p->v + 3 * b;
            double urel = ex * (va[0] - vb[0]) + ey * (va[1] - vb[1]) + ez * (va[2] - vb[2]);
            double unew = dpd_ou_unew(&ou, &q, urel, u ? u[a] : 0, u ? u[b] : 0);
            double du = unew - urel;
            double aa = du * (wa * mu), ab = du * (wb * mu);
            dpd_ou_kick(va, vb, aa, ab, ex, ey, ez);
            touched[a] = touched[b] = 1;
            if (d->nbodies) {   /* a prescribed body takes the impulse J along e, +J on a */
                double J = du * mu;
                int ba = dpd_body_of(d, a), bb = dpd_body_of(d, b);
                if (ba >= 0) {
                    d->body_impulse[ba][0] += J * ex;
                    d->body_impulse[ba][1] += J * ey;
                    d->body_impulse[ba][2] += J * ez;
                }
                if (bb >= 0) {
                    d->body_impulse[bb][0] -= J * ex;
                    d->body_impulse[bb][1] -= J * ey;
                    d->body_impulse[bb][2] -= J * ez;
                }
            }
            if (dpde) {
                double dE4 = du * ((unew + urel) * (mu * (0.25 * UNITS_MVV2E)));   /* eV, per side */
                u[a] -= dE4;
                u[b] -= dE4;
                if (!(u[a] > 0) || !(u[b] > 0))
                    rc = err_set(e, ERR_DIVERGED,
                                 "internal energy of particle %lld became %.3g eV at step %ld "
                                 "(time step too large for the heat exchanged?)",
                                 (long long)p->id[u[a] > 0 ? b : a], u[a] > 0 ? u[b] : u[a],
                                 d->step);
            }
        }
        sync_colour(d, buf, touched, u);
        memset(touched, 0, (size_t)ntot);
    }
    free(buf);
    free(touched);
    pair_list_free(&pl);
    /* the prescribed bodies' impulses of every rank's cells; the free
     * bodies' are the same on every rank already */
    if (p->halo && d->nbodies)
        halo_sum(p->halo, &d->body_impulse[0][0], 3 * DPD_MAX_BODIES);
    for (int b = 0; b < d->nbodies; b++)
        for (int c = 0; c < 3; c++)
            d->body_impulse[b][c] += bimp[b][c];
    if (p->halo && halo_any(p->halo, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_DIVERGED,
                               "stopped: an internal energy became non-positive on "
                               "another MPI rank");
    return rc;
}
