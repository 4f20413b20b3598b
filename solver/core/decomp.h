/*
 * decomp: the brick decomposition of the box over MPI ranks.
 *
 * The box is cut into grid[0] x grid[1] x grid[2] equal bricks, one per
 * rank (the Cartesian grid of core/parallel.h).  A particle belongs to the
 * brick its coordinates fall in: c = floor((x - lo) / L * grid) per axis,
 * clamped to the grid, so every rank assigns every position to the same
 * owner.  The halo exchange (halo.h) needs each brick at least as wide as
 * the interaction range (cutoff + skin) along every decomposed or periodic
 * axis, so that one exchange per face reaches every ghost.
 *
 * A tilted box (core/box.h: LAMMPS' restricted triclinic cell, periodic
 * along all three axes) is cut as LAMMPS cuts it, in fractional ("lamda")
 * coordinates: brick c along axis d holds the positions whose fractional
 * coordinate s_d falls in its share of [0, 1), so the bricks are
 * parallelepipeds with the cell's faces.  The decomposition keeps its
 * bricks as intervals of the "cut coordinate" u_d = lo_d + s_d L_d
 * (decomp_cut_coord; the position itself in an orthogonal box), and a
 * length across the faces of edge d -- the interaction range, a brick's
 * thickness -- is r L_d / h_d in u_d, h_d the cell's height across those
 * faces (box_height), so a particle within r of a brick's faces is within
 * r L_d / h_d of its interval (decomp_range_along).
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
    /* a tilted box (decomp_set_box): its tilt, xy xz yz, and its heights
     * across the faces of each edge; tilted 0: an orthogonal box */
    int tilted;
    double tilt[3], height[3];
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

/* The thinnest brick along axis d, in cut coordinates (Å). */
double decomp_min_width(const struct decomp *dc, int d);

/* The box the bricks cut (bounds and tilt; the boundaries left periodic,
 * as a tilted box's are). */
void decomp_box(const struct decomp *dc, struct box *b);

/* The box changed (free axes shrink-wrap): recompute the bricks. */
void decomp_set_box(struct decomp *dc, const struct box *b);

/* Brick coordinate along axis d of the cut coordinate x (decomp_cut_coord;
 * in an orthogonal box the position's coordinate d). */
int decomp_coord(const struct decomp *dc, int d, double x);

/* The cut coordinate u_d of position x: x[d] in an orthogonal box, lo_d +
 * s_d L_d in a tilted one (s the fractional coordinates). */
double decomp_cut_coord(const struct decomp *dc, int d, const double x[3]);

/* Brick coordinate along axis d of position x. */
int decomp_coord_at(const struct decomp *dc, int d, const double x[3]);

/* A distance across the faces of edge d (the range of the halo exchange,
 * a brick's least thickness) in cut coordinates: r in an orthogonal box,
 * r L_d / h_d in a tilted one. */
double decomp_range_along(const struct decomp *dc, int d, double r);

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
