/*
 * mpm_bricks: the material point method on a brick decomposition of its
 * background grid (docs/parallel.md, "MPM on bricks").
 *
 * The grid's cells are cut into grid[0] x grid[1] x grid[2] bricks along
 * cell faces, one per MPI rank (the Cartesian grid of core/parallel.h).  A
 * rank
 *   - owns the material points whose cell lies in its brick; they migrate
 *     to the owner of their new cell at the start of every step (a point
 *     moves less than a cell per step, so to one of the 26 neighbours;
 *     when the dynamic balance moves the cuts, to any rank in one
 *     all-to-all: mpm_bricks_recut);
 *   - owns the nodes of its brick's cells from their lower corner on (the
 *     first brick along an axis also the serial grid's halo node below 0,
 *     the last one the nodes at and beyond the upper face), so every node
 *     of the serial grid has exactly one owner;
 *   - holds a patch of the grid (mpm_grid's uniform patch: lo, nn, halo):
 *     its brick's cells plus MARGIN cells on every side that is not a
 *     face of the grid, plus the grid's own halo node.  A point up to
 *     MARGIN cells outside the brick still maps into the patch, which is
 *     what the fused update-and-map pass (mpm.h) needs: it maps the next
 *     step at the new positions, before the points migrate.
 * The nodes of the patch that another rank owns are ghosts.  After every
 * particle-to-grid pass their partial sums go to their owners and are
 * added there (the reverse halo: s1-s3, and the MUSL remap of s10), the
 * ghosts are zeroed, the owners update their nodes (s4-s5, s11), and the
 * owners' values go back to every ghost (the forward halo), so the
 * grid-to-particle passes (s6-s8, s12) see complete nodes.  Each message
 * goes straight to the neighbour that owns (or holds) the nodes: the
 * patches of edge and corner neighbours overlap too.
 *
 * What is global: the time step (the largest point speed is a maximum over
 * the ranks), the small-mass threshold (the lightest point of all), the
 * energies, momenta and rigid-body reactions (sums over the ranks), and
 * the decision to keep a fused mapping (all ranks keep theirs or all map
 * afresh: a point that migrated was mapped by its old owner).  Round-off:
 * a node's mass, momentum and force are sums over points; on bricks the
 * ghost contributions are added after the owner's own, so the last bits
 * differ from a serial run (docs/parallel.md gives the measured agreement).
 *
 * A hierarchical grid (mpm_hgrid.h) is not cut into patches: its cells
 * differ in size and a hanging node's shape functions (Guo & Yang Eq. 11)
 * reach across the faces of cells of two sizes.  On bricks (`whole`) every
 * rank holds the whole grid; the points are owned and migrate exactly as on
 * a uniform grid (the cuts are along the finest cells); after every
 * particle-to-grid pass the nodes' mass, momentum and force (and the MUSL
 * remap) are made complete where this rank's particles read them: only the
 * nodes two ranks share are exchanged, and every rank adds a node's partial
 * sums in rank order, so every copy of a node has the same bits and every
 * rank updates its nodes as the others do; the hanging nodes need nothing
 * more, since a particle's shape functions reach only its cell's nodes
 * (mpm_shared.h; 64 bytes per shared node per step, +32 with MUSL).  A
 * rigid body's node mark (aux) is shared as a maximum, and its reaction is
 * counted on each node by the lowest rank that touches it, then summed
 * over the ranks.
 *
 * Fixed owners (`fixed`, mpm_bricks_create_fixed): a whole grid whose
 * points are dealt out once by the caller and never migrate.  With the
 * grid whole on every rank a point needs no nodes near its owner, so any
 * partition of the points gives the same node sums; the handshake deals
 * its points out by the MD's bricks (couple/handshake_bricks.h), so that a
 * point and its MD copy mostly share a rank.  A uniform grid of fixed
 * owners (the handshake bars' grids) exchanges its shared nodes' sums as
 * a hierarchical one does (its touched nodes are its particles' stencils);
 * until 2026-11-28 it summed every node over all ranks by one reduction,
 * 64 bytes a node per step (+32 with MUSL).
 *
 * Extra particle sets (the couplings) are not decomposed here: each rank
 * maps its own extra particles, which a whole grid's reduction adds up.
 */
#ifndef CASCADE_MPM_BRICKS_H
#define CASCADE_MPM_BRICKS_H

#include <stdint.h>

#include "mpm/mpm.h"
#include "mpm/mpm_build.h"
#include "util/err.h"

struct parallel;
struct parallel_settings;
struct cfg;
struct mpm_shared;

#define MPM_BRICKS_MARGIN 1   /* cells a point may be outside its brick and still map */
#define MPM_BRICKS_NBR 26

/* Node lists exchanged with one neighbour (offset o = (dx, dy, dz)). */
struct mpm_bricks_link {
    int rank_to, rank_from;   /* the ranks at coords + o and coords - o (-1: none) */
    int32_t *ghost;           /* my ghost nodes the rank at +o owns (patch indices) */
    long nghost;
    int32_t *owned;           /* my owned nodes the rank at -o holds as ghosts */
    long nowned;
};

struct mpm_bricks {
    const struct parallel *par;   /* borrowed */
    int grid[3], coords[3];
    long *cut[3];                 /* grid[d] + 1 cell indices along d: brick c has cells
                                     [cut[d][c], cut[d][c + 1]) */
    int shift;                    /* parallel.balance: shift -- cuts at the points'
                                     quantiles (mpm_bricks_shift_cuts, before the points
                                     are made) */
    int whole;                    /* every rank holds the grid whole (no patch, no
                                     links): on more than one rank it exchanges its
                                     shared nodes' sums (mpm_shared.h) */
    int fixed;                    /* whole, and the points never migrate (the caller
                                     dealt them out: mpm_bricks_create_fixed) */
    int rigid;                    /* whole: some body is rigid (the nodes' aux is reduced
                                     as a maximum) */
    double *wbuf;                 /* whole: the nodes' aux during a reduction */
    struct mpm_shared *shared;    /* whole, a hierarchical grid, more than one rank:
                                     the shared nodes' plan (mpm_shared.h), or NULL */
    long ncell[3];                /* the serial grid's cells */
    long serial_nodes;            /* the serial grid's node count (with its halo) */
    size_t wcap;
    struct mpm_bricks_link link[MPM_BRICKS_NBR];
    uint8_t *is_ghost;            /* per patch node */
    double *sbuf, *rbuf;          /* message buffers */
    size_t scap, rcap;
    unsigned char *pbuf;          /* migration buffers */
    size_t pcap;
    void *prbuf;
    size_t prcap;
    long migrated;                /* points sent away in the last step (diagnostics) */
    /* The leaver scan of the end of the last step, whose flags travelled
     * with that step's sums (one sync point less a step): the next
     * migration takes it instead of scanning and reducing again. */
    int scan_valid;
    long scan_nleave;             /* this rank's points whose cell another brick owns */
    long long scan_far_id;        /* id of a point of this rank beyond the neighbours, or -1 */
    int scan_any_far, scan_any_leave;   /* the same over all ranks */
    /* dynamic balance (`parallel.balance_every`; mpm_bricks_balance.c): the
     * schedule and what its checks found */
    long balance_every;           /* steps between checks, 0: the cuts stay */
    double balance_threshold;     /* max/mean points above which the cuts move */
    long balance_next;            /* the next check at the first step at or after this */
    long balance_checks, balance_shifts;
    double balance_worst;         /* the largest max/mean a check measured */
};

/* Whether a `type: mpm` case runs on bricks: *out a new decomposition
 * plan (grid of ranks and cell cuts; the caller owns it) or NULL for a
 * serial or replicated run.  Refuses, naming the case file, line and key,
 * a grid that does not multiply to the rank count or cuts an axis into
 * bricks thinner than 4 cells (a hierarchical grid: 4 finest cells); a
 * hierarchical grid runs with the whole grid on every rank (`whole`).
 * c: the case's cfg (for messages). */
int mpm_bricks_plan(const struct parallel *par, const struct parallel_settings *ps,
                    const struct mpm_grid *g, int hierarchical, struct cfg *c,
                    struct mpm_bricks **out);

/* The points along each axis the bricks cut, by cell layer, for shifted
 * boundaries: every rank counts every point of the case (mpm_region_visit)
 * before any is made, so every rank computes the same cuts. */
struct mpm_bricks_hist {
    long *layer[3];   /* ncell[d] counts, NULL along an axis not cut */
    long n;           /* points counted */
};
int mpm_bricks_hist_init(const struct mpm_bricks *b, struct mpm_bricks_hist *h, struct err *e);
void mpm_bricks_hist_add(const struct mpm_bricks *b, const struct mpm_grid *g,
                         struct mpm_bricks_hist *h, const double x[3]);
void mpm_bricks_hist_free(struct mpm_bricks_hist *h);
/* Shifted boundaries (parallel.balance: shift): along every axis cut more
 * than once the cuts go to the quantiles of the counted points, then apart
 * where needed so that every brick keeps 4 cells. */
void mpm_bricks_shift_cuts(struct mpm_bricks *b, const struct mpm_bricks_hist *h);

/* The filter that makes the points of this rank's brick only (g: the
 * whole grid the case builds), for mpm_fill_region.  b must outlive it. */
struct mpm_bricks_owner {
    const struct mpm_bricks *b;
    const struct mpm_grid *g;
};
struct mpm_fill_owner mpm_bricks_fill_owner(const struct mpm_bricks_owner *o);
/* Whether the point at x lies in a cell of this rank's brick (g: the grid
 * or this rank's patch of it). */
int mpm_bricks_owns_point(const struct mpm_bricks *b, const struct mpm_grid *g, const double x[3]);

/* m's points are this rank's already (made with mpm_bricks_fill_owner):
 * replace the whole grid the case built by this rank's patch (a
 * hierarchical grid stays whole) and set up the exchanges.  Collective. */
int mpm_bricks_distribute(struct mpm_bricks *b, struct mpm *m, struct err *e);

void mpm_bricks_destroy(struct mpm_bricks **b);

/* A decomposition with the grid whole on every rank and fixed owners (see
 * the top of this file) for m, whose points the caller has already cut
 * down to this rank's.  Collective. */
int mpm_bricks_create_fixed(const struct parallel *par, const struct mpm *m,
                            struct mpm_bricks **out, struct err *e);

/* mpm_prepare over all ranks: thresholds, the largest speed and the
 * energies of the points of every rank.  Collective. */
int mpm_bricks_prepare(struct mpm_bricks *b, struct mpm *m, struct err *e);

/* The engine's force and integrate stages on bricks (mpm_step_map and
 * mpm_step_update with the exchanges).  Collective; an error on one rank
 * is an error on every rank. */
int mpm_bricks_step_map(struct mpm_bricks *b, struct mpm *m, struct err *e);
int mpm_bricks_step_update(struct mpm_bricks *b, struct mpm *m, double dt, struct err *e);

/* A whole grid whose sums only the sharing ranks exchanged (mpm_shared.h):
 * on rank 0, copies of the nodes and of the remap r with every node
 * complete, for output of the whole grid (*node and *r malloc'ed, the
 * caller frees them); NULL on the other ranks, which send their nodes a
 * window at a time (mpm_shared_gather_root), and for other
 * decompositions, whose arrays are complete already.  Collective. */
int mpm_bricks_complete_grid(struct mpm_bricks *b, const struct mpm *m, struct mpm_node **node,
                             double **r, struct err *e);

/* Of the shared-node sums (mpm_shared.h): the most nodes a rank shares
 * with others in the last plan, and the plans made so far (0 and 0
 * without them).  Collective. */
void mpm_bricks_shared_counts(const struct mpm_bricks *b, long *nodes_max, long *plans);

/* Sums, maxima over the ranks (no-op when b is NULL). */
void mpm_bricks_sum(const struct mpm_bricks *b, double *buf, int n);
void mpm_bricks_max(const struct mpm_bricks *b, double *buf, int n);
/* rc made collective (an error on any rank is an error on every rank). */
int mpm_bricks_agree(const struct mpm_bricks *b, int rc, struct err *e);
/* mpm_totals over all ranks. */
void mpm_bricks_totals(const struct mpm_bricks *b, const struct mpm *m, struct mpm_totals *t);
/* Points of all ranks. */
long mpm_bricks_npoints(const struct mpm_bricks *b, const struct mpm *m);
int mpm_bricks_rank(const struct mpm_bricks *b);

/* The nodes of the grid (0 .. ncell along each axis, not its halo) this
 * rank owns: global nodes [lo[d], hi[d]) along x, y, z, a block of its
 * patch; the blocks of the ranks tile the grid without overlap (a uniform
 * grid cut into bricks: the snapshot's collective write of the nodes). */
void mpm_bricks_node_block(const struct mpm_bricks *b, long lo[3], long hi[3]);
/* The step-0 mapping (s9, s1-s3 and the reverse halo) for a snapshot of
 * the initial grid.  Collective. */
int mpm_bricks_map_initial(struct mpm_bricks *b, struct mpm *m, struct err *e);

/* The cuts have changed (b->cut): every point goes to the owner of its
 * cell, whichever rank that is (one all-to-all exchange, not the 26
 * neighbours of a step's migration), a uniform grid's patch, node lists
 * and colouring blocks are made anew for the new brick, and the next step
 * maps afresh (a fused mapping of the old patch is dropped).  Kept points
 * stay in their order, arrivals follow in rank order.  Collective. */
int mpm_bricks_recut(struct mpm_bricks *b, struct mpm *m, struct err *e);

/* Dynamic balance, as the particles' engines have it (core/halo.h,
 * halo_balance_step): checks every `every` steps (from step `every` on)
 * whether the largest point count of a rank exceeds `threshold` times the
 * mean, and if so moves the cuts to the quantiles of the points' present
 * cells (mpm_bricks_shift_cuts) and the points with them
 * (mpm_bricks_recut).  Not for fixed owners (the handshake's). */
void mpm_bricks_balance_schedule(struct mpm_bricks *b, long every, double threshold);
/* At the start of a step (before the step's migration), when a check is
 * due.  Collective; 0 when nothing is due or nothing moved. */
int mpm_bricks_balance_step(struct mpm_bricks *b, struct mpm *m, struct err *e);
/* A checkpoint written or read (before the points go into id order): with
 * a schedule, the cuts go to the points now and the next check is set
 * from the present step, so a continuing run and one restarted from the
 * checkpoint go on with the same cuts and the same points per rank.
 * Collective. */
int mpm_bricks_balance_sync(struct mpm_bricks *b, struct mpm *m, struct err *e);

/* This rank's points in id order (the order a restart reads them in, so
 * that a run continued after a checkpoint and one restarted from it sum in
 * the same order).  Collective. */
int mpm_bricks_sort_by_id(struct mpm_bricks *b, struct mpm *m, struct err *e);

#endif
