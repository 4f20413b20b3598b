/* neighbor: link-cell binning (counting sort) and Verlet list construction. */
#include "core/neighbor.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct nlist *nlist_create(enum nlist_kind kind, double cutoff, double skin)
{
    struct nlist *nl = calloc(1, sizeof *nl);
    if (!nl)
        return NULL;
    nl->kind = kind;
    nl->cutoff = cutoff;
    nl->skin = skin;
    nl->ilo = 0;
    nl->ihi = 1 << 30;
    return nl;
}

void nlist_destroy(struct nlist **pnl)
{
    struct nlist *nl = pnl ? *pnl : NULL;
    if (!nl)
        return;
    free(nl->offset);
    free(nl->neigh);
    free(nl->x_build);
    free(nl->cell_start);
    free(nl->cell_of);
    free(nl->cell_sorted);
    free(nl->xs);
    free(nl);
    *pnl = NULL;
}

/* The half-list rule for a pair (i owned, j any), i != j. */
static inline int half_keeps(const struct particles *p, int i, int j)
{
    if (j < p->n_owned)
        return j > i;
    const double *xi = p->x + 3 * i, *xj = p->x + 3 * j;
    if (xj[2] != xi[2])
        return xj[2] > xi[2];
    if (xj[1] != xi[1])
        return xj[1] > xi[1];
    return xj[0] > xi[0];
}

static int reserve_common(struct nlist *nl, const struct particles *p, struct err *e)
{
    int n = p->n_owned;
    if (nl->cap_offset < n + 1) {
        int *o = realloc(nl->offset, (size_t)(n + 1) * sizeof *o);
        if (!o)
            return err_nomem(e, "neighbor offsets");
        nl->offset = o;
        nl->cap_offset = n + 1;
    }
    if (nl->cap_build < n) {
        double *xb = realloc(nl->x_build, (size_t)3 * n * sizeof *xb);
        if (!xb)
            return err_nomem(e, "neighbor positions");
        nl->x_build = xb;
        nl->cap_build = n;
    }
    if (n > 0)   /* a brick may hold no atom: x_build is still NULL then */
        memcpy(nl->x_build, p->x, (size_t)3 * n * sizeof(double));
    nl->n = n;
    return 0;
}

/* Room for `need` entries in the neighbour array. */
static int reserve_neigh(struct nlist *nl, long need, struct err *e)
{
    if (need <= nl->cap_neigh)
        return 0;
    long cap = nl->cap_neigh ? 2 * nl->cap_neigh : 1 << 16;
    while (cap < need)
        cap *= 2;
    int *nn = realloc(nl->neigh, (size_t)cap * sizeof *nn);
    if (!nn)
        return err_nomem(e, "neighbor list");
    nl->neigh = nn;
    nl->cap_neigh = cap;
    return 0;
}

static int push_neigh(struct nlist *nl, long at, int j, struct err *e)
{
    if (at >= nl->cap_neigh) {
        long cap = nl->cap_neigh ? 2 * nl->cap_neigh : 1 << 16;
        int *nn = realloc(nl->neigh, (size_t)cap * sizeof *nn);
        if (!nn)
            return err_nomem(e, "neighbor list");
        nl->neigh = nn;
        nl->cap_neigh = cap;
    }
    nl->neigh[at] = j;
    return 0;
}

/* Bin all particles into cells of edge >= `width` (when that would give
 * more than `maxcell` cells, of edge >= `wide` instead); fills nc[3],
 * lo[3], inv[3] and the CSR arrays cell_start / cell_sorted, and returns
 * in *used the edge chosen. */
static int bin_particles(struct nlist *nl, const struct particles *p, double width, double wide,
                         long maxcell, double *used, int nc[3], double lo[3], double inv[3],
                         struct err *e)
{
    int ntot = p->n_owned + p->n_ghost;
    double hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int i = 0; i < ntot; i++)
        for (int d = 0; d < 3; d++) {
            double x = p->x[3 * i + d];
            if (!isfinite(x))
                return err_set(e, ERR_DIVERGED, "particle id %lld has a non-finite %c coordinate",
                               (long long)p->id[i], "xyz"[d]);
            if (x < lo[d]) lo[d] = x;
            if (x > hi[d]) hi[d] = x;
        }
    long ncell = 1;
    for (int pass = 0; pass < 2; pass++) {
        double w = pass == 0 ? width : wide;
        ncell = 1;
        for (int d = 0; d < 3; d++) {
            if (ntot == 0) {
                lo[d] = 0;
                hi[d] = 1;
            }
            double len = hi[d] - lo[d];
            nc[d] = (int)floor(len / w);
            if (nc[d] < 1)
                nc[d] = 1;
            if (nc[d] > 1024)   /* sparse systems: bound memory, cells only get wider */
                nc[d] = 1024;
            inv[d] = nc[d] / (len > 0 ? len * (1.0 + 1e-12) + 1e-300 : 1.0);
            ncell *= nc[d];
        }
        *used = w;
        if (ncell <= maxcell || wide <= width)
            break;
    }
    if (nl->cap_cells < ncell + 1) {
        int *cs = realloc(nl->cell_start, (size_t)(ncell + 1) * sizeof *cs);
        if (!cs)
            return err_nomem(e, "link cells");
        nl->cell_start = cs;
        nl->cap_cells = ncell + 1;
    }
    if (nl->cap_cell_of < ntot) {
        int *co = realloc(nl->cell_of, (size_t)(ntot ? ntot : 1) * sizeof *co);
        int *so = realloc(nl->cell_sorted, (size_t)(ntot ? ntot : 1) * sizeof *so);
        if (!co || !so) {
            if (co) nl->cell_of = co;
            if (so) nl->cell_sorted = so;
            return err_nomem(e, "link cells");
        }
        nl->cell_of = co;
        nl->cell_sorted = so;
        nl->cap_cell_of = ntot;
    }
    memset(nl->cell_start, 0, (size_t)(ncell + 1) * sizeof(int));
    for (int i = 0; i < ntot; i++) {
        int c[3];
        for (int d = 0; d < 3; d++) {
            c[d] = (int)((p->x[3 * i + d] - lo[d]) * inv[d]);
            if (c[d] >= nc[d]) c[d] = nc[d] - 1;
            if (c[d] < 0) c[d] = 0;
        }
        int cell = (c[2] * nc[1] + c[1]) * nc[0] + c[0];
        nl->cell_of[i] = cell;
        nl->cell_start[cell + 1]++;
    }
    for (long c = 0; c < ncell; c++)
        nl->cell_start[c + 1] += nl->cell_start[c];
    /* stable fill: use cell_start as a running cursor, then restore */
    for (int i = 0; i < ntot; i++)
        nl->cell_sorted[nl->cell_start[nl->cell_of[i]]++] = i;
    for (long c = ncell; c > 0; c--)
        nl->cell_start[c] = nl->cell_start[c - 1];
    nl->cell_start[0] = 0;
    /* positions in cell order, one array per axis: the candidate loop of
     * the list build reads them contiguously */
    if (nl->cap_xs < ntot) {
        double *xs = realloc(nl->xs, (size_t)3 * (ntot ? ntot : 1) * sizeof *xs);
        if (!xs)
            return err_nomem(e, "link cells");
        nl->xs = xs;
        nl->cap_xs = ntot;
    }
    double *xs = nl->xs, *ys = xs + ntot, *zs = ys + ntot;
    for (int k = 0; k < ntot; k++) {
        const double *x = p->x + 3 * nl->cell_sorted[k];
        xs[k] = x[0];
        ys[k] = x[1];
        zs[k] = x[2];
    }
    return 0;
}

/* Cells of half the list range and a 5 x 5 x 5 stencil hold 42 % fewer
 * candidates than cells of the whole range and 27 of them; the distance,
 * read from the cell-ordered copies, is tested first (most candidates are
 * too far), the half-list rule only on the near ones. */
int nlist_build(struct nlist *nl, const struct particles *p, struct err *e)
{
    int rc = reserve_common(nl, p, e);
    if (rc)
        return rc;
    double rlist = nl->cutoff + nl->skin, rlist2 = rlist * rlist;
    int ntot = p->n_owned + p->n_ghost;
    int nc[3] = {1, 1, 1};
    double lo[3], inv[3], used = rlist;
    /* half-width cells unless they would be many more than the atoms
     * (sparse systems: vacuum around a cluster) */
    if ((rc = bin_particles(nl, p, 0.5 * rlist, rlist, 4L * ntot + 4096, &used, nc, lo, inv, e)))
        return rc;
    const int reach = used < rlist ? 2 : 1;
    const double *xs = nl->xs, *ys = xs + ntot, *zs = ys + ntot;
    const int *sorted = nl->cell_sorted, *start = nl->cell_start;
    const int half = nl->kind == NLIST_HALF;
    const int n_owned = p->n_owned;
    long at = 0;
    for (int i = 0; i < p->n_owned; i++) {
        nl->offset[i] = (int)at;
        if (i < nl->ilo || i >= nl->ihi)
            continue;
        int cell = nl->cell_of[i];
        int cx = cell % nc[0], cy = (cell / nc[0]) % nc[1], cz = cell / (nc[0] * nc[1]);
        const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
        for (int dz = -reach; dz <= reach; dz++) {
            int z = cz + dz;
            if (z < 0 || z >= nc[2]) continue;
            for (int dy = -reach; dy <= reach; dy++) {
                int y = cy + dy;
                if (y < 0 || y >= nc[1]) continue;
                /* the cells of one row are contiguous in cell order */
                int x0 = cx - reach < 0 ? 0 : cx - reach;
                int x1 = cx + reach >= nc[0] ? nc[0] - 1 : cx + reach;
                int row = (z * nc[1] + y) * nc[0];
                int k0 = start[row + x0], k1 = start[row + x1 + 1];
                if ((rc = reserve_neigh(nl, at + (k1 - k0), e)))
                    return rc;
                int *restrict out = nl->neigh;
                /* without branches: every candidate is written at the
                 * cursor, which advances only past the kept ones (the
                 * outcome of the tests is data, not predictable control) */
                for (int k = k0; k < k1; k++) {
                    double ddx = xs[k] - xi, ddy = ys[k] - yi, ddz = zs[k] - zi;
                    int j = sorted[k];
                    int keep = (ddx * ddx + ddy * ddy + ddz * ddz < rlist2) & (j != i);
                    if (half) {
                        /* half_keeps(): owned pairs under the smaller
                         * index, ghosts when above i (z, then y, then x) */
                        int above = (ddz > 0) | ((ddz == 0) & ((ddy > 0) | ((ddy == 0) & (ddx > 0))));
                        keep &= j < n_owned ? j > i : above;
                    }
                    out[at] = j;
                    at += keep;
                }
            }
        }
    }
    nl->offset[p->n_owned] = (int)at;
    nl->nbuilds++;
    return 0;
}

int nlist_build_brute(struct nlist *nl, const struct particles *p, struct err *e)
{
    int rc = reserve_common(nl, p, e);
    if (rc)
        return rc;
    double rlist2 = (nl->cutoff + nl->skin) * (nl->cutoff + nl->skin);
    int ntot = p->n_owned + p->n_ghost;
    long at = 0;
    for (int i = 0; i < p->n_owned; i++) {
        nl->offset[i] = (int)at;
        if (i < nl->ilo || i >= nl->ihi)
            continue;
        for (int j = 0; j < ntot; j++) {
            if (j == i || (nl->kind == NLIST_HALF && !half_keeps(p, i, j)))
                continue;
            double r2 = 0;
            for (int d = 0; d < 3; d++) {
                double dd = p->x[3 * j + d] - p->x[3 * i + d];
                r2 += dd * dd;
            }
            if (r2 < rlist2) {
                if ((rc = push_neigh(nl, at, j, e)))
                    return rc;
                at++;
            }
        }
    }
    nl->offset[p->n_owned] = (int)at;
    nl->nbuilds++;
    return 0;
}

int nlist_needs_rebuild(const struct nlist *nl, const struct particles *p)
{
    if (nl->nbuilds == 0 || nl->n != p->n_owned)
        return 1;
    double lim2 = 0.25 * nl->skin * nl->skin;
    for (int i = 0; i < p->n_owned; i++) {
        double dx = p->x[3 * i] - nl->x_build[3 * i], dy = p->x[3 * i + 1] - nl->x_build[3 * i + 1],
               dz = p->x[3 * i + 2] - nl->x_build[3 * i + 2];
        if (dx * dx + dy * dy + dz * dz > lim2)
            return 1;
    }
    return 0;
}

int nlist_spatial_order(const struct particles *p, double cell, int *perm, struct err *e)
{
    int n = p->n_owned;
    if (n == 0)
        return 0;
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            double x = p->x[3 * i + d];
            if (x < lo[d]) lo[d] = x;
            if (x > hi[d]) hi[d] = x;
        }
    for (int d = 0; d < 3; d++)
        if (!isfinite(lo[d]) || !isfinite(hi[d]))
            return err_set(e, ERR_DIVERGED, "a particle has a non-finite %c coordinate",
                           "xyz"[d]);
    int nc[3];
    long ncell = 1;
    for (int d = 0; d < 3; d++) {
        /* compare in double before the cast: a coordinate far outside the
         * box (1e300) must not overflow the int */
        double q = (hi[d] - lo[d]) / cell;
        nc[d] = q < 1023.0 ? (int)q + 1 : 1024;
        ncell *= nc[d];
    }
    int *count = calloc((size_t)ncell + 1, sizeof *count);
    int *cellof = malloc((size_t)n * sizeof *cellof);
    if (!count || !cellof) {
        free(count);
        free(cellof);
        return err_nomem(e, "spatial sort");
    }
    for (int i = 0; i < n; i++) {
        int c[3];
        for (int d = 0; d < 3; d++) {
            double q = (p->x[3 * i + d] - lo[d]) / cell;
            c[d] = q < (double)(nc[d] - 1) ? (int)q : nc[d] - 1;
        }
        cellof[i] = (c[2] * nc[1] + c[1]) * nc[0] + c[0];
        count[cellof[i] + 1]++;
    }
    for (long c = 0; c < ncell; c++)
        count[c + 1] += count[c];
    for (int i = 0; i < n; i++)
        perm[count[cellof[i]]++] = i;
    free(count);
    free(cellof);
    return 0;
}
