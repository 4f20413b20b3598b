/*
 * mpm_locate: step s9 of Chen 2014 -- find the cell of every particle and
 * sort the particles of each set by colouring block (a counting sort whose
 * order inside a block is the particle order, whatever the thread count).
 * Every sort_every steps the material points themselves are reordered into
 * block order, so the kernels stream through memory.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "mpm/mpm_view.h"

static int bins_reserve(struct mpm_bins *b, long n, int hier, long nblocks, int nt, struct err *e)
{
    if (n > b->cap) {
        long cap = n + n / 8 + 16;
        int32_t *blk = realloc(b->blk, (size_t)cap * sizeof *blk);
        if (blk)
            b->blk = blk;
        int32_t *order = realloc(b->order, (size_t)cap * sizeof *order);
        if (order)
            b->order = order;
        if (!blk || !order)
            return err_nomem(e, "particle bins");
        if (hier) {
            int32_t *cell = realloc(b->cell, (size_t)cap * sizeof *cell);
            if (!cell)
                return err_nomem(e, "particle bins");
            b->cell = cell;
        }
        b->cap = cap;
    }
    if (hier && !b->cell) {
        b->cell = malloc((size_t)(b->cap > 0 ? b->cap : 1) * sizeof *b->cell);
        if (!b->cell)
            return err_nomem(e, "particle bins");
    }
    if (!b->start) {
        b->start = malloc((size_t)(nblocks + 1) * sizeof *b->start);
        if (!b->start)
            return err_nomem(e, "particle bins");
    }
    if ((long)nt * nblocks > b->count_cap) {
        free(b->count);
        b->count = malloc((size_t)nt * nblocks * sizeof *b->count);
        if (!b->count)
            return err_nomem(e, "particle bins");
        b->count_cap = (long)nt * nblocks;
    }
    return 0;
}

/* Block of particle p, or -1 when it lies outside the grid. */
static inline long particle_block(const struct mpm *m, const struct mpm_view *w, long p, int kind,
                                  int32_t *cell)
{
    const struct mpm_grid *g = &m->grid;
    const double *x = w->x + 3 * p;
    long key[3];
    if (kind == MPM_ST_HIER) {
        long c = mpm_hgrid_find(g->hg, x);
        if (c < 0)
            return -1;
        *cell = (int32_t)c;
        for (int d = 0; d < 3; d++)
            key[d] = g->hg->cell[c].lo[d];
    } else {
        for (int d = 0; d < 3; d++) {
            double u = mpm_grid_u(g, x, d);
            if (!(u >= 0) || u >= (double)(g->nn[d] - 1))
                return -1;
            if (kind == MPM_ST_GIMP)
                key[d] = mpm_gimp_base(u, mpm_view_lp(m, w, p)[d]) + 1;
            else
                key[d] = (long)u;
        }
    }
    return mpm_grid_key_block(g, key);
}

static int locate_set(struct mpm *m, struct mpm_view *w, int kind, long *bad, struct err *e)
{
    const struct mpm_grid *g = &m->grid;
    struct mpm_bins *b = w->bins;
    long nb = g->nblocks, n = w->n;
    int nt = m->nthreads;
    /* blocks already computed from the positions the last step produced? */
    int known = b->blk_step == m->step && b->cap >= n && kind != MPM_ST_HIER;
    int rc = bins_reserve(b, n, kind == MPM_ST_HIER, nb, nt, e);
    if (rc)
        return rc;
    b->blk_step = -1;
    long first_bad = n;
    int unmade = 0;   /* a particle lies in a cell whose node table is not made yet */
    const uint8_t *made = kind == MPM_ST_HIER ? g->hg->cell_made : NULL;
#pragma omp parallel num_threads(nt) reduction(min : first_bad) reduction(| : unmade)
    {
        int t = omp_get_thread_num(), T = omp_get_num_threads();
        long lo = n * t / T, hi = n * (t + 1) / T;
        long *cnt = b->count + (long)t * nb;
        memset(cnt, 0, (size_t)nb * sizeof *cnt);
        for (long p = lo; p < hi; p++) {
            int32_t c = 0;
            long blk = known ? b->blk[p] : particle_block(m, w, p, kind, &c);
            if (blk < 0) {
                if (p < first_bad)
                    first_bad = p;
                blk = 0;
            }
            b->blk[p] = (int32_t)blk;
            if (kind == MPM_ST_HIER) {
                b->cell[p] = c;
                unmade |= !made[c];
            }
            cnt[blk]++;
        }
#pragma omp barrier
#pragma omp single
        {
            long off = 0;
            for (long k = 0; k < nb; k++) {
                b->start[k] = off;
                for (int tt = 0; tt < T; tt++) {
                    long c = b->count[(long)tt * nb + k];
                    b->count[(long)tt * nb + k] = off;
                    off += c;
                }
            }
            b->start[nb] = off;
        }
        for (long p = lo; p < hi; p++)
            b->order[cnt[b->blk[p]]++] = (int32_t)p;
    }
    *bad = first_bad < n ? first_bad : -1;
    if (unmade)   /* the node tables of the cells the stencils will read */
        mpm_hgrid_make_cells(g->hg, b->cell, n);
    return 0;
}

int mpm_locate_particles(struct mpm *m, struct err *e)
{
    struct mpm_view views[1 + MPM_MAX_EXTRA];
    int nv = mpm_views(m, views);
    int kind = mpm_stencil_kind(&m->grid);
    for (int s = 0; s < nv; s++) {
        long bad;
        int rc = locate_set(m, &views[s], kind, &bad, e);
        if (rc)
            return rc;
        if (bad >= 0) {
            const double *x = views[s].x + 3 * bad;
            if (s == 0)
                return err_set(e, ERR_DIVERGED,
                               "material point %lld left the grid at step %ld (x = %g %g %g Å)",
                               (long long)m->pts.id[bad], m->step, x[0], x[1], x[2]);
            return err_set(e, ERR_DIVERGED,
                           "particle %ld of set '%s' is outside the grid at step %ld (x = %g %g %g Å)",
                           bad, m->extra[s - 1]->name ? m->extra[s - 1]->name : "?", m->step,
                           x[0], x[1], x[2]);
        }
    }
    const long *starts[1 + MPM_MAX_EXTRA];
    for (int s = 0; s < nv; s++)
        starts[s] = views[s].bins->start;
    mpm_grid_order_blocks(&m->grid, starts, nv);   /* largest blocks first */
    /* reorder the material points into block order now and then */
    struct mpm_bins *b = &m->bins[0];
    if (!(m->sort_every > 0 && m->step % m->sort_every == 0 && m->pts.n > 1 &&
          m->scratch_cap >= m->pts.n))
        return 0;   /* no reorder due: no serial scan of the order either */
    long moved = 0;
    for (long k = 0; k < m->pts.n && !moved; k++)
        moved = b->order[k] != k;
    if (moved) {
        mpm_points_permute(&m->pts, b->order, m->scratch, m->nthreads);
        if (kind == MPM_ST_HIER) {
            int32_t *t32 = (int32_t *)m->scratch;
            for (long k = 0; k < m->pts.n; k++)
                t32[k] = b->cell[b->order[k]];
            memcpy(b->cell, t32, (size_t)m->pts.n * sizeof *t32);
        }
        for (long k = 0; k < m->pts.n; k++)
            b->order[k] = (int32_t)k;
    }
    return 0;
}
