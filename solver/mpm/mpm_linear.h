/*
 * mpm_linear: internal to solver/mpm -- the 8-node trilinear shape
 * functions of a uniform grid in separable form, for the kernels' fast
 * path.  Node q = a + 2b + 4c of the cell sits at base + off[q] (off =
 * a + b s1 + c s2) and has
 *   N_q = wx[a] t[bc],  t[bc] = wy[b] wz[c]  (bc = b + 2c),
 *   G_q = (dx[a] wy[b] wz[c], wx[a] dy[b] wz[c], wx[a] wy[b] dz[c]),
 * with w0 = 1 - f, w1 = f, d0 = -1/h, d1 = +1/h (h: the cell edge along the axis).  Sums over the 8 nodes
 * are taken as sums over the 4 (b, c) pairs of the two x-neighbours, which
 * needs far fewer operations than forming the 8 weights and 24 gradients.
 */
#ifndef CASCADE_MPM_LINEAR_H
#define CASCADE_MPM_LINEAR_H

#include "mpm/mpm_grid.h"

struct mpm_lin {
    long base;
    double wx[2], wy[2], wz[2];
    double t[4];   /* wy[b] wz[c] */
};

/* The weights of a point at fractions f[0..2] inside the cell at `base`. */
static inline __attribute__((always_inline)) void mpm_lin_weights(long base, const double f[3],
                                                                  struct mpm_lin *s)
{
    s->base = base;
    s->wx[0] = 1.0 - f[0];
    s->wx[1] = f[0];
    s->wy[0] = 1.0 - f[1];
    s->wy[1] = f[1];
    s->wz[0] = 1.0 - f[2];
    s->wz[1] = f[2];
    s->t[0] = s->wy[0] * s->wz[0];
    s->t[1] = s->wy[1] * s->wz[0];
    s->t[2] = s->wy[0] * s->wz[1];
    s->t[3] = s->wy[1] * s->wz[1];
}

/* Cell (patch-local index of its low corner node) and weights of x, which
 * must lie inside the grid (mpm_locate_particles checked it). */
static inline __attribute__((always_inline)) void mpm_lin_eval(const struct mpm_grid *g,
                                                               const double *x, struct mpm_lin *s)
{
    double f[3];
    long base = 0;
    for (int k = 0; k < 3; k++) {
        double u = (x[k] - g->origin[k]) * g->inv_hd[k] - (double)g->lo[k];
        long i = (long)u;   /* u >= 0 */
        f[k] = u - (double)i;
        base += (i + g->halo) * g->stride[k];
    }
    mpm_lin_weights(base, f, s);
}

/* The cell of x for the next step (s9), found once for the three uses the
 * fused pass has for it -- the point's colouring block, the test that it
 * stays near its block, and its weights: keys (integer cell coordinates)
 * and fractions as mpm_lin_eval computes them (the same bits).  Returns
 * the block, or -1 when x lies outside the grid (key and f then unset). */
static inline __attribute__((always_inline)) long mpm_lin_cell(const struct mpm_grid *g,
                                                               const double *x, long key[3],
                                                               double f[3])
{
    for (int d = 0; d < 3; d++) {
        double u = (x[d] - g->origin[d]) * g->inv_hd[d] - (double)g->lo[d];
        if (!(u >= 0) || u >= (double)(g->nn[d] - 1))
            return -1;
        key[d] = (long)u;
        f[d] = u - (double)key[d];
    }
    return mpm_grid_key_block(g, key);
}

/* Patch-local index of the low corner node of the cell with keys key[]. */
static inline long mpm_lin_base(const struct mpm_grid *g, const long key[3])
{
    return (key[0] + g->halo) * g->stride[0] + (key[1] + g->halo) * g->stride[1] +
           (key[2] + g->halo) * g->stride[2];
}

/* Offsets of the 8 nodes from the base. */
static inline void mpm_lin_offsets(const struct mpm_grid *g, long off[8])
{
    for (int k = 0; k < 8; k++)
        off[k] = (k & 1) + ((k >> 1) & 1) * g->stride[1] + (k >> 2) * g->stride[2];
}

/* Software prefetch of the nodes a run of points along x will need next.
 * Points of a block come cell row after cell row (x fastest inside the
 * block, then y, then z), so the nodes of a cell new to the cache are those
 * of the row y+1, z+1; one row of nodes is one page (64 nodes of 64 bytes
 * on the reference grid), which the hardware prefetchers do not cross, and
 * every new row cost a miss to memory on every node array (perf: a fifth of
 * the kernels' samples on those loads).  Called at a point of the cell at
 * `base`, it asks for nodes base + `ahead` and the next along x (`ahead` =
 * 2 s1 + s2: the row the next cell row makes new) of an array of `size`
 * bytes per node.  Prefetching changes no result. */
static inline __attribute__((always_inline)) void mpm_lin_prefetch(const void *array, size_t size,
                                                                   long base, long ahead)
{
    const char *a = (const char *)array + (size_t)(base + ahead) * size;
    __builtin_prefetch(a, 1, 3);
    __builtin_prefetch(a + size, 1, 3);
    if (size < 64)   /* two nodes may straddle a line */
        __builtin_prefetch(a + 2 * size - 1, 1, 3);
}

#endif
