/*
 * dpd_pair: what the pair sweep and the pair-force export share -- the
 * weight function, the pair's random-number key, rigid-body lookup and the
 * DPDE pair temperature.  Internal to solver/dpd.
 */
#ifndef CASCADE_DPD_PAIR_H
#define CASCADE_DPD_PAIR_H

#include <gsl/gsl_cdf.h>
#include <stdint.h>

#include "core/rng.h"
#include "core/units.h"
#include "dpd/dpd.h"

/* w^R(r) = 1 - r / r_d (Groot & Warren 1997); w^D = (w^R)^2. */
static inline double dpd_wr(double r, double rd) { return r < rd ? 1.0 - r / rd : 0.0; }

/* Body index of particle i (owned or ghost: ghosts carry their owner's
 * mask), or -1 for a free particle. */
static inline int dpd_body_of(const struct dpd *d, int i)
{
    uint32_t m = d->p->mask[i];
    for (int b = 0; b < d->nbodies; b++)
        if (m & d->body[b].mask)
            return b;
    return -1;
}

/* The pair's standard normal number: one uniform of the counter-based
 * stream through the inverse normal CDF (GSL's, Wichura's AS 241) --
 * cheaper than Box-Muller, which spends a log, a sqrt and a cos on it. */
static inline double dpd_normal(uint64_t key) { return gsl_cdf_ugaussian_Pinv(rng_uniform(key, 0)); }

/* Key of the physical pair (owned i, neighbour j): the two ids in
 * increasing order and which periodic copy of the higher-id particle the
 * pair joins, counted from the unwrapped positions: x_j - x_i = u_j - u_i
 * + (gshift_j - image_j + image_i) L.  The key does not change when a
 * particle is wrapped back into the box, both orientations of a pair share
 * it, and different images of one pair never do. */
static inline uint64_t dpd_pair_key(const struct dpd *d, int site, int i, int j)
{
    const struct particles *p = d->p;
    int oj = p->origin[j];
    int64_t a = p->id[i], b = p->id[oj];
    int s[3];
    for (int k = 0; k < 3; k++)
        s[k] = p->gshift[3 * j + k] - p->image[3 * oj + k] + p->image[3 * i + k];
    if (a > b) {
        int64_t t = a;
        a = b;
        b = t;
        for (int k = 0; k < 3; k++)
            s[k] = -s[k];
    }
    uint64_t code = 0;
    for (int k = 0; k < 3; k++)
        code = (code << 10) | (uint64_t)((s[k] + 512) & 1023);
    return rng_key(d->seed, (uint64_t)site, (uint64_t)d->step, (uint64_t)a,
                   ((uint64_t)b << 30) ^ code);
}

/* The same key for a pair of any two local copies a and b (owned or
 * ghost, as the cell-coloured sweep meets them: dpd_sweep_cells.c): the
 * periodic copy is counted from both ends, (gshift_b - image_b) -
 * (gshift_a - image_a), which is dpd_pair_key's count when a is owned
 * (gshift 0; a ghost carries its owner's image counts). */
static inline int dpd_copy_shift(const struct particles *p, int i, int k)
{
    /* an owned particle is its own copy; its slot's gshift may be a stale
     * ghost's (a checkpoint read refills the slots) */
    return i < p->n_owned ? 0 : p->gshift[3 * i + k];
}

static inline uint64_t dpd_pair_key_ab(const struct dpd *d, int site, int a, int b)
{
    const struct particles *p = d->p;
    int64_t ia = p->id[a], ib = p->id[b];
    int s[3];
    for (int k = 0; k < 3; k++)
        s[k] = (dpd_copy_shift(p, b, k) - p->image[3 * b + k]) -
               (dpd_copy_shift(p, a, k) - p->image[3 * a + k]);
    if (ia > ib) {
        int64_t t = ia;
        ia = ib;
        ib = t;
        for (int k = 0; k < 3; k++)
            s[k] = -s[k];
    }
    uint64_t code = 0;
    for (int k = 0; k < 3; k++)
        code = (code << 10) | (uint64_t)((s[k] + 512) & 1023);
    return rng_key(d->seed, (uint64_t)site, (uint64_t)d->step, (uint64_t)ia,
                   ((uint64_t)ib << 30) ^ code);
}

/* DPDE: 1 / Theta_ij = (1/theta_i + 1/theta_j) / 2, theta = u / (C_v kB). */
static inline double dpd_pair_temperature(const struct dpd *d, const double *u, int oi, int oj)
{
    if (d->set.variant != DPD_ENERGY)
        return d->set.temperature;
    double cv = d->set.heat_capacity * UNITS_KB;
    double ti = u[oi] / cv, tj = u[oj] / cv;
    if (!(ti > 0) || !(tj > 0))
        return 0;
    return 2.0 / (1.0 / ti + 1.0 / tj);
}

/* The pair sweep of one step (dpd_sweep.c): pairs in neighbour-list order. */
int dpd_sweep(struct dpd *d, struct err *e);
/* The pair sweep in cell-colour order (dpd_sweep_cells.c): the same result
 * on any number of bricks. */
int dpd_sweep_cells(struct dpd *d, struct err *e);


/* The conservative kernel at the current positions, ghosts and list
 * (dpd_conservative.c): p->f, d->epot, d->virial, per-particle pe/virial
 * when d->peratom, ghost contributions added to their owners. */
int dpd_conservative(struct dpd *d, struct err *e);

#endif
