/*
 * frame: one configuration of particles prepared for analysis -- owned
 * positions wrapped into the periodic box, periodic images within a range,
 * link cells, and full neighbour lists within a radius, each sorted by
 * distance (ties by owned index, then image shift).
 *
 * It takes plain positions and a box, not a model, so any particle set
 * (atoms, DPD mesoparticles, material points) can be analysed, and it never
 * touches the ghosts a force model keeps.
 *
 * Pair vectors are formed from the two OWNED positions and the integer
 * image shift, d = (x_o - x_i) + s L, never from a stored image position.
 * IEEE rounding is sign-symmetric, so the pair seen from either end has
 * bit-identical length: a pair lying at the cutoff to within round-off is a
 * neighbour of both atoms or of neither.  The neighbour relation is
 * symmetric, and whatever is built on it (common-neighbour signatures,
 * clusters) does not depend on which atom is looked at, on the thread count
 * or on where the periodic boundary cuts the crystal.  "Within" means
 * strictly: r^2 < radius^2.
 */
#ifndef CASCADE_FRAME_H
#define CASCADE_FRAME_H

#include "core/box.h"
#include "util/err.h"

struct frame {
    int n;               /* owned particles */
    int ntot;            /* owned + images */
    int cap;
    double *x;           /* 3 * ntot: wrapped owned positions, then images */
    int *origin;         /* owned index of each entry */
    int *shift;          /* 3 * ntot: image shift in box lengths */
    double len[3];       /* box lengths of periodic axes (0 otherwise) */
    /* link cells over all entries, at least the neighbour radius wide; the
     * entries in cell order with their owned position and shift (x L) side
     * by side, so a cell's candidates are contiguous in memory */
    int nc[3];
    double clo[3], cinv[3];
    int *cell_start, *cell_sorted;
    double *cell_x, *cell_s;   /* 3 per sorted entry; cell_s only with a periodic
                                  axis (without, every shift is zero: the analysis
                                  of a brick and its ghosts) */
    int periodic;              /* some axis periodic (len[d] > 0) */
    long cap_cells;
    int cap_sorted, cap_shifts;
    double range;        /* Å: images and cells cover this distance (frame_query) */
    /* neighbour lists of the owned particles */
    double radius;       /* Å */
    int *offset;         /* n + 1 */
    int *nbr;            /* entry indices, nearest first; the squared distance of
                          * entry k of i's list is frame_dist2(f, i, nbr[k]), the
                          * bits the list was sorted by (not stored: 8 bytes a
                          * neighbour, some 18 neighbours an atom) */
    long cap_nbr;
    int cap_offset;
    int nthreads;
};

/* Build from n owned positions x (3 per particle) in box b: images within
 * `range` (>= radius) of the box on periodic axes, cells at least `radius`
 * wide, neighbour lists within `radius`.  The arrays are reused by the
 * next build. */
int frame_build(struct frame *f, const double *x, int n, const struct box *b, double radius,
                double range, int nthreads, struct err *e);
void frame_free(struct frame *f);

/* Vector from entry a to entry b (owned or image), from owned positions
 * and shifts as described above. */
static inline void frame_vec(const struct frame *f, int a, int b, double d[3])
{
    int oa = f->origin[a], ob = f->origin[b];
    for (int k = 0; k < 3; k++)
        d[k] = (f->x[3 * ob + k] - f->x[3 * oa + k]) +
               (double)(f->shift[3 * b + k] - f->shift[3 * a + k]) * f->len[k];
}

static inline double frame_dist2(const struct frame *f, int a, int b)
{
    double d[3];
    frame_vec(f, a, b, d);
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

/* Call fn(ctx, entry, r2) for every entry within `radius` (<= the build
 * range) of owned particle i, i itself excluded, in no particular order. */
void frame_query(const struct frame *f, int i, double radius,
                 void (*fn)(void *ctx, int entry, double r2), void *ctx);

#endif
