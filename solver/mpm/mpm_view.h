/*
 * mpm_view: internal to solver/mpm -- one particle set (the material points
 * or an attached extra set) seen by the grid kernels, and the stencil
 * dispatch those kernels are specialised on.
 */
#ifndef CASCADE_MPM_VIEW_H
#define CASCADE_MPM_VIEW_H

#include "mpm/mpm.h"
#include "mpm/mpm_shape.h"
#include "mpm/mpm_simd.h"

#define mpm_v4_set(a, b, c, d) ((mpm_v4){(a), (b), (c), (d)})

struct mpm_view {
    long n;
    double *x, *v;
    const double *mass;
    const int *type;
    const double *type_mass;
    const double *stress, *vol;   /* s3a */
    const double *force;          /* s3b */
    double fscale;
    const int32_t *body;          /* material points: body of each point */
    double lp[3];
    int follow;
    struct mpm_bins *bins;
};

/* Views of every set: [0] the material points, then the extras. */
int mpm_views(struct mpm *m, struct mpm_view *views);

static inline double mpm_view_mass(const struct mpm_view *w, long p)
{
    return w->mass ? w->mass[p] : w->type_mass[w->type[p]];
}

static inline const double *mpm_view_lp(const struct mpm *m, const struct mpm_view *w, long p)
{
    return w->body ? m->body[w->body[p]].lp : w->lp;
}

enum { MPM_ST_LINEAR, MPM_ST_GIMP, MPM_ST_HIER };

static inline int mpm_stencil_kind(const struct mpm_grid *g)
{
    return g->kind == MPM_GRID_HIER ? MPM_ST_HIER
           : g->shape == MPM_SHAPE_GIMP ? MPM_ST_GIMP
                                        : MPM_ST_LINEAR;
}

/* Stencil of particle p of view w (kind is a constant in the callers, so
 * each kernel is compiled once per kind). */
static inline __attribute__((always_inline)) void
mpm_stencil_at(const struct mpm *m, const struct mpm_view *w, long p, int kind,
               struct mpm_stencil *s)
{
    const double *x = w->x + 3 * p;
    if (kind == MPM_ST_LINEAR)
        mpm_stencil_linear(&m->grid, x, s);
    else if (kind == MPM_ST_GIMP)
        mpm_stencil_gimp(&m->grid, x, mpm_view_lp(m, w, p), s);
    else
        mpm_stencil_hier(&m->grid, w->bins->cell[p], x, s);
}

#endif
