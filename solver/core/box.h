/*
 * box: the simulation cell with a boundary kind per axis.
 *
 *   periodic  images of the particles are ghosts (ghost.h)
 *   free      open: particles may go anywhere; the box follows them
 *             (shrink-wrapped at every neighbour rebuild), for output only
 *   fixed     the bounds never move; a particle leaving through them is an
 *             error ("lost"), as a fixed LAMMPS boundary
 *
 * The cell is LAMMPS' restricted triclinic one: edge vectors from lo
 *
 *   a = (lx, 0, 0),  b = (xy, ly, 0),  c = (xz, yz, lz),   l = hi - lo,
 *
 * tilt = (xy, xz, yz) in Å; tilt 0 0 0 is the orthogonal box, and every
 * function below takes the orthogonal code path then (bitwise the results
 * of the orthogonal-only box).  A position is x = lo + s0 a + s1 b + s2 c
 * with fractional (LAMMPS "lamda") coordinates s in [0, 1) inside the
 * cell.  A tilted box is periodic along all three axes (box_check_tilt);
 * the periodic image of shift n (integers) is x + n0 a + n1 b + n2 c.
 */
#ifndef CASCADE_BOX_H
#define CASCADE_BOX_H

#include <stddef.h>

#include "core/particles.h"
#include "util/err.h"

enum boundary { BOUNDARY_PERIODIC = 0, BOUNDARY_FREE = 1, BOUNDARY_FIXED = 2 };

extern const char *const boundary_names[];   /* NULL-terminated, enum order */

struct box {
    double lo[3], hi[3];
    enum boundary bc[3];
    double tilt[3];   /* xy xz yz, Å (0 0 0: orthogonal) */
};

static inline double box_length(const struct box *b, int d) { return b->hi[d] - b->lo[d]; }
static inline int box_tilted(const struct box *b)
{
    return b->tilt[0] != 0 || b->tilt[1] != 0 || b->tilt[2] != 0;
}
/* lx ly lz: the tilt does not change the volume of the cell */
double box_volume(const struct box *b);

/* The edge vectors as columns: h[row][col], col 0 = a, 1 = b, 2 = c. */
void box_cell_matrix(const struct box *b, double h[3][3]);
/* The width of the cell between the two faces that edge d crosses (the
 * faces spanned by the other two edges e, f): V / |a_e x a_f|; lz for
 * d = 2.  Equal to box_length for an orthogonal box. */
double box_height(const struct box *b, int d);
/* Fractional coordinates s of position x (s = H^-1 (x - lo)). */
void box_to_fractional(const struct box *b, const double x[3], double s[3]);
/* out = n0 a + n1 b + n2 c. */
void box_image_shift(const struct box *b, const int n[3], double out[3]);
/* The minimum image of a separation dx (in place) along the periodic axes:
 * reduced along z, then y, then x, as LAMMPS' Domain::minimum_image.  The
 * result is the shortest image for separations shorter than half of
 * min(lx, ly, lz), which is what its users ask (close atoms, samples two
 * cutoffs apart in boxes at least that large). */
void box_min_image(const struct box *b, double dx[3]);

/* The tilt LAMMPS accepts (read_data, "Triclinic box skew is too large"):
 * |xy| <= lx / 2, |xz| <= lx / 2, |yz| <= ly / 2 (a tilt of more is the same
 * lattice in a less skewed cell), and a tilted box periodic along all three
 * axes.  Returns 0, or -1 with the reason in why, naming the tilt factor
 * (or the boundary). */
int box_check_tilt(const struct box *b, char *why, size_t len);

/* Map owned particles back into periodic dimensions (updating image
 * counts), shrink-wrap free dimensions, and check fixed ones.  `margin` is
 * added around shrink-wrapped bounds.  Returns ERR_RUNTIME for a lost
 * particle.  A tilted box wraps the fractional coordinates into [0, 1). */
int box_remap(struct box *b, struct particles *p, double margin, struct err *e);

/* Unwrapped position of owned particle i: x + image . (a, b, c). */
void box_unwrap(const struct box *b, const struct particles *p, int i, double out[3]);

#endif
