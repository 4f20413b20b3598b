/* mpm_bricks: the grid patch of each rank, point migration, and the
 * reverse and forward halo of the nodes (mpm_bricks.h). */
#include "mpm/mpm_bricks.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/decomp.h"
#include "core/parallel.h"
#include "input/parallel_settings.h"
#include "mpm/mpm_shared.h"
#include "util/cfg.h"

#define MIN_BRICK_CELLS 4   /* a neighbour's patch reaches MARGIN + 1 nodes into a brick */

/* --- geometry of the bricks ------------------------------------------------ */

static int rank_of(const struct mpm_bricks *b, const int c[3])
{
    for (int d = 0; d < 3; d++)
        if (c[d] < 0 || c[d] >= b->grid[d])
            return -1;
    /* MPI_Cart_create without reordering: row-major, the last axis fastest */
    return (c[0] * b->grid[1] + c[1]) * b->grid[2] + c[2];
}

/* Brick coordinate along d of global cell k (clamped to the grid). */
static int cell_owner(const struct mpm_bricks *b, int d, long k)
{
    int lo = 0, hi = b->grid[d] - 1;
    while (lo < hi) {   /* the last c with cut[c] <= k */
        int mid = (lo + hi + 1) / 2;
        if (b->cut[d][mid] <= k)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* Global nodes [*lo, *hi) that brick c owns along d. */
static void owned_range(const struct mpm_bricks *b, int d, int c, long *lo, long *hi)
{
    *lo = c == 0 ? -1 : b->cut[d][c];
    *hi = c + 1 == b->grid[d] ? b->ncell[d] + 2 : b->cut[d][c + 1];
}

/* Patch cells [*pa, *pb) of brick c along d. */
static void patch_cells(const struct mpm_bricks *b, int d, int c, long *pa, long *pb)
{
    long a = b->cut[d][c] - MPM_BRICKS_MARGIN, z = b->cut[d][c + 1] + MPM_BRICKS_MARGIN;
    *pa = a > 0 ? a : 0;
    *pb = z < b->ncell[d] ? z : b->ncell[d];
}

/* Global nodes [*lo, *hi) the patch of brick c allocates along d (its
 * nodes and the grid's halo node either side). */
static void alloc_range(const struct mpm_bricks *b, int d, int c, long *lo, long *hi)
{
    long pa, pb;
    patch_cells(b, d, c, &pa, &pb);
    *lo = pa - 1;
    *hi = pb + 2;
}

/* --- plan ------------------------------------------------------------------- */

static int choose_grid(int n, const long ncell[3], int grid[3])
{
    double best = INFINITY;
    for (int px = 1; px <= n; px++) {
        if (n % px)
            continue;
        for (int py = 1; py <= n / px; py++) {
            if ((n / px) % py)
                continue;
            int g[3] = {px, py, n / px / py};
            int ok = 1;
            double w[3];
            for (int d = 0; d < 3; d++) {
                ok &= g[d] == 1 || ncell[d] / g[d] >= MIN_BRICK_CELLS;
                w[d] = (double)ncell[d] / g[d];
            }
            double area = w[0] * w[1] + w[1] * w[2] + w[0] * w[2];
            if (ok && area < best * (1 - 1e-12)) {
                best = area;
                memcpy(grid, g, sizeof g);
            }
        }
    }
    return isfinite(best) ? 0 : -1;
}

int mpm_bricks_plan(const struct parallel *par, const struct parallel_settings *ps,
                    const struct mpm_grid *g, int hierarchical, struct cfg *c,
                    struct mpm_bricks **out)
{
    *out = NULL;
    if (!par || !par->mpi || ps->decomposition == DECOMP_REPLICATED)
        return 0;
    if (ps->decomposition == DECOMP_AUTO && par->size == 1)
        return 0;
    int grid[3] = {1, 1, 1};
    if (ps->grid_given) {
        int grid_rc = parallel_settings_check_grid_ranks(c, ps, par->size);
        if (grid_rc != 0)
            return grid_rc;
        for (int d = 0; d < 3; d++) {
            if (ps->grid[d] > 1 && g->ncell[d] / ps->grid[d] < MIN_BRICK_CELLS)
                return cfg_error_at(c, "parallel.grid",
                                    "bricks of %ld / %d cells along %c are thinner than %d "
                                    "cells (the patch of a neighbour reaches %d nodes in)",
                                    g->ncell[d], ps->grid[d], "xyz"[d], MIN_BRICK_CELLS,
                                    MPM_BRICKS_MARGIN + 2);
            grid[d] = ps->grid[d];
        }
    } else if (choose_grid(par->size, g->ncell, grid) != 0) {
        if (ps->decomposition == DECOMP_BRICKS)
            return cfg_error_at(c, "parallel.decomposition",
                                "no grid of %d bricks of the %ld x %ld x %ld-cell MPM grid "
                                "has bricks at least %d cells wide; use fewer ranks or "
                                "decomposition: replicated",
                                par->size, g->ncell[0], g->ncell[1], g->ncell[2],
                                MIN_BRICK_CELLS);
        if (par->rank == 0)
            fprintf(stderr, "note: the %ld x %ld x %ld-cell MPM grid has no grid of %d bricks "
                            "at least %d cells wide: replicated data\n",
                    g->ncell[0], g->ncell[1], g->ncell[2], par->size, MIN_BRICK_CELLS);
        return 0;
    }
    struct mpm_bricks *b = calloc(1, sizeof *b);
    if (!b)
        return err_nomem(c->err, "MPM bricks");
    b->par = par;
    b->whole = hierarchical != 0;
    memcpy(b->grid, grid, sizeof b->grid);
    int nbr[3][2], periodic[3] = {0, 0, 0};
    int rc = parallel_cart(par, grid, periodic, b->coords, nbr, c->err);
    b->serial_nodes = 1;
    for (int d = 0; !rc && d < 3; d++) {
        b->ncell[d] = g->ncell[d];
        b->serial_nodes *= g->ncell[d] + 3;
        b->cut[d] = malloc((size_t)(grid[d] + 1) * sizeof *b->cut[d]);
        if (!b->cut[d]) {
            rc = err_nomem(c->err, "MPM bricks");
            break;
        }
        for (int k = 0; k <= grid[d]; k++)   /* equal shares of the cells */
            b->cut[d][k] = (long)((double)g->ncell[d] * k / grid[d] + 0.5);
    }
    if (b->whole)   /* every rank holds the hierarchical grid's nodes */
        b->serial_nodes = g->nnodes;
    b->shift = ps->balance == BALANCE_SHIFT;
    if (!rc && rank_of(b, b->coords) != par->rank)
        rc = err_set(c->err, ERR_RUNTIME, "MPM bricks: rank %d sits at brick %d %d %d",
                     par->rank, b->coords[0], b->coords[1], b->coords[2]);
    if (rc) {
        mpm_bricks_destroy(&b);
        return rc;
    }
    *out = b;
    return 0;
}

void mpm_bricks_destroy(struct mpm_bricks **bp)
{
    struct mpm_bricks *b = *bp;
    if (!b)
        return;
    for (int d = 0; d < 3; d++)
        free(b->cut[d]);
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        free(b->link[k].ghost);
        free(b->link[k].owned);
    }
    free(b->is_ghost);
    free(b->sbuf);
    free(b->rbuf);
    free(b->pbuf);
    free(b->prbuf);
    free(b->wbuf);
    if (b->shared) {
        mpm_shared_free(b->shared);
        free(b->shared);
    }
    free(b);
    *bp = NULL;
}

/* --- collectives ------------------------------------------------------------ */

void mpm_bricks_sum(const struct mpm_bricks *b, double *buf, int n)
{
    if (b)
        parallel_sum(b->par, buf, (size_t)n);
}

void mpm_bricks_max(const struct mpm_bricks *b, double *buf, int n)
{
    if (b)
        parallel_max(b->par, buf, (size_t)n);
}

int mpm_bricks_agree(const struct mpm_bricks *b, int rc, struct err *e)
{
    if (!b || b->par->size < 2)
        return rc;
    if (parallel_any(b->par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    return rc;
}

int mpm_bricks_rank(const struct mpm_bricks *b)
{
    return b ? b->par->rank : 0;
}

long mpm_bricks_npoints(const struct mpm_bricks *b, const struct mpm *m)
{
    double n = (double)m->pts.n;
    mpm_bricks_sum(b, &n, 1);
    return (long)n;
}

void mpm_bricks_totals(const struct mpm_bricks *b, const struct mpm *m, struct mpm_totals *t)
{
    mpm_totals(m, t);
    if (!b)
        return;
    double s[6] = {t->mass, t->momentum[0], t->momentum[1], t->momentum[2], t->kinetic,
                   t->strain};
    mpm_bricks_sum(b, s, 6);
    mpm_bricks_max(b, &t->vmax, 1);
    *t = (struct mpm_totals){s[0], {s[1], s[2], s[3]}, s[4], s[5], t->vmax};
}

/* --- the patch and its links ------------------------------------------------ */

/* Offset k of the 26 as (dx, dy, dz). */
static void offset_of(int k, int o[3])
{
    int q = k < 13 ? k : k + 1;   /* skip (0, 0, 0) */
    o[0] = q % 3 - 1;
    o[1] = (q / 3) % 3 - 1;
    o[2] = q / 9 - 1;
}

/* The patch indices of the global nodes in the box [lo, hi) (z, y, x
 * order) into *list. */
static int box_list(const struct mpm_grid *g, const long lo[3], const long hi[3], int32_t **list,
                    long *n, struct err *e)
{
    long cnt = 1;
    for (int d = 0; d < 3; d++)
        cnt *= hi[d] > lo[d] ? hi[d] - lo[d] : 0;
    *n = cnt;
    *list = NULL;
    if (cnt == 0)
        return 0;
    *list = malloc((size_t)cnt * sizeof **list);
    if (!*list)
        return err_nomem(e, "MPM halo lists");
    long k = 0;
    for (long z = lo[2]; z < hi[2]; z++)
        for (long y = lo[1]; y < hi[1]; y++)
            for (long x = lo[0]; x < hi[0]; x++) {
                long i = (x - g->lo[0] + g->halo) + (y - g->lo[1] + g->halo) * g->stride[1] +
                         (z - g->lo[2] + g->halo) * g->stride[2];
                (*list)[k++] = (int32_t)i;
            }
    return 0;
}

static int reserve_doubles(double **buf, size_t *cap, size_t n, struct err *e)
{
    if (n <= *cap)
        return 0;
    double *p = realloc(*buf, n * sizeof *p);
    if (!p)
        return err_nomem(e, "MPM halo buffer");
    *buf = p;
    *cap = n;
    return 0;
}

/* The ranks at coords + o and coords - o of the 26 offsets (-1: none):
 * whom the points of a link go to and come from. */
static void link_ranks(struct mpm_bricks *b)
{
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        int o[3], to[3], from[3];
        offset_of(k, o);
        for (int d = 0; d < 3; d++) {
            to[d] = b->coords[d] + o[d];
            from[d] = b->coords[d] - o[d];
        }
        b->link[k].rank_to = rank_of(b, to);
        b->link[k].rank_from = rank_of(b, from);
    }
}

static int build_links(struct mpm_bricks *b, const struct mpm_grid *g, struct err *e)
{
    long nghost_total = 0;
    link_ranks(b);
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        struct mpm_bricks_link *L = &b->link[k];
        int o[3], to[3], from[3];
        offset_of(k, o);
        for (int d = 0; d < 3; d++) {
            to[d] = b->coords[d] + o[d];
            from[d] = b->coords[d] - o[d];
        }
        long lo[3], hi[3], a, z;
        if (L->rank_to >= 0) {   /* my patch's nodes that brick `to` owns */
            for (int d = 0; d < 3; d++) {
                alloc_range(b, d, b->coords[d], &lo[d], &hi[d]);
                owned_range(b, d, to[d], &a, &z);
                lo[d] = lo[d] > a ? lo[d] : a;
                hi[d] = hi[d] < z ? hi[d] : z;
            }
            int rc = box_list(g, lo, hi, &L->ghost, &L->nghost, e);
            if (rc)
                return rc;
            nghost_total += L->nghost;
        }
        if (L->rank_from >= 0) {   /* my nodes in the patch of brick `from` */
            for (int d = 0; d < 3; d++) {
                owned_range(b, d, b->coords[d], &lo[d], &hi[d]);
                alloc_range(b, d, from[d], &a, &z);
                lo[d] = lo[d] > a ? lo[d] : a;
                hi[d] = hi[d] < z ? hi[d] : z;
            }
            int rc = box_list(g, lo, hi, &L->owned, &L->nowned, e);
            if (rc)
                return rc;
        }
    }
    /* every patch node I do not own is a ghost of exactly one neighbour */
    b->is_ghost = calloc((size_t)g->nnodes, 1);
    if (!b->is_ghost)
        return err_nomem(e, "MPM halo lists");
    long nown = 1;
    for (int d = 0; d < 3; d++) {
        long lo, hi, a, z;
        alloc_range(b, d, b->coords[d], &lo, &hi);
        owned_range(b, d, b->coords[d], &a, &z);
        nown *= (hi < z ? hi : z) - (lo > a ? lo : a);
    }
    long most = 0;
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        for (long i = 0; i < b->link[k].nghost; i++)
            b->is_ghost[b->link[k].ghost[i]] = 1;
        most = b->link[k].nghost > most ? b->link[k].nghost : most;
        most = b->link[k].nowned > most ? b->link[k].nowned : most;
    }
    /* the largest message of a node pass: the passes then allocate nothing
     * and cannot fail on one rank alone */
    int rc = reserve_doubles(&b->sbuf, &b->scap, (size_t)(8 * most + 1), e);
    if (!rc)
        rc = reserve_doubles(&b->rbuf, &b->rcap, (size_t)(8 * most + 1), e);
    if (rc)
        return rc;
    if (nown + nghost_total != g->nnodes)
        return err_set(e, ERR_RUNTIME, "MPM bricks: the patch of %ld nodes has %ld owned and "
                                       "%ld ghost nodes",
                       g->nnodes, nown, nghost_total);
    return 0;
}

/* --- node halo --------------------------------------------------------------- */

/* A whole grid without shared-node sums (a uniform grid in fixed-owner
 * mode, mpm_bricks_create_fixed): the nodes' partial sums
 * (nc doubles per node, contiguous: stride == nc) summed over the ranks in
 * place, the same bits on every rank (parallel_sum reduces on rank 0 and
 * broadcasts), so every rank then updates every node identically (the
 * forward pass is nothing).  aux_max: the last value of a node (the rigid
 * body + 1 whose points touch it) is a maximum, not a sum; reduced apart
 * only when the case has a rigid body (else it is 0 on every rank).  The
 * buffer is reserved at set-up: the reduction fails on no rank alone. */
static int whole_sum(struct mpm_bricks *b, double *base, int stride, int nc, int aux_max,
                     long nnodes, struct err *e)
{
    if (stride != nc)
        return err_set(e, ERR_RUNTIME, "MPM bricks: whole-grid sums of strided values");
    if (!aux_max || !b->rigid) {
        parallel_sum(b->par, base, (size_t)nnodes * (size_t)nc);
        return 0;
    }
    if ((size_t)nnodes > b->wcap)
        return err_set(e, ERR_RUNTIME, "MPM bricks: %ld nodes, aux buffer of %zu", nnodes,
                       b->wcap);
    for (long i = 0; i < nnodes; i++) {
        b->wbuf[i] = base[i * nc + nc - 1];
        base[i * nc + nc - 1] = 0;
    }
    parallel_sum(b->par, base, (size_t)nnodes * (size_t)nc);
    parallel_max(b->par, b->wbuf, (size_t)nnodes);
    for (long i = 0; i < nnodes; i++)
        base[i * nc + nc - 1] = b->wbuf[i];
    return 0;
}

/* The values are nc doubles per node at base + stride * i.  reverse: the
 * ghosts' values are added to (aux_max: the last one taken as a maximum,
 * the rigid body of the node) their owners, then zeroed; forward: the
 * owners' values overwrite the ghosts'. */
static int node_exchange(struct mpm_bricks *b, double *base, int stride, int nc, int reverse,
                         int aux_max, long nnodes, struct err *e)
{
    if (b->whole && !reverse)
        return 0;   /* every rank's sums of its nodes are complete */
    if (b->shared)
        return stride == nc ? mpm_shared_sum(b->shared, base, nc, aux_max, e)
                            : err_set(e, ERR_RUNTIME, "MPM bricks: shared-node sums of strided "
                                                      "values");
    if (b->whole)
        return whole_sum(b, base, stride, nc, aux_max, nnodes, e);
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        struct mpm_bricks_link *L = &b->link[k];
        if (L->rank_to < 0 && L->rank_from < 0)
            continue;
        /* reverse: ghosts to their owner (+o), my owned from -o; forward:
         * my owned to -o, my ghosts from +o */
        const int32_t *slist = reverse ? L->ghost : L->owned;
        long ns = reverse ? L->nghost : L->nowned;
        const int32_t *rlist = reverse ? L->owned : L->ghost;
        long nr = reverse ? L->nowned : L->nghost;
        int dest = reverse ? L->rank_to : L->rank_from;
        int src = reverse ? L->rank_from : L->rank_to;
        if (dest < 0)
            ns = 0;
        if (src < 0)
            nr = 0;
        int rc = reserve_doubles(&b->sbuf, &b->scap, (size_t)(ns * nc + 1), e);
        if (!rc)
            rc = reserve_doubles(&b->rbuf, &b->rcap, (size_t)(nr * nc + 1), e);
        if (rc)
            return rc;
        for (long i = 0; i < ns; i++)
            memcpy(b->sbuf + i * nc, base + (long)slist[i] * stride, (size_t)nc * sizeof(double));
        rc = parallel_sendrecv_known(b->par, dest, b->sbuf, (size_t)ns * nc * sizeof(double), src,
                                     b->rbuf, (size_t)nr * nc * sizeof(double), e);
        if (rc)
            return rc;
        for (long i = 0; i < nr; i++) {
            double *dst = base + (long)rlist[i] * stride;
            const double *v = b->rbuf + i * nc;
            if (!reverse) {
                memcpy(dst, v, (size_t)nc * sizeof(double));
                continue;
            }
            int nsum = aux_max ? nc - 1 : nc;
            for (int c = 0; c < nsum; c++)
                dst[c] += v[c];
            if (aux_max && v[nc - 1] > dst[nc - 1])
                dst[nc - 1] = v[nc - 1];
        }
    }
    if (reverse)
        for (long i = 0; i < nnodes; i++)
            if (b->is_ghost[i])
                memset(base + i * stride, 0, (size_t)nc * sizeof(double));
    return 0;
}

/* A node record as 8 doubles (m, q, f, aux; checked in model_mpm.c). */
_Static_assert(sizeof(struct mpm_node) == 8 * sizeof(double), "mpm_node is 8 doubles");

static int nodes_reverse(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    struct mpm_grid *g = &m->grid;
    if (b->shared) {   /* the nodes this rank's particles now touch (located by the map) */
        int rc = mpm_shared_plan(b->shared, m, e);
        if (rc)
            return rc;
        g->active = b->shared->touched;   /* the grid stages visit only these */
        g->nactive = b->shared->ntouched;
        g->active_first = b->shared->first;
    }
    return node_exchange(b, (double *)g->node, 8, 8, 1, 1, g->nnodes, e);
}

static int nodes_forward(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    struct mpm_grid *g = &m->grid;
    return node_exchange(b, (double *)g->node, 8, 8, 0, 0, g->nnodes, e);
}

/* --- points ------------------------------------------------------------------- */

static long point_doubles(const struct mpm_points *p)
{
    return 3 + 3 + 3 + 1 + 1 + 1 + 6 + 9 + 1 + p->nstate + (p->fext ? 3 : 0) + 3;
}

static void pack_point(const struct mpm_points *p, long i, double *r)
{
    long k = 0;
    memcpy(r + k, p->x + 3 * i, 3 * sizeof *r), k += 3;
    memcpy(r + k, p->x0 + 3 * i, 3 * sizeof *r), k += 3;
    memcpy(r + k, p->v + 3 * i, 3 * sizeof *r), k += 3;
    r[k++] = p->mass[i];
    r[k++] = p->vol0[i];
    r[k++] = p->vol[i];
    memcpy(r + k, p->stress + 6 * i, 6 * sizeof *r), k += 6;
    memcpy(r + k, p->F + 9 * i, 9 * sizeof *r), k += 9;
    r[k++] = p->eint[i];
    if (p->nstate)
        memcpy(r + k, p->state + (long)p->nstate * i, (size_t)p->nstate * sizeof *r);
    k += p->nstate;
    if (p->fext) {
        memcpy(r + k, p->fext + 3 * i, 3 * sizeof *r);
        k += 3;
    }
    int64_t body = p->body[i], mask = p->mask[i];
    memcpy(r + k++, &body, sizeof body);
    memcpy(r + k++, &p->id[i], sizeof p->id[i]);
    memcpy(r + k++, &mask, sizeof mask);
}

static void unpack_point(struct mpm_points *p, long i, const double *r)
{
    long k = 0;
    memcpy(p->x + 3 * i, r + k, 3 * sizeof *r), k += 3;
    memcpy(p->x0 + 3 * i, r + k, 3 * sizeof *r), k += 3;
    memcpy(p->v + 3 * i, r + k, 3 * sizeof *r), k += 3;
    p->mass[i] = r[k++];
    p->vol0[i] = r[k++];
    p->vol[i] = r[k++];
    memcpy(p->stress + 6 * i, r + k, 6 * sizeof *r), k += 6;
    memcpy(p->F + 9 * i, r + k, 9 * sizeof *r), k += 9;
    p->eint[i] = r[k++];
    if (p->nstate)
        memcpy(p->state + (long)p->nstate * i, r + k, (size_t)p->nstate * sizeof *r);
    k += p->nstate;
    if (p->fext) {
        memcpy(p->fext + 3 * i, r + k, 3 * sizeof *r);
        k += 3;
    }
    int64_t body, mask;
    memcpy(&body, r + k++, sizeof body);
    memcpy(&p->id[i], r + k++, sizeof p->id[i]);
    memcpy(&mask, r + k++, sizeof mask);
    p->body[i] = (int32_t)body;
    p->mask[i] = (uint32_t)mask;
}

/* Copy point i of src to slot j of dst (same layout). */
static void copy_point(struct mpm_points *dst, long j, const struct mpm_points *src, long i)
{
    double rec[64 + 3 * 3 + 16];
    double *r = src->nstate > 32 ? malloc((size_t)point_doubles(src) * sizeof *r) : rec;
    if (!r)
        return;
    pack_point(src, i, r);
    unpack_point(dst, j, r);
    if (r != rec)
        free(r);
}

/* The brick coordinates of the cell holding x (clamped to the grid). */
static void point_brick(const struct mpm_bricks *b, const struct mpm_grid *g, const double *x,
                        int c[3], long cell[3])
{
    for (int d = 0; d < 3; d++) {
        double u = floor((x[d] - g->origin[d]) * g->inv_hd[d]);
        long k = !(u >= 0) ? 0 : u >= (double)b->ncell[d] ? b->ncell[d] - 1 : (long)u;
        cell[d] = k;
        c[d] = cell_owner(b, d, k);
    }
}

/* Offset index (0..25) from me to brick c, -1 for me, -2 beyond the
 * neighbours. */
static int offset_index(const struct mpm_bricks *b, const int c[3])
{
    int q = 0, mul = 1, self = 1;
    for (int d = 0; d < 3; d++) {
        int o = c[d] - b->coords[d];
        if (o < -1 || o > 1)
            return -2;
        self &= o == 0;
        q += (o + 1) * mul;
        mul *= 3;
    }
    if (self)
        return -1;
    return q < 13 ? q : q - 1;
}

/* Points whose cell another brick owns go to it (one of the 26
 * neighbours: a point moves less than a cell per step).  Collective. */
/* Whether the point at x lies in a cell of this rank's brick: the common
 * case, decided without looking up the owner of each axis' cell (the
 * clamping is point_brick's). */
static int point_in_own_brick(const struct mpm_bricks *b, const struct mpm_grid *g,
                              const double *x)
{
    int in = 1;
    for (int d = 0; d < 3; d++) {
        double u = floor((x[d] - g->origin[d]) * g->inv_hd[d]);
        long k = !(u >= 0) ? 0 : u >= (double)b->ncell[d] ? b->ncell[d] - 1 : (long)u;
        in &= k >= b->cut[d][b->coords[d]] && k < b->cut[d][b->coords[d] + 1];
    }
    return in;
}

/* Offset index of the brick the point at x belongs to (offset_index). */
static int point_offset(const struct mpm_bricks *b, const struct mpm_grid *g, const double *x)
{
    if (point_in_own_brick(b, g, x))
        return -1;
    int c[3];
    long cell[3];
    point_brick(b, g, x, c, cell);
    return offset_index(b, c);
}

/* How many of this rank's points have a cell another brick owns, and the
 * id of one beyond the neighbours (-1: none). */
static void scan_leavers(const struct mpm_bricks *b, const struct mpm *m, long *nleave,
                         long long *far_id)
{
    const struct mpm_points *p = &m->pts;
    long count = 0, far = -1;
    for (long i = 0; i < p->n; i++) {
        int q = point_offset(b, &m->grid, p->x + 3 * i);
        if (q == -2 && far < 0)
            far = i;
        if (q >= 0)
            count++;
    }
    *nleave = count;
    *far_id = far >= 0 ? (long long)p->id[far] : -1;
}

/* The reorder's scratch follows the point count. */
static int reserve_scratch(struct mpm *m, struct err *e)
{
    long n = m->pts.n;
    if (m->scratch_cap >= n)
        return 0;
    free(m->scratch);
    m->scratch_cap = n + n / 8 + 16;
    m->scratch = malloc((size_t)m->scratch_cap * sizeof *m->scratch);
    if (m->scratch)
        return 0;
    m->scratch_cap = 0;
    return err_nomem(e, "reorder scratch");
}

static int migrate(struct mpm_bricks *b, struct mpm *m, long *moved, struct err *e)
{
    struct mpm_points *p = &m->pts;
    long n = p->n, rec = point_doubles(p);
    long cnt[MPM_BRICKS_NBR] = {0}, nleave;
    long long far_id;
    int8_t *dest = NULL;
    *moved = 0;
    double flag[2];
    if (b->scan_valid) {   /* scanned and reduced at the end of the last step */
        nleave = b->scan_nleave;
        far_id = b->scan_far_id;
        flag[0] = b->scan_any_far;
        flag[1] = b->scan_any_leave;
        b->scan_valid = 0;
    } else {
        scan_leavers(b, m, &nleave, &far_id);
        /* one reduction: did a point move beyond the neighbours, does any leave */
        flag[0] = far_id >= 0;
        flag[1] = nleave > 0;
        parallel_max(b->par, flag, 2);
    }
    if (far_id >= 0)
        return err_set(e, ERR_DIVERGED, "material point %lld moved more than a brick in one step "
                                        "(step %ld)",
                       far_id, m->step);
    if (flag[0] > 0)
        return err_set_elsewhere(e, ERR_DIVERGED,
                                 "step %ld: a material point moved more than a brick "
                                 "in one step (on another MPI rank)",
                                 m->step);
    if (flag[1] == 0)
        return 0;
    int rc = 0;
    if (nleave) {
        dest = malloc((size_t)n);
        if (!dest)
            rc = err_nomem(e, "MPM migration");
    }
    for (long i = 0; !rc && nleave && i < n; i++) {
        int q = point_offset(b, &m->grid, p->x + 3 * i);
        dest[i] = (int8_t)q;
        if (q >= 0)
            cnt[q]++;
    }
    size_t need = (size_t)(nleave * rec + 1) * sizeof(double);
    if (!rc && need > b->pcap) {
        unsigned char *pb = realloc(b->pbuf, need);
        if (!pb)
            rc = err_nomem(e, "MPM migration");
        else {
            b->pbuf = pb;
            b->pcap = need;
        }
    }
    rc = mpm_bricks_agree(b, rc, e);
    if (rc) {
        free(dest);
        return rc;
    }
    /* pack by destination, in point order */
    long start[MPM_BRICKS_NBR + 1];
    start[0] = 0;
    for (int q = 0; q < MPM_BRICKS_NBR; q++)
        start[q + 1] = start[q] + cnt[q];
    long fill[MPM_BRICKS_NBR];
    memcpy(fill, start, sizeof fill);
    double *sb = (double *)b->pbuf;
    long keep = 0;
    for (long i = 0; i < n; i++) {
        if (nleave && dest[i] >= 0) {
            pack_point(p, i, sb + fill[dest[i]]++ * rec);
            continue;
        }
        if (keep != i)
            copy_point(p, keep, p, i);
        keep++;
    }
    free(dest);
    p->n = keep;
    *moved = nleave;
    for (int q = 0; q < MPM_BRICKS_NBR && !rc; q++) {
        struct mpm_bricks_link *L = &b->link[q];
        size_t got = 0;
        rc = parallel_sendrecv(b->par, L->rank_to, sb + start[q] * rec,
                               (size_t)cnt[q] * rec * sizeof(double), L->rank_from, &b->prbuf,
                               &b->prcap, &got, e);
        long nin = (long)(got / (rec * sizeof(double)));
        if (!rc && nin > 0) {
            if (p->n + nin > p->cap)
                rc = mpm_points_reserve(p, p->n + nin + p->n / 8, e);
            for (long k = 0; !rc && k < nin; k++)
                unpack_point(p, p->n++, (const double *)b->prbuf + k * rec);
            *moved += nin;
        }
    }
    if (!rc)
        rc = reserve_scratch(m, e);
    return mpm_bricks_agree(b, rc, e);
}

/* Every point to the rank whose brick holds its cell, wherever that is:
 * one all-to-all (a re-cut may move a face by more than a brick).  The
 * kept points stay in their order; the arrivals follow, in rank order.
 * Collective. */
static int migrate_to_owners(struct mpm_bricks *b, struct mpm *m, long *moved, struct err *e)
{
    const struct parallel *par = b->par;
    struct mpm_points *p = &m->pts;
    int nr = par->size, me = par->rank;
    long n = p->n, rec = point_doubles(p);
    size_t rbytes = (size_t)rec * sizeof(double);
    int *dest = malloc((size_t)(n > 0 ? n : 1) * sizeof *dest);
    int *cnt = calloc((size_t)nr * 4, sizeof *cnt);
    long *nsend = calloc((size_t)nr, sizeof *nsend);
    unsigned char *sb = NULL, *rb = NULL;
    int rc = dest && cnt && nsend ? 0 : err_nomem(e, "MPM re-cut");
    long nout = 0;
    for (long i = 0; !rc && i < n; i++) {
        int c[3];
        long cell[3];
        point_brick(b, &m->grid, p->x + 3 * i, c, cell);
        dest[i] = rank_of(b, c);
        if (dest[i] != me) {
            nsend[dest[i]]++;
            nout++;
        }
    }
    int *scount = cnt, *sdispl = cnt + nr, *rcount = cnt + 2 * nr, *rdispl = cnt + 3 * nr;
    if (!rc && (double)nout * (double)rbytes > INT_MAX)   /* MPI's counts are ints */
        rc = err_set(e, ERR_RUNTIME,
                     "MPM re-cut: %ld points (%.0f bytes) to send from rank %d, more than one "
                     "MPI message holds",
                     nout, (double)nout * (double)rbytes, me);
    if (!rc) {
        for (int r = 0, off = 0; r < nr; r++) {
            scount[r] = (int)((size_t)nsend[r] * rbytes);
            sdispl[r] = off;
            off += scount[r];
        }
        sb = malloc((size_t)nout * rbytes + 1);
        if (!sb)
            rc = err_nomem(e, "MPM re-cut");
    }
    rc = mpm_bricks_agree(b, rc, e);
    if (!rc) {   /* pack by destination rank, in point order; compact the kept ones */
        long *fill = nsend;   /* reused: the next record of each rank */
        for (int r = 0; r < nr; r++)
            fill[r] = sdispl[r] / (long)rbytes;
        long keep = 0;
        for (long i = 0; i < n; i++) {
            if (dest[i] != me) {
                pack_point(p, i, (double *)(sb + (size_t)fill[dest[i]]++ * rbytes));
                continue;
            }
            if (keep != i)
                copy_point(p, keep, p, i);
            keep++;
        }
        p->n = keep;
        rc = parallel_alltoall_int(par, scount, rcount, e);
    }
    long nin = 0;
    if (!rc) {
        double total = 0;
        for (int r = 0; r < nr; r++)
            total += rcount[r];
        if (total > INT_MAX)
            rc = err_set(e, ERR_RUNTIME,
                         "MPM re-cut: %.0f bytes of points to receive on rank %d, more than "
                         "one MPI message holds",
                         total, me);
        for (int r = 0, off = 0; !rc && r < nr; r++) {
            rdispl[r] = off;
            off += rcount[r];
        }
        nin = (long)(total / (double)rbytes);
        if (!rc && !(rb = malloc((size_t)total + 1)))
            rc = err_nomem(e, "MPM re-cut");
        if (!rc && p->n + nin > p->cap)
            rc = mpm_points_reserve(p, p->n + nin + p->n / 8, e);
    }
    rc = mpm_bricks_agree(b, rc, e);
    if (!rc)
        rc = parallel_alltoallv_bytes(par, sb, scount, sdispl, rb, rcount, rdispl, e);
    for (long k = 0; !rc && k < nin; k++)
        unpack_point(p, p->n++, (const double *)(rb + (size_t)k * rbytes));
    *moved = nout + nin;
    if (!rc)
        rc = reserve_scratch(m, e);
    free(dest);
    free(cnt);
    free(nsend);
    free(sb);
    free(rb);
    return mpm_bricks_agree(b, rc, e);
}

/* The node sums of a whole grid: on more than one rank only the shared
 * nodes are exchanged (mpm_shared.h; a rigid body's mark taken as a
 * maximum, its reaction counted on the nodes a rank is the lowest toucher
 * of); on one rank every node is "reduced" (whole_sum, nothing to send). */
static int whole_sums_init(struct mpm_bricks *b, const struct mpm *m, struct err *e)
{
    b->rigid = 0;
    for (int k = 0; k < m->nbody; k++)
        b->rigid |= m->body[k].rigid != 0;
    if (!b->par || b->par->size < 2) {   /* whole_sum: all nodes */
        if (!b->rigid)
            return 0;
        b->wbuf = malloc((size_t)(m->grid.nnodes > 0 ? m->grid.nnodes : 1) * sizeof *b->wbuf);
        b->wcap = b->wbuf ? (size_t)m->grid.nnodes : 0;
        return b->wbuf ? 0 : err_nomem(e, "MPM whole-grid sums");
    }
    b->shared = malloc(sizeof *b->shared);
    if (!b->shared)
        return err_nomem(e, "MPM shared nodes");
    int rc = mpm_shared_init(b->shared, b->par, m, e);
    if (rc) {
        free(b->shared);
        b->shared = NULL;
    }
    return rc;
}

int mpm_bricks_create_fixed(const struct parallel *par, const struct mpm *m,
                            struct mpm_bricks **out, struct err *e)
{
    *out = NULL;
    struct mpm_bricks *b = calloc(1, sizeof *b);
    int rc = b ? 0 : err_nomem(e, "MPM bricks");
    if (b) {
        b->par = par;
        b->whole = b->fixed = 1;
        for (int d = 0; d < 3; d++)
            b->grid[d] = 1;   /* no cuts: the caller dealt the points out */
        b->serial_nodes = m->grid.nnodes;
        rc = whole_sums_init(b, m, e);
    }
    if (par && par->size > 1 && parallel_any(par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    if (rc) {
        mpm_bricks_destroy(&b);
        return rc;
    }
    *out = b;
    return 0;
}

/* Shifted boundaries (parallel.balance: shift), as decomp_shift does for
 * particles, from the points counted along each axis before they were
 * made (every rank counted all of them, so every rank computes the same
 * cuts). */
int mpm_bricks_hist_init(const struct mpm_bricks *b, struct mpm_bricks_hist *h, struct err *e)
{
    memset(h, 0, sizeof *h);
    for (int d = 0; d < 3; d++) {
        if (b->grid[d] < 2)
            continue;
        h->layer[d] = calloc((size_t)b->ncell[d], sizeof *h->layer[d]);
        if (!h->layer[d]) {
            mpm_bricks_hist_free(h);
            return err_nomem(e, "MPM balance");
        }
    }
    return 0;
}

void mpm_bricks_hist_add(const struct mpm_bricks *b, const struct mpm_grid *g,
                         struct mpm_bricks_hist *h, const double x[3])
{
    for (int d = 0; d < 3; d++) {
        if (!h->layer[d])
            continue;
        long nc = b->ncell[d];
        double u = floor((x[d] - g->origin[d]) * g->inv_hd[d]);
        h->layer[d][!(u >= 0) ? 0 : u >= (double)nc ? nc - 1 : (long)u]++;
    }
    h->n++;
}

void mpm_bricks_hist_free(struct mpm_bricks_hist *h)
{
    for (int d = 0; d < 3; d++) {
        free(h->layer[d]);
        h->layer[d] = NULL;
    }
}

void mpm_bricks_shift_cuts(struct mpm_bricks *b, const struct mpm_bricks_hist *h)
{
    for (int d = 0; d < 3; d++) {
        int P = b->grid[d];
        long nc = b->ncell[d];
        const long *hist = h->layer[d];
        if (P < 2 || h->n == 0 || !hist)
            continue;
        long acc = 0, k = 0;
        for (int c = 1; c < P; c++) {   /* the first cell after c / P of the points */
            long want = (long)((double)h->n * c / P + 0.5);
            while (k < nc && acc + hist[k] <= want)
                acc += hist[k++];
            b->cut[d][c] = k;
        }
        for (int c = 1; c < P; c++)   /* wide enough bricks, from below then from above */
            if (b->cut[d][c] < b->cut[d][c - 1] + MIN_BRICK_CELLS)
                b->cut[d][c] = b->cut[d][c - 1] + MIN_BRICK_CELLS;
        for (int c = P - 1; c >= 1; c--)
            if (b->cut[d][c] > b->cut[d][c + 1] - MIN_BRICK_CELLS)
                b->cut[d][c] = b->cut[d][c + 1] - MIN_BRICK_CELLS;
    }
}

int mpm_bricks_owns_point(const struct mpm_bricks *b, const struct mpm_grid *g, const double x[3])
{
    return point_in_own_brick(b, g, x);
}

static int owner_keeps(const void *ctx, const double x[3])
{
    const struct mpm_bricks_owner *o = ctx;
    return point_in_own_brick(o->b, o->g, x);
}

struct mpm_fill_owner mpm_bricks_fill_owner(const struct mpm_bricks_owner *o)
{
    struct mpm_fill_owner f = {owner_keeps, o};
    return f;
}

/* A hierarchical grid: the grid stays whole on every rank; reserve the
 * reduction's buffer. */
static int distribute_whole(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    link_ranks(b);   /* the points' neighbours; no node lists */
    return mpm_bricks_agree(b, whole_sums_init(b, m, e), e);
}

/* The node lists of the links and the ghost marks, before new ones are
 * built (build_links). */
static void free_links(struct mpm_bricks *b)
{
    for (int k = 0; k < MPM_BRICKS_NBR; k++) {
        struct mpm_bricks_link *L = &b->link[k];
        free(L->ghost);
        free(L->owned);
        L->ghost = L->owned = NULL;
        L->nghost = L->nowned = 0;
    }
    free(b->is_ghost);
    b->is_ghost = NULL;
}

/* m's uniform grid (the serial grid the case built, or this rank's patch
 * under the cuts before a re-cut: only its origin, cell, shape and faces
 * are read) replaced by the patch of this rank's brick under the present
 * cuts, with its node lists; the patch's nodes are zero. */
static int make_patch(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    struct mpm_grid *old = &m->grid, patch;
    long pa[3], pb[3], npatch[3];
    for (int d = 0; d < 3; d++) {
        patch_cells(b, d, b->coords[d], &pa[d], &pb[d]);
        npatch[d] = pb[d] - pa[d];
    }
    double origin[3];
    memcpy(origin, old->origin, sizeof origin);
    int rc = mpm_grid_init_uniform(&patch, origin, old->h, npatch, old->shape, e);
    if (rc)
        return rc;
    /* the patch's nodes are numbered from its first global node; the grid's
     * faces and cells stay the serial grid's */
    for (int d = 0; d < 3; d++) {
        patch.lo[d] = pa[d];
        patch.ncell[d] = b->ncell[d];
    }
    rc = mpm_grid_set_faces(&patch, old->face, e);
    free_links(b);
    if (!rc)
        rc = build_links(b, &patch, e);
    /* the brick's cells in the keys of the patch (mpm_lin_cell: the global
     * cell less the patch's first), for the fused pass's leaver count */
    m->own_keys = 1;
    for (int d = 0; d < 3; d++) {
        m->own_lo[d] = b->cut[d][b->coords[d]] - pa[d];
        m->own_hi[d] = b->cut[d][b->coords[d] + 1] - pa[d];
    }
    if (rc) {
        mpm_grid_free(&patch);
        return rc;
    }
    mpm_grid_free(old);
    m->grid = patch;
    /* the bins' block counts were sized for the serial grid */
    for (int s = 0; s <= MPM_MAX_EXTRA; s++) {
        free(m->bins[s].start);
        free(m->bins[s].count);
        m->bins[s].start = NULL;
        m->bins[s].count = NULL;
        m->bins[s].count_cap = 0;
        m->bins[s].blk_step = -1;
    }
    mpm_points_moved(m);
    return 0;
}

int mpm_bricks_distribute(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    if (b->whole)
        return distribute_whole(b, m, e);
    return mpm_bricks_agree(b, make_patch(b, m, e), e);
}

/* The fused pass's mapping of the coming step dropped: the grid holds this
 * step's velocities again (snapshots read them) and the next step maps
 * afresh. */
static void drop_fused_mapping(struct mpm *m)
{
    if (m->fused_ready) {
        struct mpm_grid *g = &m->grid;
        struct mpm_node *t = g->node;
        g->node = g->node_next;
        g->node_next = t;
    }
    m->fused_ready = m->grid_fresh = 0;
}

int mpm_bricks_recut(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    long moved = 0;
    int rc = migrate_to_owners(b, m, &moved, e);
    if (rc)
        return rc;
    /* a fused mapping was summed on the old patch, of points some of
     * which have left: every rank maps afresh */
    drop_fused_mapping(m);
    b->scan_valid = 0;   /* the last step's leaver scan used the old cuts */
    m->bins[0].blk_step = -1;
    mpm_points_moved(m);
    if (!b->whole)
        rc = make_patch(b, m, e);
    return mpm_bricks_agree(b, rc, e);
}

int mpm_bricks_prepare(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    int rc = mpm_bricks_agree(b, mpm_prepare(m, e), e);
    if (rc)
        return rc;
    /* the lightest point and the largest speed of all ranks; the energies
     * summed over the ranks */
    double mmin = INFINITY;
    for (long i = 0; i < m->pts.n; i++)
        mmin = fmin(mmin, m->pts.mass[i]);
    double mx[2] = {-mmin, m->vmax};
    mpm_bricks_max(b, mx, 2);
    m->small_mass = isfinite(mx[0]) ? m->small_mass_rel * -mx[0] : 0.0;
    m->vmax = mx[1];
    double s[2] = {m->ke, m->strain};
    mpm_bricks_sum(b, s, 2);
    m->ke = m->ke_centred = s[0];
    m->strain = m->strain_before = s[1];
    return 0;
}

/* --- the step ------------------------------------------------------------ */

static void tstart(struct mpm *m, enum timer_id t)
{
    if (m->timers)
        timer_start(m->timers, t);
}

static void tstop(struct mpm *m, enum timer_id t)
{
    if (m->timers)
        timer_stop(m->timers, t);
}

int mpm_bricks_step_map(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    tstart(m, TIMER_COMM);
    long moved = 0;
    int rc = mpm_bricks_balance_step(b, m, e);   /* new cuts when due and needed */
    if (!rc && !b->fixed)                        /* fixed owners: no migration */
        rc = migrate(b, m, &moved, e);
    tstop(m, TIMER_COMM);
    if (rc)
        return rc;
    b->migrated = moved;
    if (moved)   /* indices changed: the cached blocks are stale (the mapping is not) */
        m->bins[0].blk_step = -1;
    int fresh = !(mpm_fusable(m) && m->fused_ready);   /* the same on every rank */
    rc = mpm_bricks_agree(b, mpm_step_map(m, e), e);
    if (rc || !fresh)
        return rc;   /* a fused mapping was reduced by the last update */
    tstart(m, TIMER_COMM);
    rc = nodes_reverse(b, m, e);
    tstop(m, TIMER_COMM);
    return rc;
}

int mpm_bricks_map_initial(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    int rc = mpm_bricks_agree(b, mpm_locate_particles(m, e), e);
    if (rc)
        return rc;
    mpm_clear_grid(m);
    mpm_map_to_grid(m, MPM_MAP_ALL);
    return mpm_bricks_agree(b, nodes_reverse(b, m, e), e);
}

int mpm_bricks_complete_grid(struct mpm_bricks *b, const struct mpm *m, struct mpm_node **node,
                             double **r, struct err *e)
{
    *node = NULL;
    *r = NULL;
    if (!b->shared)
        return 0;
    /* rank 0's copies (its own arrays stay zero beyond its touched nodes,
     * which the grid stages rely on: mpm_grid.h, `active`); the other
     * ranks send their nodes a window at a time and hold no copy */
    const struct mpm_grid *g = &m->grid;
    size_t nn = (size_t)(g->nnodes > 0 ? g->nnodes : 1);
    int root = mpm_bricks_rank(b) == 0;
    struct mpm_node *cn = root ? malloc(nn * sizeof *cn) : NULL;
    double *cr = root ? malloc(nn * 4 * sizeof *cr) : NULL;
    int rc = mpm_bricks_agree(b, root && !(cn && cr) ? err_nomem(e, "MPM grid snapshot") : 0, e);
    if (!rc)
        rc = mpm_shared_gather_root(b->shared, (const double *)g->node, 8, (double *)cn, e);
    if (!rc && g->r)   /* the remap's arrays: every rank has them or none */
        rc = mpm_shared_gather_root(b->shared, g->r, 4, cr, e);
    else if (!rc && root)
        memset(cr, 0, nn * 4 * sizeof *cr);
    if (rc) {
        free(cn);
        free(cr);
        return rc;
    }
    *node = cn;
    *r = cr;
    return 0;
}

void mpm_bricks_shared_counts(const struct mpm_bricks *b, long *nodes_max, long *plans)
{
    double v[2] = {0, 0};
    if (b && b->shared) {
        v[0] = (double)mpm_shared_nodes(b->shared);
        v[1] = (double)b->shared->rebuilds;
    }
    if (b)
        parallel_max(b->par, v, 2);
    *nodes_max = (long)v[0];
    *plans = (long)v[1];
}

int mpm_bricks_step_update(struct mpm_bricks *b, struct mpm *m, double dt, struct err *e)
{
    struct mpm_grid *g = &m->grid;
    int fused = mpm_fusable(m);
    tstart(m, TIMER_MPM_GRID);
    mpm_update_grid(m, dt);                /* s4-s5 on the owned nodes (ghosts are zero) */
    tstop(m, TIMER_MPM_GRID);
    tstart(m, TIMER_COMM);
    int rc = nodes_forward(b, m, e);   /* buffers reserved at set-up: fails on no rank */
    tstop(m, TIMER_COMM);
    if (rc)
        return rc;
    tstart(m, TIMER_MPM_G2P);
    mpm_map_to_particles(m, dt);           /* s6, s10 */
    tstop(m, TIMER_MPM_G2P);
    if (m->algorithm == MPM_MUSL) {
        tstart(m, TIMER_COMM);
        rc = node_exchange(b, g->r, 4, 4, 1, 0, g->nnodes, e);   /* the remap to the owners */
        tstop(m, TIMER_COMM);
        tstart(m, TIMER_MPM_GRID);
        if (!rc)
            mpm_update_grid_velocity(m);   /* s11 */
        tstop(m, TIMER_MPM_GRID);
        tstart(m, TIMER_COMM);
        if (!rc)
            rc = node_exchange(b, g->r, 4, 4, 0, 0, g->nnodes, e);
        tstop(m, TIMER_COMM);
        if (rc)
            return rc;
    }
    tstart(m, TIMER_MPM_G2P);
    m->fused_map_seconds = 0;
    if (fused)
        mpm_update_particles_and_map(m, dt);   /* s7-s8, s12-s14 and s1-s3 of the next step */
    else
        mpm_update_particles(m, dt);           /* s7-s8, s12-s14 */
    tstop(m, TIMER_MPM_G2P);
    if (m->timers && fused) {
        m->timers->total[TIMER_MPM_G2P] -= m->fused_map_seconds;
        m->timers->total[TIMER_MPM_P2G] += m->fused_map_seconds;
    }
    /* a fused mapping is kept only when every rank kept its own and no
     * point left its patch (the pass skips those); the pass counted them */
    int drop = fused && (!m->fused_ready || m->fused_outside > 0);
    /* global: energies, momenta of the rigid bodies' nodes, largest speed */
    double s[3 + 3 * MPM_MAX_BODIES];
    int ns = 0;
    s[ns++] = m->ke;
    s[ns++] = m->ke_centred;
    s[ns++] = m->strain;
    /* a whole grid's reactions are over all nodes already, the same on
     * every rank; with shared-node sums each rank's are over the nodes it
     * is the lowest toucher of */
    int nreact = b->whole && !b->shared ? 0 : m->nbody;
    for (int k = 0; k < nreact; k++)
        for (int d = 0; d < 3; d++)
            s[ns++] = m->body[k].reaction[d];
    /* the next step's migration scan, here so that its flags go with the
     * sums: one collective for energies, speed, fused-map drop and leavers */
    tstart(m, TIMER_COMM);
    b->scan_nleave = 0;
    b->scan_far_id = -1;
    if (!b->fixed && fused && !drop && m->own_keys) {
        /* every point's new cell lies in the patch, one cell at most beyond
         * the brick (MPM_BRICKS_MARGIN), so in a neighbour's brick at the
         * farthest: the pass counted those (mpm.h, own_keys) */
        b->scan_nleave = m->fused_leavers;
    } else if (!b->fixed) {
        scan_leavers(b, m, &b->scan_nleave, &b->scan_far_id);
    }
    double mx[4] = {m->vmax, drop, b->scan_far_id >= 0, b->scan_nleave > 0};
    parallel_sum_max(b->par, s, (size_t)ns, mx, 4);
    b->scan_any_far = mx[2] > 0;
    b->scan_any_leave = mx[3] > 0;
    b->scan_valid = 1;
    ns = 0;
    m->ke = s[ns++];
    m->ke_centred = s[ns++];
    m->strain = s[ns++];
    for (int k = 0; k < nreact; k++)
        for (int d = 0; d < 3; d++)
            m->body[k].reaction[d] = s[ns++];
    m->vmax = mx[0];
    if (fused && mx[1] > 0) {
        drop_fused_mapping(m);   /* back to the velocities of this step; map afresh */
    } else if (fused) {
        rc = nodes_reverse(b, m, e);   /* the next step's s1-s3 to the owners */
    }
    tstop(m, TIMER_COMM);
    if (rc)
        return rc;
    m->time += dt;
    m->step++;
    if (!isfinite(m->vmax))
        return err_set(e, ERR_DIVERGED, "non-finite particle velocity at step %ld", m->step);
    return 0;
}

/* --- gathers for output and checkpoints ------------------------------------ */

static int cmp_id(const void *a, const void *b)
{
    int64_t x = ((const int64_t *)a)[0], y = ((const int64_t *)b)[0];
    return (x > y) - (x < y);
}

int mpm_bricks_sort_by_id(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    struct mpm_points *p = &m->pts;
    long n = p->n;
    int64_t *key = malloc((size_t)(n > 0 ? n : 1) * 2 * sizeof *key);
    int32_t *perm = malloc((size_t)(n > 0 ? n : 1) * sizeof *perm);
    int rc = key && perm ? 0 : err_nomem(e, "MPM point order");
    if (!rc && m->scratch_cap < n) {
        free(m->scratch);
        m->scratch = malloc((size_t)(n > 0 ? n : 1) * sizeof *m->scratch);
        m->scratch_cap = m->scratch ? n : 0;
        if (!m->scratch)
            rc = err_nomem(e, "reorder scratch");
    }
    if (!rc) {
        for (long i = 0; i < n; i++) {
            key[2 * i] = p->id[i];
            key[2 * i + 1] = i;
        }
        qsort(key, (size_t)n, 2 * sizeof *key, cmp_id);
        for (long i = 0; i < n; i++)
            perm[i] = (int32_t)key[2 * i + 1];
        mpm_points_permute(p, perm, m->scratch, m->nthreads);
        mpm_points_moved(m);
    }
    free(key);
    free(perm);
    return mpm_bricks_agree(b, rc, e);
}

void mpm_bricks_node_block(const struct mpm_bricks *b, long lo[3], long hi[3])
{
    for (int d = 0; d < 3; d++) {
        long a, z;
        alloc_range(b, d, b->coords[d], &lo[d], &hi[d]);
        owned_range(b, d, b->coords[d], &a, &z);
        /* the grid's own nodes 0 .. ncell, not its halo's */
        a = a > 0 ? a : 0;
        z = z < b->ncell[d] + 1 ? z : b->ncell[d] + 1;
        lo[d] = lo[d] > a ? lo[d] : a;
        hi[d] = hi[d] < z ? hi[d] : z;
        if (hi[d] < lo[d])
            hi[d] = lo[d];
    }
}
