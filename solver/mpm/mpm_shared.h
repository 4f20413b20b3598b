/*
 * mpm_shared: the node sums of a grid held whole on every rank
 * (mpm_bricks.h, `whole`: a hierarchical grid, or the uniform grid of a
 * handshake bar), exchanged only where ranks share nodes.
 *
 * After a particle-to-grid pass each rank holds partial sums on the nodes
 * of the cells its particles (its material points and its extra sets) lie
 * in -- its touched nodes -- and zeros elsewhere.  A node's complete value
 * is the sum over the ranks that touch it.  Rather than reduce the whole
 * grid over all ranks (8 doubles a node, every node, every step), each rank
 * sends its partial sums of the nodes it shares with another rank to that
 * rank, and every rank adds the contributions of a node in ascending rank
 * order, its own at its place: every rank that touches a node computes the
 * same additions in the same order, so every copy has the same bits and
 * every rank updates its nodes exactly as the others do.  A particle's
 * shape functions reach only its cell's nodes (Guo & Yang 2005, Eq. (11),
 * hanging nodes included, mpm_shape.c), so a rank's particles read back
 * only its touched nodes, which are then complete; the nodes it does not
 * touch stay zero on it, so the grid stages (the clear before a mapping,
 * s4-s5, s11) visit only the touched nodes (mpm_grid.h, `active`): the
 * clear those of the last mapping, the updates those of the new one.
 *
 * The plan (which nodes a rank shares with which rank) is made when the
 * touched sets change: each rank marks its touched nodes after locating
 * its particles, and when any rank's set differs from the last plan's, the
 * ranks exchange their sets where their index ranges overlap and intersect
 * them.  The hierarchical grid numbers its nodes in lexicographic order of
 * (i, j, k), k slowest, so ranks that hold slabs of the body touch short,
 * mostly disjoint index ranges.
 */
#ifndef CASCADE_MPM_SHARED_H
#define CASCADE_MPM_SHARED_H

#include <stddef.h>
#include <stdint.h>

#include "util/err.h"

struct parallel;
struct mpm;

/* The most doubles a node a sum carries (a node record: m, q, f, aux). */
#define MPM_SHARED_MAX_NC 8

struct mpm_shared {
    const struct parallel *par;   /* borrowed */
    uint8_t *cell_mark;           /* per cell of the grid: a particle of this rank lies in it */
    uint8_t *node_mark;           /* per node: bit 0 touched here, bit 1 shared */
    long ncell, nnodes;
    int32_t *touched;             /* this rank's touched nodes, ascending (the plan's) */
    long ntouched;
    uint8_t *first;               /* per touched node: no lower rank touches it */
    int32_t *fresh;               /* the touched nodes of the current mapping */
    long nfresh;
    int32_t *list;                /* per rank r: the nodes shared with r, ascending */
    long *count, *displ;          /* size entries each: list + displ[r], count[r] nodes */
    long nlist, cap_list;
    int32_t *uni;                 /* the union of the shared lists, ascending */
    long nuni;
    double *sbuf, *rbuf, *own;    /* packed values: sent, received, this rank's own */
    size_t sbuf_cap, rbuf_cap, own_cap;
    int *scount, *sdispl, *rcount, *rdispl;   /* bytes, for the all-to-all */
    int valid;                    /* a plan is in place */
    long rebuilds;                /* plans made (diagnostics) */
};

/* An empty plan for m's grid (no MPI traffic). */
int mpm_shared_init(struct mpm_shared *s, const struct parallel *par, const struct mpm *m,
                    struct err *e);
void mpm_shared_free(struct mpm_shared *s);

/* Mark this rank's touched nodes from the cells of its located particles
 * (every set of m) and make a new plan if any rank's set changed.
 * Collective; an error on one rank is an error on every rank. */
int mpm_shared_plan(struct mpm_shared *s, const struct mpm *m, struct err *e);

/* The partial sums at base (nc doubles a node, contiguous) of the shared
 * nodes made complete, added in rank order (see above); aux_max: the last
 * value of a node (a rigid body's mark, body + 1) is a maximum instead.
 * Collective. */
int mpm_shared_sum(struct mpm_shared *s, double *base, int nc, int aux_max, struct err *e);

/* Every node of the grid complete on rank 0 alone, for output of the
 * whole grid (base: nc doubles a node, as the step left it): rank 0
 * copies its own arrays into out (nnodes * nc doubles, rank 0's; NULL
 * elsewhere) and receives, a window of node indices at a time, the
 * nodes each other rank is the lowest to touch (one non-zero term a
 * node: exact), so no other rank holds more than a window of records.
 * Collective; an error on one rank is an error on every rank. */
int mpm_shared_gather_root(struct mpm_shared *s, const double *base, int nc, double *out,
                           struct err *e);

/* Shared nodes of this rank (with any other rank, each counted once). */
long mpm_shared_nodes(const struct mpm_shared *s);

#endif
