/*
 * mpm_build: material points from regions (Chen 2014, section 3.1, step 1):
 * every grid cell whose sub-positions fall in the region receives n x n x n
 * points at the reduced coordinates (k + 1/2)/n (for n = 2: +-1/2, as in
 * Guo & Yang 2005), each with the cell volume / n^3 and mass density x
 * volume.  On a hierarchical grid the points of coarse cells are
 * correspondingly larger and heavier (Guo & Yang 2005, section 2.2).
 */
#ifndef CASCADE_MPM_BUILD_H
#define CASCADE_MPM_BUILD_H

#include "core/region.h"
#include "mpm/mpm.h"

/* Append the points of body `body` (already added to m) filling region r
 * with n^3 points per cell; *added receives the count.  Points get the
 * body's velocity. */
int mpm_fill_region(struct mpm *m, const struct region *r, int body, int n, long *added,
                    struct err *e);

#endif
