/* mpm_hgrid: building the hierarchical grid (levels, 2:1 balance, hanging nodes). */
#include "mpm/mpm_hgrid.h"

#include <stdlib.h>
#include <string.h>

struct builder {
    struct mpm_hgrid *hg;
    const struct mpm_hlevel *lv;
    struct err *e;
    int failed;
};

/* Highest level l whose regions 1..l all contain x. */
static int wanted_level(const struct builder *b, const double x[3])
{
    int l = 0;
    while (l < b->hg->nlevels && region_contains(&b->lv[l].region, x))
        l++;
    return l;
}

/* Whether every finest cell of the block [lo, lo + size) wants level >= l. */
static int block_wants(const struct builder *b, const long lo[3], const long size[3], int l)
{
    const struct mpm_hgrid *hg = b->hg;
    for (long k = lo[2]; k < lo[2] + size[2]; k++)
        for (long j = lo[1]; j < lo[1] + size[1]; j++)
            for (long i = lo[0]; i < lo[0] + size[0]; i++) {
                double x[3] = {hg->origin[0] + (i + 0.5) * hg->hd[0],
                               hg->origin[1] + (j + 0.5) * hg->hd[1],
                               hg->origin[2] + (k + 0.5) * hg->hd[2]};
                if (wanted_level(b, x) < l)
                    return 0;
            }
    return 1;
}

static long tree_alloc(struct builder *b, long n)
{
    struct mpm_hgrid *hg = b->hg;
    if (hg->ntree + n > hg->cap_tree) {
        long cap = hg->cap_tree ? 2 * hg->cap_tree : 1024;
        while (cap < hg->ntree + n)
            cap *= 2;
        int32_t *t = realloc(hg->tree, (size_t)cap * sizeof *t);
        if (!t) {
            b->failed = err_nomem(b->e, "hierarchical grid");
            return -1;
        }
        hg->tree = t;
        hg->cap_tree = cap;
    }
    long base = hg->ntree;
    hg->ntree += n;
    return base;
}

static int32_t cell_new(struct builder *b, const long lo[3], int level)
{
    struct mpm_hgrid *hg = b->hg;
    if (hg->ncell >= hg->cap_cell) {
        long cap = hg->cap_cell ? 2 * hg->cap_cell : 1024;
        struct mpm_hcell *c = realloc(hg->cell, (size_t)cap * sizeof *c);
        if (!c) {
            b->failed = err_nomem(b->e, "hierarchical grid cells");
            return HG_EMPTY;
        }
        hg->cell = c;
        hg->cap_cell = cap;
    }
    struct mpm_hcell *c = &hg->cell[hg->ncell];
    memset(c, 0, sizeof *c);
    for (int d = 0; d < 3; d++) {
        c->lo[d] = (int32_t)lo[d];
        c->lg[d] = (uint8_t)hg->lg[level][d];
    }
    c->level = (uint8_t)level;
    return (int32_t)hg->ncell++;
}

/* `slot` >= 0: tree[slot]; < 0: root[-slot - 1] -- where a cell is referenced. */
static void set_slot(struct mpm_hgrid *hg, long slot, int32_t v)
{
    if (slot >= 0)
        hg->tree[slot] = v;
    else
        hg->root[-slot - 1] = v;
}

/* Fill the tree entry at `slot` for the block of level l at lo. */
static void make(struct builder *b, const long lo[3], int l, long slot)
{
    struct mpm_hgrid *hg = b->hg;
    if (b->failed)
        return;
    long size[3];
    int inside = 1;
    for (int d = 0; d < 3; d++) {
        size[d] = 1L << hg->lg[l][d];
        if (lo[d] >= hg->ncell_fine[d]) {
            set_slot(hg, slot, HG_EMPTY);
            return;
        }
        if (lo[d] + size[d] > hg->ncell_fine[d])
            inside = 0;
    }
    if (l == 0 || (inside && block_wants(b, lo, size, l))) {
        set_slot(hg, slot, cell_new(b, lo, l));
        return;
    }
    unsigned mask = hg->coarsen[l];
    int nch = 1 << __builtin_popcount(mask);
    long base = tree_alloc(b, nch);
    if (base < 0)
        return;
    set_slot(hg, slot, (int32_t)(HG_SPLIT_BASE - base));
    for (int c = 0; c < nch; c++) {
        long clo[3] = {lo[0], lo[1], lo[2]};
        int bit = 0;
        for (int d = 0; d < 3; d++)
            if (mask & (1u << d))
                clo[d] += (long)((c >> bit++) & 1) << hg->lg[l - 1][d];
        make(b, clo, l - 1, base + c);
    }
}

/* --- node set: sorted unique keys of all cell corners --------------------- */

static int64_t node_key(const struct mpm_hgrid *hg, long i, long j, long k)
{
    return (int64_t)i + (int64_t)(hg->ncell_fine[0] + 1) *
                            ((int64_t)j + (int64_t)(hg->ncell_fine[1] + 1) * (int64_t)k);
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static long key_find(const int64_t *keys, long n, int64_t k)
{
    long lo = 0, hi = n - 1;
    while (lo <= hi) {
        long mid = (lo + hi) / 2;
        if (keys[mid] < k)
            lo = mid + 1;
        else if (keys[mid] > k)
            hi = mid - 1;
        else
            return mid;
    }
    return -1;
}

/* Sorted unique keys of keys[0..n), in place; returns their count. */
static long sort_unique(int64_t *keys, long n)
{
    qsort(keys, (size_t)n, sizeof *keys, cmp_i64);
    long u = 0;
    for (long k = 0; k < n; k++)
        if (u == 0 || keys[k] != keys[u - 1])
            keys[u++] = keys[k];
    return u;
}

/* A heap of runs by their next key, for the merge of node_set. */
struct run_heap {
    long *run;                 /* run indices, heap-ordered by key */
    long n;
    const int64_t *keys;
    long *at, *end;            /* per run: next position, one past its last */
};

static void run_heap_down(struct run_heap *h, long i)
{
    for (;;) {
        long l = 2 * i + 1, r = l + 1, m = i;
        if (l < h->n && h->keys[h->at[h->run[l]]] < h->keys[h->at[h->run[m]]])
            m = l;
        if (r < h->n && h->keys[h->at[h->run[r]]] < h->keys[h->at[h->run[m]]])
            m = r;
        if (m == i)
            return;
        long t = h->run[i];
        h->run[i] = h->run[m];
        h->run[m] = t;
        i = m;
    }
}

/* The sorted unique keys of every cell corner.  The corners are made a
 * chunk of cells at a time (cells in tree order lie close together, so a
 * chunk's corners are mostly shared among its cells) and each chunk's made
 * unique, then the chunks' runs merged: the transient is the runs (a
 * little more than the nodes) and one chunk, not eight keys a cell. */
enum { NODE_SET_CHUNK = 32768 };   /* cells a chunk: 2 MB of corner keys */

static int node_set(struct mpm_hgrid *hg, int64_t **keys_out, long *n_out, struct err *e)
{
    *keys_out = NULL;
    *n_out = 0;
    long nchunk = (hg->ncell + NODE_SET_CHUNK - 1) / NODE_SET_CHUNK;
    int64_t *chunk = malloc((size_t)NODE_SET_CHUNK * 8 * sizeof *chunk);
    long *bounds = malloc((size_t)(nchunk + 1) * sizeof *bounds);
    int64_t *runs = NULL;
    long nruns = 0, cap = 0;
    int rc = chunk && bounds ? 0 : err_nomem(e, "hierarchical grid nodes");
    for (long ch = 0; ch < nchunk && !rc; ch++) {
        long c0 = ch * NODE_SET_CHUNK, c1 = c0 + NODE_SET_CHUNK < hg->ncell ? c0 + NODE_SET_CHUNK
                                                                             : hg->ncell;
        long n = 0;
        for (long c = c0; c < c1; c++) {
            const struct mpm_hcell *cl = &hg->cell[c];
            for (int q = 0; q < 8; q++) {
                long ijk[3];
                for (int d = 0; d < 3; d++)
                    ijk[d] = cl->lo[d] + (((q >> d) & 1) ? (1L << cl->lg[d]) : 0);
                chunk[n++] = node_key(hg, ijk[0], ijk[1], ijk[2]);
            }
        }
        n = sort_unique(chunk, n);
        if (nruns + n > cap) {
            long nc = cap ? 2 * cap : 8 * NODE_SET_CHUNK;
            while (nc < nruns + n)
                nc *= 2;
            int64_t *r = realloc(runs, (size_t)nc * sizeof *r);
            if (!r) {
                rc = err_nomem(e, "hierarchical grid nodes");
                break;
            }
            runs = r;
            cap = nc;
        }
        bounds[ch] = nruns;
        memcpy(runs + nruns, chunk, (size_t)n * sizeof *chunk);
        nruns += n;
    }
    free(chunk);
    int64_t *keys = NULL;
    long *heap = NULL, *at = NULL;
    if (!rc) {
        bounds[nchunk] = nruns;
        keys = malloc((size_t)(nruns > 0 ? nruns : 1) * sizeof *keys);
        heap = malloc((size_t)(nchunk > 0 ? nchunk : 1) * sizeof *heap);
        at = malloc((size_t)(nchunk > 0 ? nchunk : 1) * sizeof *at);
        if (!keys || !heap || !at)
            rc = err_nomem(e, "hierarchical grid nodes");
    }
    long u = 0;
    if (!rc) {
        struct run_heap h = {heap, 0, runs, at, bounds + 1};
        for (long ch = 0; ch < nchunk; ch++) {
            at[ch] = bounds[ch];
            if (at[ch] < bounds[ch + 1])
                heap[h.n++] = ch;
        }
        for (long i = h.n / 2 - 1; i >= 0; i--)
            run_heap_down(&h, i);
        while (h.n > 0) {
            long r = heap[0];
            int64_t k = runs[at[r]++];
            if (u == 0 || keys[u - 1] != k)
                keys[u++] = k;
            if (at[r] == h.end[r])
                heap[0] = heap[--h.n];
            run_heap_down(&h, 0);
        }
        int64_t *fit = realloc(keys, (size_t)(u > 0 ? u : 1) * sizeof *fit);
        if (fit)
            keys = fit;
    }
    free(runs);
    free(bounds);
    free(heap);
    free(at);
    if (rc) {
        free(keys);
        return rc;
    }
    *keys_out = keys;
    *n_out = u;
    return 0;
}

/* Whether some node lies on the boundary of cell c at a position that is not
 * a corner, edge midpoint or face centre of c (the 2:1 rule is broken). */
static int cell_unbalanced(const struct mpm_hgrid *hg, const struct mpm_hcell *c,
                           const int64_t *keys, long nkeys)
{
    long s[3];
    int big = 0;
    for (int d = 0; d < 3; d++) {
        s[d] = 1L << c->lg[d];
        big |= s[d] > 2;
    }
    if (!big)
        return 0;   /* every boundary lattice point is a candidate */
    for (int fd = 0; fd < 3; fd++) {
        int a = (fd + 1) % 3, b = (fd + 2) % 3;
        for (int side = 0; side < 2; side++) {
            long ijk[3];
            ijk[fd] = c->lo[fd] + side * s[fd];
            for (long u = 0; u <= s[a]; u++)
                for (long v = 0; v <= s[b]; v++) {
                    int cand_a = u == 0 || u == s[a] || 2 * u == s[a];
                    int cand_b = v == 0 || v == s[b] || 2 * v == s[b];
                    if (cand_a && cand_b)
                        continue;
                    ijk[a] = c->lo[a] + u;
                    ijk[b] = c->lo[b] + v;
                    if (key_find(keys, nkeys, node_key(hg, ijk[0], ijk[1], ijk[2])) >= 0)
                        return 1;
                }
        }
    }
    return 0;
}

/* Where cell c is referenced in the tree (found by descending from its root). */
static long cell_slot(const struct mpm_hgrid *hg, long c)
{
    const struct mpm_hcell *cl = &hg->cell[c];
    int L = hg->nlevels;
    long i[3] = {cl->lo[0], cl->lo[1], cl->lo[2]};
    long r = ((i[2] >> hg->lg[L][2]) * hg->nroot[1] + (i[1] >> hg->lg[L][1])) * hg->nroot[0] +
             (i[0] >> hg->lg[L][0]);
    long slot = -r - 1;
    int32_t t = hg->root[r];
    int lev = L;
    while (t <= HG_SPLIT_BASE) {
        long base = HG_SPLIT_BASE - t;
        unsigned mask = hg->coarsen[lev];
        int child = 0, bit = 0;
        for (int d = 0; d < 3; d++)
            if (mask & (1u << d))
                child |= (int)((i[d] >> hg->lg[lev - 1][d]) & 1) << bit++;
        slot = base + child;
        t = hg->tree[slot];
        lev--;
    }
    return t == c ? slot : HG_EMPTY - 1;
}

/* Rebuild the tree without cells marked dead (level 0xff), renumbering. */
static void cells_compact(struct mpm_hgrid *hg)
{
    long u = 0;
    for (long c = 0; c < hg->ncell; c++) {
        if (hg->cell[c].level == 0xff)
            continue;
        if (u != c) {
            long slot = cell_slot(hg, c);
            hg->cell[u] = hg->cell[c];
            if (slot != HG_EMPTY - 1)
                set_slot(hg, slot, (int32_t)u);
        }
        u++;
    }
    hg->ncell = u;
}

static int hgrid_balance(struct builder *b)
{
    struct mpm_hgrid *hg = b->hg;
    for (int pass = 0; pass < 64; pass++) {
        int64_t *keys;
        long nkeys;
        int rc = node_set(hg, &keys, &nkeys, b->e);
        if (rc)
            return rc;
        long nsplit = 0, n0 = hg->ncell;
        for (long c = 0; c < n0 && !b->failed; c++) {
            if (hg->cell[c].level == 0 || !cell_unbalanced(hg, &hg->cell[c], keys, nkeys))
                continue;
            /* split c into its children of the level below */
            long slot = cell_slot(hg, c);
            int l = hg->cell[c].level;
            long lo[3] = {hg->cell[c].lo[0], hg->cell[c].lo[1], hg->cell[c].lo[2]};
            hg->cell[c].level = 0xff;
            unsigned mask = hg->coarsen[l];
            int nch = 1 << __builtin_popcount(mask);
            long base = tree_alloc(b, nch);
            if (base < 0)
                break;
            set_slot(hg, slot, (int32_t)(HG_SPLIT_BASE - base));
            for (int ch = 0; ch < nch; ch++) {
                long clo[3] = {lo[0], lo[1], lo[2]};
                int bit = 0;
                for (int d = 0; d < 3; d++)
                    if (mask & (1u << d))
                        clo[d] += (long)((ch >> bit++) & 1) << hg->lg[l - 1][d];
                hg->tree[base + ch] = cell_new(b, clo, l - 1);
            }
            nsplit++;
        }
        free(keys);
        if (b->failed)
            return b->failed;
        cells_compact(hg);
        if (nsplit == 0)
            return 0;
    }
    return err_set(b->e, ERR_INPUT, "hierarchical grid: 2:1 balance did not converge");
}

/* Index of the node at finest-lattice (i, j, k), or -1: a binary search of
 * node_ijk, which is in the order of node_key. */
static long node_find(const struct mpm_hgrid *hg, const long ijk[3])
{
    const int64_t want = node_key(hg, ijk[0], ijk[1], ijk[2]);
    long lo = 0, hi = hg->nnodes - 1;
    while (lo <= hi) {
        long mid = (lo + hi) / 2;
        const int32_t *n = hg->node_ijk + 3 * mid;
        int64_t k = node_key(hg, n[0], n[1], n[2]);
        if (k < want)
            lo = mid + 1;
        else if (k > want)
            hi = mid - 1;
        else
            return mid;
    }
    return -1;
}

/* The 27 candidate nodes of cell cl (-1 where absent). */
static void cell_table(const struct mpm_hgrid *hg, const struct mpm_hcell *cl, int32_t node[27])
{
    for (int q = 0; q < 27; q++) {
        int ab[3] = {q % 3, (q / 3) % 3, q / 9};
        long ijk[3];
        int ok = !(ab[0] == 1 && ab[1] == 1 && ab[2] == 1);
        for (int d = 0; d < 3 && ok; d++) {
            long s = 1L << cl->lg[d];
            if (ab[d] == 1 && s < 2)
                ok = 0;
            ijk[d] = cl->lo[d] + (ab[d] == 0 ? 0 : ab[d] == 1 ? s / 2 : s);
        }
        node[q] = ok ? (int32_t)node_find(hg, ijk) : -1;
    }
}

/* Whether a cell's table breaks what the shape functions rely on: corners
 * always exist, and a face centre implies its four edge midpoints. */
static int table_invalid(const int32_t node[27])
{
    for (int q = 0; q < 27; q++) {
        int ab[3] = {q % 3, (q / 3) % 3, q / 9};
        int nmid = (ab[0] == 1) + (ab[1] == 1) + (ab[2] == 1);
        if (nmid == 0 && node[q] < 0)
            return 1;
        if (nmid != 2 || node[q] < 0)
            continue;
        for (int d = 0; d < 3; d++) {
            if (ab[d] != 1)
                continue;
            for (int end = 0; end <= 2; end += 2) {
                int e2[3] = {ab[0], ab[1], ab[2]};
                e2[d] = end;
                if (node[e2[0] + 3 * e2[1] + 9 * e2[2]] < 0)
                    return 2;
            }
        }
    }
    return 0;
}

/* Assign node indices; check every cell's candidate nodes (the tables
 * themselves are made on first use, mpm_hgrid_make_cells). */
static int hgrid_nodes(struct builder *b)
{
    struct mpm_hgrid *hg = b->hg;
    int64_t *keys;
    long nkeys;
    int rc = node_set(hg, &keys, &nkeys, b->e);
    if (rc)
        return rc;
    hg->node_ijk = malloc((size_t)nkeys * 3 * sizeof *hg->node_ijk);
    if (!hg->node_ijk) {
        free(keys);
        return err_nomem(b->e, "hierarchical grid nodes");
    }
    hg->nnodes = nkeys;
    long nx = hg->ncell_fine[0] + 1, ny = hg->ncell_fine[1] + 1;
    for (long n = 0; n < nkeys; n++) {
        hg->node_ijk[3 * n + 0] = (int32_t)(keys[n] % nx);
        hg->node_ijk[3 * n + 1] = (int32_t)((keys[n] / nx) % ny);
        hg->node_ijk[3 * n + 2] = (int32_t)(keys[n] / nx / ny);
    }
    free(keys);
    /* the cells of the tree are final: trim the array grown by doubling */
    struct mpm_hcell *trim = realloc(hg->cell, (size_t)(hg->ncell > 0 ? hg->ncell : 1) *
                                                   sizeof *trim);
    if (trim) {
        hg->cell = trim;
        hg->cap_cell = hg->ncell;
    }
    hg->cell_node_bytes = (size_t)(hg->ncell > 0 ? hg->ncell : 1) * MPM_HCELL_NODES *
                          sizeof *hg->cell_node;
    hg->cell_node = mpm_grid_zeroed_alloc(hg->cell_node_bytes);
    hg->cell_made = calloc((size_t)(hg->ncell > 0 ? hg->ncell : 1), 1);
    if (!hg->cell_node || !hg->cell_made)
        return err_nomem(b->e, "hierarchical grid node tables");
    for (int l = 0; l <= MPM_MAX_LEVELS; l++)
        hg->ncell_level[l] = 0;
    for (long c = 0; c < hg->ncell; c++) {
        const struct mpm_hcell *cl = &hg->cell[c];
        hg->ncell_level[cl->level]++;
        int32_t node[27];
        cell_table(hg, cl, node);
        int bad = table_invalid(node);
        if (bad == 1)
            return err_set(b->e, ERR_RUNTIME, "hierarchical grid: cell %ld lacks a corner", c);
        if (bad == 2)
            return err_set(b->e, ERR_RUNTIME,
                           "hierarchical grid: cell %ld has a face centre node without its "
                           "edge midpoints",
                           c);
    }
    return 0;
}

void mpm_hgrid_make_cells(struct mpm_hgrid *hg, const int32_t *cell, long n)
{
    for (long i = 0; i < n; i++) {
        long c = cell[i];
        if (c < 0 || c >= hg->ncell || hg->cell_made[c])
            continue;
        int32_t node[27];
        cell_table(hg, &hg->cell[c], node);
        int32_t *t = hg->cell_node + (long)MPM_HCELL_NODES * c;
        const struct mpm_hcell *cl = &hg->cell[c];
        memcpy(t, node, sizeof node);
        for (int q = 27; q < MPM_HCELL_NODES; q++)
            t[q] = -1;
        for (int d = 0; d < 3; d++)
            t[MPM_HCELL_LO + d] = cl->lo[d];
        t[MPM_HCELL_LG] = (int32_t)(cl->lg[0] | (unsigned)cl->lg[1] << 8 | (unsigned)cl->lg[2] << 16);
        hg->cell_made[c] = 1;
        hg->ncell_made++;
    }
}

const int32_t *mpm_hgrid_nodes(struct mpm_hgrid *hg, long c)
{
    int32_t c32 = (int32_t)c;
    mpm_hgrid_make_cells(hg, &c32, 1);
    return mpm_hgrid_cell_nodes(hg, c);
}

double mpm_hgrid_bytes(const struct mpm_hgrid *hg)
{
    long nroot = hg->nroot[0] * hg->nroot[1] * hg->nroot[2];
    return (double)hg->ncell * (sizeof(struct mpm_hcell) + 1) +
           (double)hg->ncell_made * MPM_HCELL_NODES * sizeof(int32_t) +
           (double)hg->nnodes * 3 * sizeof(int32_t) + (double)(hg->ntree + nroot) * 4;
}

int mpm_hgrid_build(struct mpm_hgrid **out, const double origin[3], double h,
                    const long ncell[3], const struct mpm_hlevel *levels, int nlevels,
                    enum mpm_hanging hanging, struct err *e)
{
    const double h3[3] = {h, h, h};
    return mpm_hgrid_build3(out, origin, h3, ncell, levels, nlevels, hanging, e);
}

int mpm_hgrid_build3(struct mpm_hgrid **out, const double origin[3], const double h[3],
                     const long ncell[3], const struct mpm_hlevel *levels, int nlevels,
                     enum mpm_hanging hanging, struct err *e)
{
    *out = NULL;
    if (nlevels < 0 || nlevels > MPM_MAX_LEVELS)
        return err_set(e, ERR_INPUT, "hierarchical grid: %d levels (at most %d)", nlevels,
                       MPM_MAX_LEVELS);
    struct mpm_hgrid *hg = calloc(1, sizeof *hg);
    if (!hg)
        return err_nomem(e, "hierarchical grid");
    hg->nlevels = nlevels;
    hg->h = h[0];
    hg->hanging = hanging;
    for (int d = 0; d < 3; d++) {
        hg->origin[d] = origin[d];
        hg->hd[d] = h[d];
        hg->ncell_fine[d] = ncell[d];
        hg->lg[0][d] = 0;
    }
    for (int l = 1; l <= nlevels; l++) {
        hg->coarsen[l] = levels[l - 1].coarsen;
        if ((hg->coarsen[l] & 7u) == 0 || (hg->coarsen[l] & ~7u)) {
            free(hg);
            return err_set(e, ERR_INPUT, "hierarchical grid: level %d coarsens no direction", l);
        }
        for (int d = 0; d < 3; d++)
            hg->lg[l][d] = hg->lg[l - 1][d] + ((hg->coarsen[l] >> d) & 1);
    }
    int L = nlevels;
    long nroot = 1;
    for (int d = 0; d < 3; d++) {
        long s = 1L << hg->lg[L][d];
        hg->nroot[d] = (ncell[d] + s - 1) / s;
        nroot *= hg->nroot[d];
    }
    hg->root = malloc((size_t)nroot * sizeof *hg->root);
    if (!hg->root) {
        free(hg);
        return err_nomem(e, "hierarchical grid");
    }
    struct builder b = {hg, levels, e, 0};
    for (long k = 0; k < hg->nroot[2] && !b.failed; k++)
        for (long j = 0; j < hg->nroot[1] && !b.failed; j++)
            for (long i = 0; i < hg->nroot[0] && !b.failed; i++) {
                long lo[3] = {i << hg->lg[L][0], j << hg->lg[L][1], k << hg->lg[L][2]};
                long r = (k * hg->nroot[1] + j) * hg->nroot[0] + i;
                make(&b, lo, L, -r - 1);
            }
    int rc = b.failed;
    if (!rc)
        rc = hgrid_balance(&b);
    if (!rc)
        rc = hgrid_nodes(&b);
    if (rc) {
        mpm_hgrid_destroy(&hg);
        return rc;
    }
    *out = hg;
    return 0;
}

void mpm_hgrid_destroy(struct mpm_hgrid **hg)
{
    if (!hg || !*hg)
        return;
    free((*hg)->root);
    free((*hg)->tree);
    free((*hg)->cell);
    free((*hg)->node_ijk);
    mpm_grid_zeroed_free((*hg)->cell_node, (*hg)->cell_node_bytes);
    free((*hg)->cell_made);
    free(*hg);
    *hg = NULL;
}
