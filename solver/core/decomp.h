/*
 * decomp: the brick decomposition of an orthogonal box over MPI ranks.
 *
 * The box is cut into grid[0] x grid[1] x grid[2] equal bricks, one per
 * rank (the Cartesian grid of core/parallel.h).  A particle belongs to the
 * brick its coordinates fall in: c = floor((x - lo) / L * grid) per axis,
 * clamped to the grid, so every rank assigns every position to the same
 * owner.  The halo exchange (halo.h) needs each brick at least as wide as
 * the interaction range (cutoff + skin) along every decomposed or periodic
 * axis, so that one exchange per face reaches every ghost.
 */
#ifndef CASCADE_DECOMP_H
#define CASCADE_DECOMP_H

#include <stddef.h>

#include "core/box.h"
#include "util/err.h"

struct parallel;

struct decomp {
    const struct parallel *par;   /* borrowed */
    int grid[3], coords[3];
    int nbr[3][2];                /* rank below / above along each axis (-1: none) */
    int periodic[3];
    double blo[3], bhi[3];        /* the box the bricks cut */
    double lo[3], hi[3];          /* this rank's brick */
    /* shifted boundaries (decomp_shift): the cuts along each axis as
     * fractions of the box, grid[d] + 1 of them from 0 to 1; NULL: equal
     * bricks */
    double *frac[3];
};

/* The grid for nranks bricks of the box: of the factorisations px py pz =
 * nranks whose bricks are at least `range` wide (along every axis with more
 * than one brick, and along every periodic one), the one with the smallest
 * brick surface (the ghost volume), as LAMMPS' procs2box.  (MPI_Dims_create
 * balances the factors but ignores the box shape.)  Returns 0, or -1 when
 * no factorisation gives wide enough bricks. */
int decomp_choose_grid(int nranks, const struct box *b, double range, int grid[3]);

/* 0 when the grid fits the box and range, else -1 with the reason in why. */
int decomp_check_grid(const int grid[3], const struct box *b, double range, char *why,
                      size_t len);

/* Set up the bricks of grid over par's ranks for box b. */
int decomp_init(struct decomp *dc, const struct parallel *par, const int grid[3],
                const struct box *b, struct err *e);

void decomp_free(struct decomp *dc);

/* Shifted boundaries, as LAMMPS' `balance shift`: along every axis cut
 * more than once, the cuts move to the quantiles of the particles' global
 * distribution along that axis (a histogram of 4096 bins summed over the
 * ranks), so each slab of bricks holds about the same number of
 * particles, and then apart where needed so that every brick stays at
 * least `range` wide.  x: this rank's n positions.  Collective; every
 * rank computes the same cuts.  The bricks keep their fractions of the
 * box when it shrink-wraps. */
int decomp_shift(struct decomp *dc, const double *x, int n, double range, struct err *e);

/* The thinnest brick along axis d (Å). */
double decomp_min_width(const struct decomp *dc, int d);

/* The box changed (free axes shrink-wrap): recompute the bricks. */
void decomp_set_box(struct decomp *dc, const struct box *b);

/* Brick coordinate along axis d of a position. */
int decomp_coord(const struct decomp *dc, int d, double x);

/* 1 when x lies in this rank's brick. */
int decomp_owns(const struct decomp *dc, const double x[3]);
/* The same as a point predicate (dc: a struct decomp), for the builders
 * and readers that keep one brick's points (lattice_fill_where,
 * ckpt_get_particles_where). */
int decomp_owns_point(const void *dc, const double x[3]);

/* The rank whose brick holds x (positions beyond the box clamp to the
 * nearest brick, as decomp_coord). */
int decomp_owner(const struct decomp *dc, const double x[3]);

#endif
