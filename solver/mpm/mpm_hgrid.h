/*
 * mpm_hgrid: hierarchical background grid (Guo & Yang 2005, section 2.1,
 * Fig. 1): cells coarsen by 2 per level in 1, 2 or 3 directions, up to
 * MPM_MAX_LEVELS levels, so that 2, 4 or 8 finer cells condense into one.
 *
 * Coordinates are integers on the finest lattice (node (i, j, k) sits at
 * origin + h (i, j, k)).  A cell of level l spans 2^lg[l][d] finest cells in
 * direction d and is aligned to its size.  Level l is wanted wherever a
 * point lies inside the regions of levels 1..l; the grid is built top-down
 * (coarsest blocks split until they are wanted whole) and then refined until
 * neighbouring cells differ by at most a factor 2 per direction, so every
 * node on a cell's boundary is a corner, an edge midpoint or a face centre
 * of that cell.  Such "hanging" nodes get the modified linear shape
 * functions of Guo & Yang Eq. (11) (mpm_shape.h).
 *
 * Cells are found from a position by a dense array of root blocks (the
 * coarsest cell size) and a descent of at most MPM_MAX_LEVELS steps.
 *
 * A cell's candidate nodes (its node table, 27 entries) are made when a
 * particle first lies in it (mpm_hgrid_make_cells, called by the locate
 * step): the tables come zero from the kernel and only the made ones are
 * resident, so a rank that holds the whole grid but whose particles lie in
 * a part of it holds the tables of that part -- the cells' geometry (16
 * bytes a cell), the tree and the nodes' coordinates (12 bytes a node) are
 * whole, the tables (128 bytes a cell) are not.
 */
#ifndef CASCADE_MPM_HGRID_H
#define CASCADE_MPM_HGRID_H

#include <stdint.h>

#include "core/region.h"
#include "mpm/mpm_grid.h"
#include "util/err.h"

/* Tree entries: >= 0 a cell, HG_EMPTY no cell (outside the domain),
 * <= HG_SPLIT_BASE children start at index HG_SPLIT_BASE - entry. */
#define HG_EMPTY (-1)
#define HG_SPLIT_BASE (-2)

struct mpm_hcell {
    int32_t lo[3];      /* finest-lattice coordinates of the low corner     */
    uint8_t lg[3];      /* log2 of the cell size (finest cells) per direction */
    uint8_t level;
};

/* Entries between two cells' node tables, 128 bytes, so a table is two
 * whole cache lines: 27 nodes (the node at candidate (a, b, c) in
 * {0,1,2}^3 at index a + 3b + 9c, 1 = midpoint; -1 when absent), then a
 * copy of the cell's geometry for the shape functions, which then read
 * one record: its low corner (MPM_HCELL_LO, 3 entries) and its sizes
 * (MPM_HCELL_LG: lg[0] | lg[1] << 8 | lg[2] << 16). */
#define MPM_HCELL_NODES 32
#define MPM_HCELL_LO 27
#define MPM_HCELL_LG 30

struct mpm_hlevel {
    unsigned coarsen;   /* direction bits (x 1, y 2, z 4) halved from level l-1 */
    struct region region;
};

struct mpm_hgrid {
    int nlevels;
    unsigned coarsen[MPM_MAX_LEVELS + 1];
    int lg[MPM_MAX_LEVELS + 1][3];   /* log2 cell size of level l per direction */
    long ncell_fine[3];
    double origin[3], h;             /* h: finest edge along x */
    double hd[3];                    /* finest edge per axis (all h for cubic cells) */
    enum mpm_hanging hanging;

    long nroot[3];
    int32_t *root;                   /* tree entry of each root block        */
    int32_t *tree;
    long ntree, cap_tree;

    struct mpm_hcell *cell;
    long ncell, cap_cell;
    long ncell_level[MPM_MAX_LEVELS + 1];

    int32_t *node_ijk;               /* 3 per node: finest-lattice coordinates, in
                                        lexicographic order (k slowest) */
    long nnodes;

    int32_t *cell_node;              /* node tables, MPM_HCELL_NODES a cell, made on
                                        first use (zero pages until then) */
    size_t cell_node_bytes;
    uint8_t *cell_made;              /* per cell: its node table is made */
    long ncell_made;
};

/* Build the grid over ncell finest cells of edge h (Å) from `origin`, with
 * `nlevels` levels (0: uniform).  Level regions are in Å. */
int mpm_hgrid_build(struct mpm_hgrid **out, const double origin[3], double h,
                    const long ncell[3], const struct mpm_hlevel *levels, int nlevels,
                    enum mpm_hanging hanging, struct err *e);
/* The same with a finest edge per axis, h[0] x h[1] x h[2] (Å). */
int mpm_hgrid_build3(struct mpm_hgrid **out, const double origin[3], const double h[3],
                     const long ncell[3], const struct mpm_hlevel *levels, int nlevels,
                     enum mpm_hanging hanging, struct err *e);
void mpm_hgrid_destroy(struct mpm_hgrid **hg);

/* Make the node tables of the cells cell[0..n) (entries < 0 skipped) that
 * are not made yet.  Not thread-safe: the locate step calls it after its
 * threaded pass, before any pass reads the tables. */
void mpm_hgrid_make_cells(struct mpm_hgrid *hg, const int32_t *cell, long n);

/* The node table of cell c, which must be made (the cells of located
 * particles are). */
static inline const int32_t *mpm_hgrid_cell_nodes(const struct mpm_hgrid *hg, long c)
{
    return hg->cell_node + (long)MPM_HCELL_NODES * c;
}

/* The node table of cell c, made now if it is not yet (for callers outside
 * the step: set-up, output, tests). */
const int32_t *mpm_hgrid_nodes(struct mpm_hgrid *hg, long c);

/* Bytes the grid's structure holds: the cells, tree, node coordinates and
 * the node tables made so far. */
double mpm_hgrid_bytes(const struct mpm_hgrid *hg);

/* Cell containing x (Å), or -1 outside. */
static inline long mpm_hgrid_find(const struct mpm_hgrid *hg, const double x[3])
{
    long i[3];
    for (int d = 0; d < 3; d++) {
        double u = (x[d] - hg->origin[d]) / hg->hd[d];
        if (!(u >= 0) || u >= (double)hg->ncell_fine[d])
            return -1;
        i[d] = (long)u;
    }
    int L = hg->nlevels;
    long r = ((i[2] >> hg->lg[L][2]) * hg->nroot[1] + (i[1] >> hg->lg[L][1])) * hg->nroot[0] +
             (i[0] >> hg->lg[L][0]);
    int32_t t = hg->root[r];
    int lev = L;
    while (t <= HG_SPLIT_BASE) {
        long base = HG_SPLIT_BASE - t;
        unsigned mask = hg->coarsen[lev];
        int child = 0, bit = 0;
        for (int d = 0; d < 3; d++)
            if (mask & (1u << d))
                child |= (int)((i[d] >> hg->lg[lev - 1][d]) & 1) << bit++;
        t = hg->tree[base + child];
        lev--;
    }
    return t;
}

#endif
