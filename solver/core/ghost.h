/*
 * ghost: periodic images as ghost particles -- the serial form of the halo
 * exchange (CoMD's pattern).  Under the MPI brick decomposition (particles
 * with a halo, core/halo.h) ghosts come from neighbour ranks and the
 * functions below dispatch to the halo exchange; kernels do not change.
 *
 * Ghosts are rebuilt with the neighbour list (ghost_build) and refreshed
 * every step in between (ghost_update_positions).  Data flows owner ->
 * ghost (ghost_forward) and ghost -> owner (ghost_reverse_add).
 */
#ifndef CASCADE_GHOST_H
#define CASCADE_GHOST_H

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

/* Create ghosts for every periodic axis: images of owned particles (and of
 * ghosts made for earlier axes, which covers edges and corners) that lie
 * within `range` of the box.  Several image layers are made when the box is
 * shorter than `range`.  Existing ghosts are dropped first.  A tilted box
 * (core/box.h) selects the images by their fractional coordinates (see
 * ghost.c). */
int ghost_build(struct particles *p, const struct box *b, double range, struct err *e);

/* Ghosts ghost_build would make for n particles spread uniformly over the
 * box: n (prod over periodic axes of (1 + 2 range / L) - 1).  ghost_build
 * refuses (ERR_INPUT) a range whose estimate is beyond what int particle
 * indices hold, before making any: a cutoff of 1e9 Å in a 16 Å box means
 * 1e8 image layers per axis. */
double ghost_estimate(const struct box *b, long n, double range);

/* x[g] = x[origin[g]] + gshift[g] . (a, b, c) (gshift[g] * L per axis in
 * an orthogonal box), for all ghosts; extra fields flagged
 * ghost_copy are copied as well. */
void ghost_update_positions(struct particles *p, const struct box *b);
/* Copy velocities to ghosts (needed by velocity-dependent pair forces). */
void ghost_update_velocities(struct particles *p);

/* The array holds this rank's partial sums over owned and ghost entries
 * (forces, densities, ...): sum them over ranks (parallel runs), then add
 * each ghost's entry to its owner: arr[ncomp * origin[g] + c] += arr[ncomp * g + c]. */
void ghost_reverse_add(const struct particles *p, double *arr, int ncomp);
/* arr[ncomp * g + c] = arr[ncomp * origin[g] + c]. */
void ghost_forward(const struct particles *p, double *arr, int ncomp);

#endif
