/* ghost: creation and refresh of periodic-image ghost particles. */
#include "core/ghost.h"

#include "core/halo.h"
#include "core/parallel.h"

#include <limits.h>
#include <math.h>
#include <string.h>

static int add_image(struct particles *p, int src, int d, int shift, double len, struct err *e)
{
    int n = p->n_owned + p->n_ghost;
    if (particles_reserve(p, n + 1, e) != 0)
        return -1;
    particles_copy_one(p, n, src);
    p->x[3 * n + d] += shift * len;
    p->origin[n] = p->origin[src];
    p->gshift[3 * n + d] = p->gshift[3 * src + d] + shift;
    p->n_ghost++;
    return 0;
}

/* The image of particle src shifted by `shift` edges d of a tilted cell:
 * the edge vector moves up to all three coordinates. */
static int add_image_tilted(struct particles *p, int src, int d, int shift, const struct box *b,
                            struct err *e)
{
    int n = p->n_owned + p->n_ghost;
    if (particles_reserve(p, n + 1, e) != 0)
        return -1;
    particles_copy_one(p, n, src);
    p->origin[n] = p->origin[src];
    p->gshift[3 * n + d] = p->gshift[3 * src + d] + shift;
    /* from the owner, as ghost_update_positions computes it (one rounding) */
    double sh[3];
    box_image_shift(b, p->gshift + 3 * n, sh);
    for (int c = 0; c < 3; c++)
        p->x[3 * n + c] = p->x[3 * p->origin[n] + c] + sh[c];
    p->n_ghost++;
    return 0;
}

double ghost_estimate(const struct box *b, long n, double range)
{
    double f = 1;
    for (int d = 0; d < 3; d++)
        if (b->bc[d] == BOUNDARY_PERIODIC)
            f *= 1 + 2 * range / box_height(b, d);
    return (double)n * (f - 1);
}

/* Ghosts of a tilted cell, made as LAMMPS does in lamda coordinates: along
 * each edge d (a, then b, then c: images of the earlier edges' ghosts too)
 * the images whose fractional coordinate s_d lies within range / h_d of
 * [0, 1), h_d the cell's height across the faces that edge crosses
 * (box_height).  A point within `range` of the cell differs from some point
 * of the cell by at most range / h_d in s_d, so every pair within range is
 * found; the shift changes only s_d, so the three passes compose.  The
 * neighbour list then bins the owned and ghost positions in Cartesian
 * space as for an orthogonal box (core/neighbor.h): only the ghosts know
 * about the tilt. */
static int ghost_build_tilted(struct particles *p, const struct box *b, double range,
                              struct err *e)
{
    for (int d = 0; d < 3; d++) {
        double height = box_height(b, d), rf = range / height;
        if (!(rf <= 100.0))
            return err_set(e, ERR_INPUT, "the periodic tilted box is %g Å high across its %c "
                           "faces, less than a hundredth of the interaction range %g Å", height,
                           "abc"[d], range);
        int nlayers = (int)ceil(rf);
        int nsrc = p->n_owned + p->n_ghost;
        for (int s = 1; s <= nlayers; s++) {
            for (int i = 0; i < nsrc; i++) {
                double f[3];
                box_to_fractional(b, p->x + 3 * i, f);
                if (f[d] + s < 1.0 + rf && add_image_tilted(p, i, d, s, b, e))
                    return ERR_RUNTIME;
                if (f[d] - s >= -rf && add_image_tilted(p, i, d, -s, b, e))
                    return ERR_RUNTIME;
            }
        }
    }
    return 0;
}

int ghost_build(struct particles *p, const struct box *b, double range, struct err *e)
{
    double est = ghost_estimate(b, p->n_owned, range);
    if (!(est < INT_MAX / 2 - (double)p->n_owned))
        return err_set(e, ERR_INPUT,
                       "an interaction range of %g Å needs about %.3g periodic images of the %d "
                       "particles in the %g x %g x %g Å box, more than particle indices hold",
                       range, est, p->n_owned, box_length(b, 0), box_length(b, 1),
                       box_length(b, 2));
    p->n_ghost = 0;
    for (int i = 0; i < p->n_owned; i++) {
        p->origin[i] = i;
        p->gshift[3 * i] = p->gshift[3 * i + 1] = p->gshift[3 * i + 2] = 0;
    }
    if (box_tilted(b))
        return ghost_build_tilted(p, b, range, e);
    for (int d = 0; d < 3; d++) {
        if (b->bc[d] != BOUNDARY_PERIODIC)
            continue;
        double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
        /* a box a hundred times shorter than the range is a broken input
         * (a data file's box of 1e-300 Å): its layer count overflowed the
         * int, and a million layers would not fit in memory either */
        if (!(range / len <= 100.0))
            return err_set(e, ERR_INPUT, "the periodic box is %g Å long along %c, less than "
                           "a hundredth of the interaction range %g Å", len, "xyz"[d], range);
        int nlayers = (int)ceil(range / len);
        int nsrc = p->n_owned + p->n_ghost;   /* images of ghosts of earlier axes too */
        for (int s = 1; s <= nlayers; s++) {
            for (int i = 0; i < nsrc; i++) {
                double x = p->x[3 * i + d];
                /* image shifted by +s*len lands above hi: keep if within range */
                if (x + s * len < hi + range && add_image(p, i, d, s, len, e))
                    return ERR_RUNTIME;
                if (x - s * len >= lo - range && add_image(p, i, d, -s, len, e))
                    return ERR_RUNTIME;
            }
        }
    }
    return 0;
}

void ghost_update_positions(struct particles *p, const struct box *b)
{
    if (p->halo) {   /* the buffers were sized at the build: cannot fail */
        (void)halo_update_positions(p->halo, p);
        return;
    }
    double len[3] = {box_length(b, 0), box_length(b, 1), box_length(b, 2)};
    int n0 = p->n_owned, n1 = p->n_owned + p->n_ghost;
    if (box_tilted(b)) {
        for (int g = n0; g < n1; g++) {
            int o = p->origin[g];
            double sh[3];
            box_image_shift(b, p->gshift + 3 * g, sh);
            for (int d = 0; d < 3; d++)
                p->x[3 * g + d] = p->x[3 * o + d] + sh[d];
        }
    } else {
        for (int g = n0; g < n1; g++) {
            int o = p->origin[g];
            for (int d = 0; d < 3; d++)
                p->x[3 * g + d] = p->x[3 * o + d] + p->gshift[3 * g + d] * len[d];
        }
    }
    for (int k = 0; k < p->nfields; k++)
        if (p->fields[k].ghost_copy)
            ghost_forward(p, p->fields[k].data, p->fields[k].ncomp);
}

void ghost_update_velocities(struct particles *p) { ghost_forward(p, p->v, 3); }

void ghost_reverse_add(const struct particles *p, double *arr, int ncomp)
{
    if (p->halo) {
        (void)halo_reverse_add(p->halo, p, arr, ncomp);
        return;
    }
    int n0 = p->n_owned, n1 = p->n_owned + p->n_ghost;
    parallel_sum(p->par, arr, (size_t)ncomp * n1);
    for (int g = n0; g < n1; g++) {
        int o = p->origin[g];
        for (int c = 0; c < ncomp; c++)
            arr[(size_t)ncomp * o + c] += arr[(size_t)ncomp * g + c];
    }
}

void ghost_forward(const struct particles *p, double *arr, int ncomp)
{
    if (p->halo) {
        (void)halo_forward(p->halo, p, arr, ncomp);
        return;
    }
    int n0 = p->n_owned, n1 = p->n_owned + p->n_ghost;
    for (int g = n0; g < n1; g++) {
        int o = p->origin[g];
        memcpy(arr + (size_t)ncomp * g, arr + (size_t)ncomp * o, (size_t)ncomp * sizeof(double));
    }
}
