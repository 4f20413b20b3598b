/*
 * mpm_build: material points from regions (Chen 2014, section 3.1, step 1):
 * every grid cell whose sub-positions fall in the region receives n x n x n
 * points at the reduced coordinates (k + 1/2)/n (for n = 2: +-1/2, as in
 * Guo & Yang 2005), each with the cell volume / n^3 and mass density x
 * volume.  On a hierarchical grid the points of coarse cells are
 * correspondingly larger and heavier (Guo & Yang 2005, section 2.2).
 *
 * The points of a region come in one fixed order (cell by cell, x fastest;
 * on a hierarchical grid the grid's cell order), so a point's place in that
 * order is its global id whatever the rank count: on MPI bricks every rank
 * visits every point of the case (mpm_region_visit) but stores only its
 * own (mpm_fill_region with an owner), so no rank ever holds the whole set.
 */
#ifndef CASCADE_MPM_BUILD_H
#define CASCADE_MPM_BUILD_H

#include <stdint.h>

#include "core/region.h"
#include "mpm/mpm.h"

/* Called for each point of a region in order, with its volume (its cell's
 * over n^3); a non-zero return stops the visit and is returned by it. */
typedef int (*mpm_point_visitor)(void *ctx, const double x[3], double vol);

/* Visit the points that n^3 points per cell of m's grid put in region r;
 * *count receives how many were visited (all of them unless fn stopped
 * the visit).  Returns fn's non-zero value, or 0. */
int mpm_region_visit(const struct mpm *m, const struct region *r, int n, mpm_point_visitor fn,
                     void *ctx, long *count);

/* Which points this process stores: keep(ctx, x) is non-zero for its own
 * (an MPI brick's); NULL stores every point. */
struct mpm_fill_owner {
    int (*keep)(const void *ctx, const double x[3]);
    const void *ctx;
};

/* Append the points of body `body` (already added to m) filling region r
 * with n^3 points per cell, those `owner` keeps (all when NULL).  The
 * region's k-th point (from 0) gets id first_id + k; *added receives the
 * region's point count (every rank's), *kept how many were stored here.
 * Points get the body's velocity. */
int mpm_fill_region(struct mpm *m, const struct region *r, int body, int n,
                    const struct mpm_fill_owner *owner, int64_t first_id, long *added, long *kept,
                    struct err *e);

#endif
