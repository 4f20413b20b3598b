/* mpm_build: placing material points in regions, cell by cell. */
#include "mpm/mpm_build.h"

#include <math.h>

#include "mpm/mpm_hgrid.h"

/* Visit the n^3 sub-positions of one cell [lo, lo + size) (Å) inside r. */
static long fill_cell(struct mpm *m, const struct region *r, int body, int n, const double lo[3],
                      const double size[3], int count_only, struct err *e)
{
    const struct mpm_body *b = &m->body[body];
    double rho = m->mat[b->material]->density;
    double vol = size[0] * size[1] * size[2] / (double)(n * n * n);
    long k = 0;
    for (int c = 0; c < n; c++)
        for (int bb = 0; bb < n; bb++)
            for (int a = 0; a < n; a++) {
                double x[3] = {lo[0] + (a + 0.5) / n * size[0], lo[1] + (bb + 0.5) / n * size[1],
                               lo[2] + (c + 0.5) / n * size[2]};
                if (!region_contains(r, x))
                    continue;
                k++;
                if (count_only)
                    continue;
                if (mpm_points_add(&m->pts, x, b->velocity, rho * vol, vol, body,
                                   (int64_t)m->pts.n + 1, e) < 0)
                    return -1;
            }
    return k;
}

static long fill(struct mpm *m, const struct region *r, int body, int n, int count_only,
                 struct err *e)
{
    const struct mpm_grid *g = &m->grid;
    double rlo[3], rhi[3];
    region_bounds(r, rlo, rhi);
    long total = 0;
    if (g->kind == MPM_GRID_HIER) {
        const struct mpm_hgrid *hg = g->hg;
        for (long c = 0; c < hg->ncell; c++) {
            const struct mpm_hcell *cl = &hg->cell[c];
            double lo[3], size[3];
            int skip = 0;
            for (int d = 0; d < 3; d++) {
                lo[d] = g->origin[d] + cl->lo[d] * g->h;
                size[d] = (double)(1L << cl->lg[d]) * g->h;
                skip |= lo[d] > rhi[d] || lo[d] + size[d] < rlo[d];
            }
            if (skip)
                continue;
            long k = fill_cell(m, r, body, n, lo, size, count_only, e);
            if (k < 0)
                return -1;
            total += k;
        }
        return total;
    }
    long i0[3], i1[3];
    for (int d = 0; d < 3; d++) {
        double a = floor((rlo[d] - g->origin[d]) * g->inv_h) - 1;
        double b = ceil((rhi[d] - g->origin[d]) * g->inv_h) + 1;
        i0[d] = (long)fmax(0.0, fmin(a, (double)g->ncell[d]));
        i1[d] = (long)fmax(0.0, fmin(b, (double)g->ncell[d]));
    }
    double size[3] = {g->h, g->h, g->h};
    /* x fastest, so consecutive points are neighbours */
    for (long kz = i0[2]; kz < i1[2]; kz++)
        for (long ky = i0[1]; ky < i1[1]; ky++)
            for (long kx = i0[0]; kx < i1[0]; kx++) {
                double lo[3] = {g->origin[0] + kx * g->h, g->origin[1] + ky * g->h,
                                g->origin[2] + kz * g->h};
                long k = fill_cell(m, r, body, n, lo, size, count_only, e);
                if (k < 0)
                    return -1;
                total += k;
            }
    return total;
}

int mpm_fill_region(struct mpm *m, const struct region *r, int body, int n, long *added,
                    struct err *e)
{
    *added = 0;
    if (n < 1)
        return err_set(e, ERR_INPUT, "points per cell must be at least 1");
    long k = fill(m, r, body, n, 1, e);
    if (k < 0)
        return e->code ? e->code : ERR_RUNTIME;
    int rc = mpm_points_reserve(&m->pts, m->pts.n + k, e);
    if (rc)
        return rc;
    k = fill(m, r, body, n, 0, e);
    if (k < 0)
        return e->code ? e->code : ERR_RUNTIME;
    for (int d = 0; d < 3; d++)
        m->body[body].lp[d] = 0.5 / n;
    *added = k;
    return 0;
}
