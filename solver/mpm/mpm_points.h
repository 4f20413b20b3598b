/*
 * mpm_points: material points as a structure of arrays.
 *
 * A material point carries a fixed mass (so mass is conserved exactly,
 * Guo & Yang 2005 Eq. (1)), its initial and current volume, position,
 * velocity, Cauchy stress, deformation gradient (its strain: see
 * mpm_points_strain), the stress work done on it (its strain energy), state
 * variables of its constitutive law, and the body it belongs to.  All arrays are owned here
 * and allocated in bulk; nothing is allocated per point.
 *
 * Units are metal: Å, Å/ps, amu, Å^3, eV/Å^3, eV.  Tensors with 6
 * components are stored xx yy zz xy xz yz (tensor, not engineering, shear);
 * F is stored row-major (F[3*a + b] = F_ab).
 *
 * Points are reordered (mpm_points_permute) to follow the grid blocks, so a
 * point's index changes; its `id` does not.
 */
#ifndef CASCADE_MPM_POINTS_H
#define CASCADE_MPM_POINTS_H

#include <stdint.h>

#include "util/err.h"

struct mpm_points {
    long n, cap;
    int nstate;         /* state variables per point (max over the materials) */

    double *x;          /* 3: position                                        */
    double *x0;         /* 3: initial position (displacement u = x - x0, s9)   */
    double *v;          /* 3: velocity                                         */
    double *mass;       /* 1: mass (amu), constant                             */
    double *vol0;       /* 1: initial volume                                   */
    double *vol;        /* 1: current volume = vol0 det F                      */
    double *stress;     /* 6: Cauchy stress                                    */
    double *F;          /* 9: deformation gradient                             */
    double *eint;       /* 1: stress work done on the point (eV)               */
    double *state;      /* nstate: constitutive state (e.g. plastic strain)    */
    double *fext;       /* 3: external force (eV/Å), NULL until a load needs it */
    int32_t *body;      /* 1: body index                                       */
    int64_t *id;        /* 1: global id, 1-based, stable                       */
    uint32_t *mask;     /* 1: group bits for couplings and analysis            */
};

/* An empty set whose points have `nstate` state variables. */
int mpm_points_init(struct mpm_points *p, int nstate, struct err *e);
void mpm_points_free(struct mpm_points *p);

int mpm_points_reserve(struct mpm_points *p, long n, struct err *e);

/* Append a point at x with velocity v, mass and volume (metal units), at
 * zero stress, F = I; returns its index or -1 (out of memory). */
long mpm_points_add(struct mpm_points *p, const double x[3], const double v[3], double mass,
                    double vol, int body, int64_t id, struct err *e);

/* Allocate the external-force array (zeroed) if it is not there yet. */
int mpm_points_enable_fext(struct mpm_points *p, struct err *e);

/* Reorder: new index k holds old index perm[k].  `tmp` is scratch of at
 * least n doubles (the reorder goes one component at a time so that its
 * memory overhead is one array, not a second copy of the set; when at most
 * a quarter of the points move, as in a periodic reorder, it follows the
 * permutation's cycles instead and touches the moved points only). */
void mpm_points_permute(struct mpm_points *p, const int32_t *perm, double *tmp, int nthreads);

/* Logarithmic (Hencky) strain of point i, ln V with F = V R:
 * 1/2 ln(F F^T) as xx yy zz xy xz yz.  It is what summing the strain
 * increments sym(L) dt (Chen 2014, Eq. (s13)) gives along a path without
 * rotation, and unlike that sum it is objective. */
void mpm_points_strain(const struct mpm_points *p, long i, double eps[6]);

/* Bytes held per point (all arrays), for memory reports. */
double mpm_points_bytes_per_point(const struct mpm_points *p);

#endif
