/*
 * region: geometric regions used to select lattice sites, groups of
 * particles and material-point bodies.
 *
 *   box       lo, hi                          (Å)
 *   sphere    center, radius
 *   slab      axis (x|y|z), lo, hi            (all of space between two planes)
 *   cylinder  axis, center (2 coordinates across the axis), radius, lo, hi
 *
 * `side: out` selects the complement.
 */
#ifndef CASCADE_REGION_H
#define CASCADE_REGION_H

#include "util/cfg.h"

enum region_shape { REGION_BOX, REGION_SPHERE, REGION_SLAB, REGION_CYLINDER };

struct region {
    enum region_shape shape;
    double lo[3], hi[3];   /* box; slab/cylinder use lo[axis], hi[axis] */
    double center[3];      /* sphere; cylinder uses the two axes across */
    double radius;
    int axis;
    int outside;           /* select the complement */
};

int region_contains(const struct region *r, const double x[3]);

/* Bounding box of the region (infinite extents where unbounded). */
void region_bounds(const struct region *r, double lo[3], double hi[3]);

/* Volume (Å^3) of a bounded, inside region; INFINITY otherwise. */
double region_volume(const struct region *r);

/* Read a region mapping (see the keys above). */
int region_read(struct cfg_obj *o, struct region *r);

#endif
