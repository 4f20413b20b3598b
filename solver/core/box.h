/*
 * box: an orthogonal simulation box with a boundary kind per axis.
 *
 *   periodic  images of the particles are ghosts (ghost.h)
 *   free      open: particles may go anywhere; the box follows them
 *             (shrink-wrapped at every neighbour rebuild), for output only
 *   fixed     the bounds never move; a particle leaving through them is an
 *             error ("lost"), as a fixed LAMMPS boundary
 */
#ifndef CASCADE_BOX_H
#define CASCADE_BOX_H

#include "core/particles.h"
#include "util/err.h"

enum boundary { BOUNDARY_PERIODIC = 0, BOUNDARY_FREE = 1, BOUNDARY_FIXED = 2 };

extern const char *const boundary_names[];   /* NULL-terminated, enum order */

struct box {
    double lo[3], hi[3];
    enum boundary bc[3];
};

static inline double box_length(const struct box *b, int d) { return b->hi[d] - b->lo[d]; }
double box_volume(const struct box *b);

/* Map owned particles back into periodic dimensions (updating image
 * counts), shrink-wrap free dimensions, and check fixed ones.  `margin` is
 * added around shrink-wrapped bounds.  Returns ERR_RUNTIME for a lost particle. */
int box_remap(struct box *b, struct particles *p, double margin, struct err *e);

/* Unwrapped position of owned particle i. */
void box_unwrap(const struct box *b, const struct particles *p, int i, double out[3]);

#endif
