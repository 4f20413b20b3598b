/* mpm_build: placing material points in regions, cell by cell. */
#include "mpm/mpm_build.h"

#include <math.h>

#include "mpm/mpm_hgrid.h"

/* Visit the n^3 sub-positions of one cell [lo, lo + size) (Å) inside r. */
static int visit_cell(const struct region *r, int n, const double lo[3], const double size[3],
                      mpm_point_visitor fn, void *ctx, long *count)
{
    double vol = size[0] * size[1] * size[2] / (double)(n * n * n);
    for (int c = 0; c < n; c++)
        for (int bb = 0; bb < n; bb++)
            for (int a = 0; a < n; a++) {
                double x[3] = {lo[0] + (a + 0.5) / n * size[0], lo[1] + (bb + 0.5) / n * size[1],
                               lo[2] + (c + 0.5) / n * size[2]};
                if (!region_contains(r, x))
                    continue;
                int rc = fn(ctx, x, vol);
                if (rc)
                    return rc;
                ++*count;
            }
    return 0;
}

int mpm_region_visit(const struct mpm *m, const struct region *r, int n, mpm_point_visitor fn,
                     void *ctx, long *count)
{
    const struct mpm_grid *g = &m->grid;
    double rlo[3], rhi[3];
    region_bounds(r, rlo, rhi);
    *count = 0;
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
            int rc = visit_cell(r, n, lo, size, fn, ctx, count);
            if (rc)
                return rc;
        }
        return 0;
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
                int rc = visit_cell(r, n, lo, size, fn, ctx, count);
                if (rc)
                    return rc;
            }
    return 0;
}

/* The two passes of mpm_fill_region: count what this process keeps, then
 * store it. */
struct fill_pass {
    struct mpm *m;
    const struct mpm_fill_owner *owner;
    int body, store;
    double rho;
    int64_t next_id;
    long kept;
    struct err *e;
};

static int fill_point(void *ctx, const double x[3], double vol)
{
    struct fill_pass *f = ctx;
    int64_t id = f->next_id++;
    if (f->owner && !f->owner->keep(f->owner->ctx, x))
        return 0;
    f->kept++;
    if (!f->store)
        return 0;
    struct mpm *m = f->m;
    return mpm_points_add(&m->pts, x, m->body[f->body].velocity, f->rho * vol, vol, f->body, id,
                          f->e) < 0
               ? -1
               : 0;
}

int mpm_fill_region(struct mpm *m, const struct region *r, int body, int n,
                    const struct mpm_fill_owner *owner, int64_t first_id, long *added, long *kept,
                    struct err *e)
{
    *added = *kept = 0;
    if (n < 1)
        return err_set(e, ERR_INPUT, "points per cell must be at least 1");
    const struct mpm_body *b = &m->body[body];
    struct fill_pass f = {m, owner, body, 0, m->mat[b->material]->density, first_id, 0, e};
    long count;
    int rc = mpm_region_visit(m, r, n, fill_point, &f, &count);
    if (!rc)
        rc = mpm_points_reserve(&m->pts, m->pts.n + f.kept, e);
    if (rc)
        return rc;
    f.store = 1;
    f.kept = 0;
    f.next_id = first_id;
    rc = mpm_region_visit(m, r, n, fill_point, &f, &count);
    if (rc)
        return e->code ? e->code : ERR_RUNTIME;
    for (int d = 0; d < 3; d++)
        m->body[body].lp[d] = 0.5 / n;
    *added = count;
    *kept = f.kept;
    return 0;
}
