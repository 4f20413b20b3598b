/*
 * mpm_grid: the background grid of the material point method.
 *
 * Two kinds share one node store and one interface:
 *   - uniform: a 3-D grid of cubic 8-node cells stored as a patch of nodes
 *     [lo, lo + nn) (global node indices) with a halo of `halo` nodes on
 *     every side.  In a serial run the patch is the whole grid; under domain
 *     decomposition each rank owns a patch and the halo is what an exchange
 *     module adds to and copies from the neighbours.  Node (i, j, k) of the
 *     patch (i in [-halo, nn0 + halo)) is node[(i+H) + (j+H) dim0 + (k+H) dim0 dim1].
 *   - hierarchical (mpm_hgrid.h): cells coarsen by 2 per level in 1, 2 or 3
 *     directions (Guo & Yang 2005, Fig. 1), with hanging nodes.
 *
 * Node records hold what one MUSL step accumulates: mass m (s1), momentum q
 * (s2, then the updated velocity after mpm_update_nodes), force f (s3-s4,
 * then the acceleration), and the remapped momentum r (s10, then the
 * velocity of s11).  Colouring blocks (MPM_COLOURS of them) let threads
 * scatter to nodes without races: blocks of one colour never share a node.
 */
#ifndef CASCADE_MPM_GRID_H
#define CASCADE_MPM_GRID_H

#include <stdint.h>

#include "util/err.h"

#define MPM_COLOURS 8
#define MPM_MAX_LEVELS 5

enum mpm_grid_kind { MPM_GRID_UNIFORM, MPM_GRID_HIER };
enum mpm_shape_kind { MPM_SHAPE_LINEAR, MPM_SHAPE_GIMP };
/* Shape functions on cells with hanging nodes: Guo & Yang Eq. (11) (|.|) or
 * the standard transition-element functions of Eq. (9) (squares), the
 * latter only to show the artificial forces they produce. */
enum mpm_hanging { MPM_HANGING_MODIFIED, MPM_HANGING_STANDARD };
enum mpm_face_bc { MPM_FACE_FREE, MPM_FACE_FIXED, MPM_FACE_SLIDING };

struct mpm_node {
    double m;      /* mass (amu)                                             */
    double q[3];   /* momentum (amu Å/ps); after the node update: velocity   */
    double f[3];   /* force (eV/Å); after the node update: acceleration      */
    double aux;    /* rigid body + 1 whose points touch the node (0: none)   */
};

struct mpm_hgrid;

struct mpm_grid {
    enum mpm_grid_kind kind;
    enum mpm_shape_kind shape;
    double origin[3];            /* Å: global position of node (0, 0, 0)   */
    double h, inv_h;             /* Å: (finest) cell edge along x          */
    double hd[3], inv_hd[3];     /* Å: (finest) cell edge per axis: all h but for the
                                    cells of a rotated crystal (handshake along [110]) */
    long ncell[3];               /* global cells per direction (finest)    */
    enum mpm_face_bc face[6];    /* x_lo x_hi y_lo y_hi z_lo z_hi          */

    /* uniform patch */
    long lo[3], nn[3];           /* owned nodes: global [lo, lo + nn)      */
    int halo;
    long dim[3];                 /* allocated nodes per direction          */
    long stride[3];              /* 1, dim0, dim0 dim1                     */

    /* hierarchical */
    struct mpm_hgrid *hg;

    /* node store: pages from the kernel (mpm_grid_zeroed_alloc), zero until
     * written and resident only where written -- a rank that updates only
     * its touched nodes of a whole grid (`active` below) holds the pages
     * of those, not the grid's */
    long nnodes;
    struct mpm_node *node;
    struct mpm_node *node_next;  /* second buffer of the fused pass (mpm_step), or NULL */
    double *r;                   /* 4 per node (r0 r1 r2 0): remapped momentum, then the
                                    velocity of s11; padded for vector access */
    size_t node_bytes, r_bytes;  /* sizes of node (and node_next) and r */
    int pristine;                /* node and r are as allocated (zero): the first
                                    clear has nothing to do, and writes none */

    /* the nodes the grid stages (clear, s4-s5, s11) visit, ascending, or
     * NULL for all: on bricks with shared-node sums (mpm_shared.h) a
     * rank's touched nodes, every other node being zero there.  Borrowed
     * from the plan; the clear before a mapping visits the last
     * mapping's nodes, the updates after it the new ones. */
    const int32_t *active;
    long nactive;
    const uint8_t *active_first;   /* per active node: this rank is the lowest that
                                      touches it (sums over nodes count it here), or NULL */

    /* essential boundary conditions: node and bits of the fixed components */
    long nbc;
    int32_t *bc_node;
    uint8_t *bc_bits;

    /* colouring: key (integer cell coordinate) -> block (mpm_grid.c): blocks
     * are bricks of bw[d] keys, cut across y and z (and x on grids too
     * narrow for enough blocks); block (bx, by, bz) has colour
     * (bx & 1) | (by & 1) << 1 | (bz & 1) << 2 */
    long bw[3];                  /* block width in keys per direction      */
    long nb[3];                  /* blocks per direction                   */
    long nkeys[3];               /* keys per direction                     */
    int32_t *key_block[3];       /* per direction: block coordinate of each key times
                                    the block stride (1, nb0, nb0 nb1): a block is the
                                    sum over d, no division per point */
    long nblocks;
    long ncolour[MPM_COLOURS];   /* blocks of each colour                  */
    int32_t *colour_block[MPM_COLOURS];
    int64_t *colour_key;         /* scratch of mpm_grid_order_blocks       */
};

/* Block of the keys key[0..2] (each in [0, nkeys[d])). */
static inline long mpm_grid_key_block(const struct mpm_grid *g, const long key[3])
{
    return (long)g->key_block[0][key[0]] + g->key_block[1][key[1]] + g->key_block[2][key[2]];
}

/* A uniform grid of ncell cells of edge h (Å) with its low corner at origin. */
int mpm_grid_init_uniform(struct mpm_grid *g, const double origin[3], double h,
                          const long ncell[3], enum mpm_shape_kind shape, struct err *e);
/* The same with an edge per axis (Å): cells h[0] x h[1] x h[2]. */
int mpm_grid_init_uniform3(struct mpm_grid *g, const double origin[3], const double h[3],
                           const long ncell[3], enum mpm_shape_kind shape, struct err *e);
/* The hierarchical grid `hg` (built with mpm_hgrid_build; the grid takes
 * ownership).  Linear shape functions only. */
int mpm_grid_init_hier(struct mpm_grid *g, struct mpm_hgrid *hg, struct err *e);
void mpm_grid_free(struct mpm_grid *g);

/* Set the face conditions and build the list of constrained nodes. */
int mpm_grid_set_faces(struct mpm_grid *g, const enum mpm_face_bc face[6], struct err *e);

/* Position (Å) of node `i`. */
void mpm_grid_node_position(const struct mpm_grid *g, long i, double x[3]);

/* Smallest cell edge (Å), for the CFL condition. */
double mpm_grid_min_cell(const struct mpm_grid *g);

/* Whether x lies where points may be (inside the grid's cells). */
int mpm_grid_contains(const struct mpm_grid *g, const double x[3]);

/* Domain bounds (Å). */
void mpm_grid_bounds(const struct mpm_grid *g, double lo[3], double hi[3]);

/* Zeroed, page-aligned memory whose pages become resident when first
 * written (an anonymous mapping), for the node arrays; NULL without
 * memory.  Freed with the same size. */
void *mpm_grid_zeroed_alloc(size_t bytes);
void mpm_grid_zeroed_free(void *p, size_t bytes);

/* Zero the accumulators (m, q, f, aux) of every node. */
void mpm_grid_clear(struct mpm_grid *g, int nthreads);
/* Zero n nodes (the grid's or its second buffer), threads sharing the work. */
void mpm_grid_clear_nodes(struct mpm_node *nd, long n, int nthreads);

/* Order the blocks of each colour by decreasing number of particles (ties
 * by block index): the nsets bins start[s][0..nblocks] (particles of block
 * b: start[s][b + 1] - start[s][b]).  Threads that take the blocks of a
 * colour one by one then finish together (largest first), and as blocks of
 * a colour share no node the order changes no sum at a node. */
void mpm_grid_order_blocks(struct mpm_grid *g, const long *const *start, int nsets);

/* Bytes held by the grid. */
double mpm_grid_bytes(const struct mpm_grid *g);

#endif
