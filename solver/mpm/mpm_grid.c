/* mpm_grid: node store, boundary node lists and colouring blocks. */
#include "mpm/mpm_grid.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "mpm/mpm_hgrid.h"

void *mpm_grid_zeroed_alloc(size_t bytes)
{
    void *p = mmap(NULL, bytes ? bytes : 1, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                   -1, 0);
    return p == MAP_FAILED ? NULL : p;
}

void mpm_grid_zeroed_free(void *p, size_t bytes)
{
    if (p)
        munmap(p, bytes ? bytes : 1);
}

static int alloc_nodes(struct mpm_grid *g, struct err *e)
{
    /* zero from the kernel and resident only where written: no clear here
     * (mpm_grid.h, `pristine`) */
    g->node_bytes = (size_t)g->nnodes * sizeof *g->node;
    g->r_bytes = (size_t)g->nnodes * 4 * sizeof *g->r;
    g->node = mpm_grid_zeroed_alloc(g->node_bytes);
    g->r = mpm_grid_zeroed_alloc(g->r_bytes);
    if (!g->node || !g->r)
        return err_nomem(e, "grid nodes");
    g->pristine = 1;
    return 0;
}

/* Colouring blocks: bricks of bw[d] keys.  The nodes a block touches
 * reach so little beyond its keys (the callers' `width`, below) that with
 * bw[d] >= width blocks two apart along any axis never share a node, and
 * the blocks of one colour --
 * the parities of their three block coordinates -- can be summed into the
 * grid in parallel, in any order, with no atomics.
 *
 * The cuts go across y and z, `width` keys apart: a block is then a bundle
 * of whole rows of cells along x, the direction nodes are contiguous in
 * memory, so the points of a block (kept in cell-row order) stream through
 * the node arrays along pages, and the many small blocks balance between
 * threads (the earlier slabs across one axis gave two threads at most 9 / 5
 * of one thread's speed on the reference problem, docs/bench.md).  Only a
 * grid too thin across y and z for MIN_BLOCKS blocks is cut along x too. */
enum { MIN_BLOCKS = 64 };

static int make_blocks(struct mpm_grid *g, const long nkeys[3], long width, struct err *e)
{
    for (int d = 0; d < 3; d++) {
        g->nkeys[d] = nkeys[d];
        g->bw[d] = d == 0 ? nkeys[0] : width;
        g->nb[d] = (nkeys[d] + g->bw[d] - 1) / g->bw[d];
    }
    long nyz = g->nb[1] * g->nb[2];
    if (nyz < MIN_BLOCKS) {
        long nx = (MIN_BLOCKS + nyz - 1) / nyz;
        long bw0 = (nkeys[0] + nx - 1) / nx;
        g->bw[0] = bw0 > width ? bw0 : width;
        g->nb[0] = (nkeys[0] + g->bw[0] - 1) / g->bw[0];
    }
    g->nblocks = g->nb[0] * g->nb[1] * g->nb[2];
    if (g->nblocks > INT32_MAX)
        return err_set(e, ERR_INPUT, "grid colouring: %ld blocks", g->nblocks);
    long bstride = 1;
    for (int d = 0; d < 3; d++) {
        g->key_block[d] = malloc((size_t)nkeys[d] * sizeof *g->key_block[d]);
        if (!g->key_block[d])
            return err_nomem(e, "grid colouring");
        for (long k = 0; k < nkeys[d]; k++)
            g->key_block[d][k] = (int32_t)(k / g->bw[d] * bstride);
        bstride *= g->nb[d];
    }
    long most = ((g->nb[0] + 1) / 2) * ((g->nb[1] + 1) / 2) * ((g->nb[2] + 1) / 2);
    g->colour_key = malloc((size_t)most * sizeof *g->colour_key);
    if (!g->colour_key)
        return err_nomem(e, "grid colouring");
    for (int c = 0; c < MPM_COLOURS; c++) {
        g->ncolour[c] = 0;
        g->colour_block[c] = malloc((size_t)most * sizeof(int32_t));
        if (!g->colour_block[c])
            return err_nomem(e, "grid colouring");
    }
    for (long bz = 0; bz < g->nb[2]; bz++)
        for (long by = 0; by < g->nb[1]; by++)
            for (long bx = 0; bx < g->nb[0]; bx++) {
                int c = (int)((bx & 1) | ((by & 1) << 1) | ((bz & 1) << 2));
                long b = (bz * g->nb[1] + by) * g->nb[0] + bx;
                g->colour_block[c][g->ncolour[c]++] = (int32_t)b;
            }
    return 0;
}

static int key_descending(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x < y) - (x > y);
}

void mpm_grid_order_blocks(struct mpm_grid *g, const long *const *start, int nsets)
{
    for (int c = 0; c < MPM_COLOURS; c++) {
        long n = g->ncolour[c];
        int32_t *blk = g->colour_block[c];
        for (long i = 0; i < n; i++) {
            int64_t b = blk[i], w = 0;
            for (int s = 0; s < nsets; s++)
                w += start[s][b + 1] - start[s][b];
            g->colour_key[i] = (w << 31) | (INT32_MAX - b);   /* count, then lower index */
        }
        qsort(g->colour_key, (size_t)n, sizeof *g->colour_key, key_descending);
        for (long i = 0; i < n; i++)
            blk[i] = (int32_t)(INT32_MAX - (g->colour_key[i] & INT32_MAX));
    }
}

/* Edges per axis; h and inv_h are those along x. */
static void set_edges(struct mpm_grid *g, const double h[3])
{
    for (int d = 0; d < 3; d++) {
        g->hd[d] = h[d];
        g->inv_hd[d] = 1.0 / h[d];
    }
    g->h = g->hd[0];
    g->inv_h = g->inv_hd[0];
}

int mpm_grid_init_uniform(struct mpm_grid *g, const double origin[3], double h,
                          const long ncell[3], enum mpm_shape_kind shape, struct err *e)
{
    const double h3[3] = {h, h, h};
    return mpm_grid_init_uniform3(g, origin, h3, ncell, shape, e);
}

int mpm_grid_init_uniform3(struct mpm_grid *g, const double origin[3], const double h[3],
                           const long ncell[3], enum mpm_shape_kind shape, struct err *e)
{
    memset(g, 0, sizeof *g);
    g->kind = MPM_GRID_UNIFORM;
    g->shape = shape;
    set_edges(g, h);
    g->halo = 1;   /* GIMP reaches one node beyond the cell of a point near a face */
    g->nnodes = 1;
    for (int d = 0; d < 3; d++) {
        if (ncell[d] < 1)
            return err_set(e, ERR_INPUT, "grid needs at least one cell per direction");
        g->origin[d] = origin[d];
        g->ncell[d] = ncell[d];
        g->lo[d] = 0;
        g->nn[d] = ncell[d] + 1;
        g->dim[d] = g->nn[d] + 2 * g->halo;
        g->nnodes *= g->dim[d];
    }
    if (g->nnodes > INT32_MAX)
        return err_set(e, ERR_INPUT, "grid of %ld nodes is too large", g->nnodes);
    g->stride[0] = 1;
    g->stride[1] = g->dim[0];
    g->stride[2] = g->dim[0] * g->dim[1];
    int rc = alloc_nodes(g, e);
    if (rc)
        return rc;
    long nkeys[3];
    for (int d = 0; d < 3; d++)
        nkeys[d] = shape == MPM_SHAPE_GIMP ? ncell[d] + 1 : ncell[d];
    /* keys: linear, the cell (nodes key..key+1); GIMP, base node + 1 (nodes
     * key-1..key+1).  Linear blocks are 3 cells wide so that a point may move
     * by less than a cell within a step and still map into nodes no block of
     * its colour touches (the fused update-and-map pass, mpm_step) */
    return make_blocks(g, nkeys, shape == MPM_SHAPE_LINEAR ? 3 : 2, e);
}

int mpm_grid_init_hier(struct mpm_grid *g, struct mpm_hgrid *hg, struct err *e)
{
    memset(g, 0, sizeof *g);
    g->kind = MPM_GRID_HIER;
    g->shape = MPM_SHAPE_LINEAR;
    g->hg = hg;
    set_edges(g, hg->hd);
    g->nnodes = hg->nnodes;
    long nkeys[3], width = 2;
    for (int d = 0; d < 3; d++) {
        g->origin[d] = hg->origin[d];
        g->ncell[d] = hg->ncell_fine[d];
        nkeys[d] = hg->ncell_fine[d];
        long smax = 1L << hg->lg[hg->nlevels][d];   /* keys: cell corners, aligned */
        if (smax > width)
            width = smax;
    }
    int rc = alloc_nodes(g, e);
    if (!rc)
        rc = make_blocks(g, nkeys, width, e);
    return rc;
}

void mpm_grid_free(struct mpm_grid *g)
{
    mpm_grid_zeroed_free(g->node, g->node_bytes);
    mpm_grid_zeroed_free(g->node_next, g->node_bytes);
    mpm_grid_zeroed_free(g->r, g->r_bytes);
    free(g->bc_node);
    free(g->bc_bits);
    for (int d = 0; d < 3; d++)
        free(g->key_block[d]);
    for (int c = 0; c < MPM_COLOURS; c++)
        free(g->colour_block[c]);
    free(g->colour_key);
    mpm_hgrid_destroy(&g->hg);
    memset(g, 0, sizeof *g);
}

/* Global lattice coordinates of node i (finest lattice for hierarchical). */
static void node_ijk(const struct mpm_grid *g, long i, long ijk[3])
{
    if (g->kind == MPM_GRID_HIER) {
        for (int d = 0; d < 3; d++)
            ijk[d] = g->hg->node_ijk[3 * i + d];
        return;
    }
    ijk[0] = i % g->dim[0] - g->halo + g->lo[0];
    ijk[1] = (i / g->dim[0]) % g->dim[1] - g->halo + g->lo[1];
    ijk[2] = i / (g->dim[0] * g->dim[1]) - g->halo + g->lo[2];
}

void mpm_grid_node_position(const struct mpm_grid *g, long i, double x[3])
{
    long ijk[3];
    node_ijk(g, i, ijk);
    for (int d = 0; d < 3; d++)
        x[d] = g->origin[d] + (double)ijk[d] * g->hd[d];
}

int mpm_grid_set_faces(struct mpm_grid *g, const enum mpm_face_bc face[6], struct err *e)
{
    for (int f = 0; f < 6; f++)
        g->face[f] = face[f];
    free(g->bc_node);
    free(g->bc_bits);
    g->bc_node = NULL;
    g->bc_bits = NULL;
    g->nbc = 0;
    long cap = 0;
    for (long i = 0; i < g->nnodes; i++) {
        long ijk[3];
        node_ijk(g, i, ijk);
        unsigned bits = 0;
        for (int d = 0; d < 3; d++) {
            for (int side = 0; side < 2; side++) {
                enum mpm_face_bc bc = face[2 * d + side];
                if (bc == MPM_FACE_FREE)
                    continue;
                int on = side == 0 ? ijk[d] <= 0 : ijk[d] >= g->ncell[d];
                if (!on)
                    continue;
                bits |= bc == MPM_FACE_FIXED ? 7u : (1u << d);
            }
        }
        if (!bits)
            continue;
        if (g->nbc >= cap) {
            cap = cap ? 2 * cap : 1024;
            int32_t *bn = realloc(g->bc_node, (size_t)cap * sizeof *bn);
            if (bn)
                g->bc_node = bn;
            uint8_t *bb = realloc(g->bc_bits, (size_t)cap * sizeof *bb);
            if (bb)
                g->bc_bits = bb;
            if (!bn || !bb)
                return err_nomem(e, "grid boundary nodes");
        }
        g->bc_node[g->nbc] = (int32_t)i;
        g->bc_bits[g->nbc] = (uint8_t)bits;
        g->nbc++;
    }
    return 0;
}

double mpm_grid_min_cell(const struct mpm_grid *g)
{
    return fmin(g->hd[0], fmin(g->hd[1], g->hd[2]));
}

void mpm_grid_bounds(const struct mpm_grid *g, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        lo[d] = g->origin[d];
        hi[d] = g->origin[d] + (double)g->ncell[d] * g->hd[d];
    }
}

int mpm_grid_contains(const struct mpm_grid *g, const double x[3])
{
    if (g->kind == MPM_GRID_HIER)
        return mpm_hgrid_find(g->hg, x) >= 0;
    for (int d = 0; d < 3; d++) {
        double u = (x[d] - g->origin[d]) * g->inv_hd[d];
        if (!(u >= 0) || u >= (double)g->ncell[d])
            return 0;
    }
    return 1;
}

void mpm_grid_clear_nodes(struct mpm_node *nd, long n, int nthreads)
{
    /* one memset per thread over the same contiguous share of the nodes a
     * static loop would give it (so each thread touches the pages it maps) */
#pragma omp parallel num_threads(nthreads)
    {
        int nt = omp_get_num_threads(), t = omp_get_thread_num();
        long lo = n * t / nt, hi = n * (t + 1) / nt;
        if (hi > lo)
            memset(nd + lo, 0, (size_t)(hi - lo) * sizeof *nd);
    }
}

void mpm_grid_clear(struct mpm_grid *g, int nthreads)
{
    if (g->pristine) {   /* nothing written since the allocation zeroed it */
        g->pristine = 0;
        return;
    }
    if (!g->active) {
        mpm_grid_clear_nodes(g->node, g->nnodes, nthreads);
        return;
    }
    /* only the nodes the last mapping touched hold values; the remap r of
     * s10-s11 is zeroed with them (the update zeroes only the nodes it
     * visits) */
    const int32_t *act = g->active;
    long n = g->nactive;
    struct mpm_node *node = g->node;
    double *r = g->r;
#pragma omp parallel for schedule(static) num_threads(nthreads)
    for (long k = 0; k < n; k++) {
        long i = act[k];
        memset(&node[i], 0, sizeof node[i]);
        if (r)
            r[4 * i + 0] = r[4 * i + 1] = r[4 * i + 2] = r[4 * i + 3] = 0.0;
    }
}

double mpm_grid_bytes(const struct mpm_grid *g)
{
    double b = (double)g->nnodes * ((g->node_next ? 2 : 1) * sizeof(struct mpm_node) +
                                    4 * sizeof(double));
    b += (double)g->nbc * (sizeof(int32_t) + 1);
    if (g->hg)
        b += mpm_hgrid_bytes(g->hg);
    return b;
}
