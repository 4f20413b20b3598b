/*
 * mpm_shape: shape functions N_i and their gradients G_i at a point, as a
 * stencil (node indices, weights, gradients) -- Chen 2014, Eq. (s1)-(s12).
 *
 *   linear   the papers' 8-node trilinear functions on a uniform grid
 *   GIMP     uniform GIMP (Bardenhagen & Kober 2004): the linear functions
 *            convolved with the point's box of half-width lp, smooth across
 *            cell faces; 3 nodes per direction
 *   hierarchical cells: the trilinear functions plus midpoint "bubbles" for
 *            hanging nodes, with |.| in place of squared terms
 *            (Guo & Yang 2005, Eq. (11)); see mpm_stencil_hier.
 *
 * The stencil is recomputed in every pass from the point's position at the
 * start of the step (a few dozen flops for linear), which costs less memory
 * traffic than storing 8 weights and 24 gradients per point.
 */
#ifndef CASCADE_MPM_SHAPE_H
#define CASCADE_MPM_SHAPE_H

#include <math.h>
#include <stdint.h>

#include "mpm/mpm_grid.h"
#include "mpm/mpm_hgrid.h"

#define MPM_STENCIL_MAX 27

struct mpm_stencil {
    int n;
    int32_t node[MPM_STENCIL_MAX];
    double w[MPM_STENCIL_MAX];
    double gx[MPM_STENCIL_MAX], gy[MPM_STENCIL_MAX], gz[MPM_STENCIL_MAX];   /* 1/Å */
};

/* Patch-local node coordinate of x along d. */
static inline double mpm_grid_u(const struct mpm_grid *g, const double *x, int d)
{
    return (x[d] - g->origin[d]) * g->inv_hd[d] - (double)g->lo[d];
}

/* Linear shape functions on a uniform grid: 8 nodes of the cell holding x. */
static inline void mpm_stencil_linear(const struct mpm_grid *g, const double *x,
                                      struct mpm_stencil *s)
{
    double w[3][2], dw[3][2];
    long base = 0;
    for (int d = 0; d < 3; d++) {
        double u = mpm_grid_u(g, x, d);
        long i = (long)floor(u);
        double f = u - (double)i;
        w[d][0] = 1.0 - f;
        w[d][1] = f;
        dw[d][0] = -g->inv_hd[d];
        dw[d][1] = g->inv_hd[d];
        base += (i + g->halo) * g->stride[d];
    }
    int k = 0;
    for (int c = 0; c < 2; c++)
        for (int b = 0; b < 2; b++) {
            double wyz = w[1][b] * w[2][c];
            double gy = dw[1][b] * w[2][c], gz = w[1][b] * dw[2][c];
            for (int a = 0; a < 2; a++, k++) {
                s->node[k] = (int32_t)(base + a + b * g->stride[1] + c * g->stride[2]);
                s->w[k] = w[0][a] * wyz;
                s->gx[k] = dw[0][a] * wyz;
                s->gy[k] = w[0][a] * gy;
                s->gz[k] = w[0][a] * gz;
            }
        }
    s->n = 8;
}

/* 1-D uGIMP weight and derivative (per unit of d) for node distance d
 * (in cells) and half-width lp (in cells, 0 < lp <= 0.5). */
static inline void mpm_gimp_1d(double d, double lp, double *S, double *dS)
{
    double ad = fabs(d), sg = d < 0 ? -1.0 : 1.0;
    if (ad < lp) {
        *S = 1.0 - (d * d + lp * lp) / (2.0 * lp);
        *dS = -d / lp;
    } else if (ad < 1.0 - lp) {
        *S = 1.0 - ad;
        *dS = -sg;
    } else if (ad < 1.0 + lp) {
        double t = 1.0 + lp - ad;
        *S = t * t / (4.0 * lp);
        *dS = -sg * t / (2.0 * lp);
    } else {
        *S = 0.0;
        *dS = 0.0;
    }
}

/* First of the three nodes a GIMP point at node coordinate u touches. */
static inline long mpm_gimp_base(double u, double lp)
{
    return (long)floor(u - 1.0 - lp) + 1;
}

/* uGIMP on a uniform grid: 27 nodes (some weights may be zero). */
static inline void mpm_stencil_gimp(const struct mpm_grid *g, const double *x, const double lp[3],
                                    struct mpm_stencil *s)
{
    double w[3][3], dw[3][3];
    long base = 0;
    for (int d = 0; d < 3; d++) {
        double u = mpm_grid_u(g, x, d);
        long b = mpm_gimp_base(u, lp[d]);
        for (int a = 0; a < 3; a++) {
            mpm_gimp_1d(u - (double)(b + a), lp[d], &w[d][a], &dw[d][a]);
            dw[d][a] *= g->inv_hd[d];
        }
        base += (b + g->halo) * g->stride[d];
    }
    int k = 0;
    for (int c = 0; c < 3; c++)
        for (int b = 0; b < 3; b++) {
            double wyz = w[1][b] * w[2][c];
            double gy = dw[1][b] * w[2][c], gz = w[1][b] * dw[2][c];
            for (int a = 0; a < 3; a++, k++) {
                s->node[k] = (int32_t)(base + a + b * g->stride[1] + c * g->stride[2]);
                s->w[k] = w[0][a] * wyz;
                s->gx[k] = dw[0][a] * wyz;
                s->gy[k] = w[0][a] * gy;
                s->gz[k] = w[0][a] * gz;
            }
        }
    s->n = 27;
}

/* Shape functions on cell `c` of a hierarchical grid (mpm_shape.c). */
void mpm_stencil_hier(const struct mpm_grid *g, long c, const double *x, struct mpm_stencil *s);

#endif
