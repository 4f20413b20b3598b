/*
 * dpd_pair: what the pair sweep and the pair-force export share -- the
 * weight function, the pair's random-number key, rigid-body lookup and the
 * DPDE pair temperature.  Internal to solver/dpd.
 */
#ifndef CASCADE_DPD_PAIR_H
#define CASCADE_DPD_PAIR_H

#include <stdint.h>

#include "core/rng.h"
#include "core/units.h"
#include "dpd/dpd.h"
#include "dpd/dpd_normal.h"

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
 * stream through the inverse normal CDF (Wichura's AS 241, dpd_normal.h,
 * the same numbers as GSL's) -- cheaper than Box-Muller, which spends a
 * log, a sqrt and a cos on it. */
static inline double dpd_normal(uint64_t key) { return dpd_normal_of_uniform(rng_uniform(key, 0)); }

/* The (seed, site, step) part of every pair key of this step. */
static inline uint64_t dpd_key_prefix(const struct dpd *d, int site)
{
    return rng_key_prefix(d->seed, (uint64_t)site, (uint64_t)d->step);
}

/* The pair part of the key: ids a, b and the periodic-copy counts s of
 * b's copy seen from a's; both orientations give the same key (the lower
 * id first, the counts negated with the swap), without a branch. */
static inline uint64_t dpd_key_ids(uint64_t prefix, int64_t a, int64_t b, int s0, int s1, int s2)
{
    const int flip = a > b;
    const int64_t lo = flip ? b : a, hi = flip ? a : b;
    const int sg = flip ? -1 : 1;
    uint64_t code = (uint64_t)((sg * s0 + 512) & 1023) << 20 |
                    (uint64_t)((sg * s1 + 512) & 1023) << 10 | (uint64_t)((sg * s2 + 512) & 1023);
    return rng_key_from(prefix, (uint64_t)lo, ((uint64_t)hi << 30) ^ code);
}

/* Key of the physical pair (owned i, neighbour j): the two ids in
 * increasing order and which periodic copy of the higher-id particle the
 * pair joins, counted from the unwrapped positions: x_j - x_i = u_j - u_i
 * + (gshift_j - image_j + image_i) L.  The key does not change when a
 * particle is wrapped back into the box, both orientations of a pair share
 * it, and different images of one pair never do. */
static inline uint64_t dpd_pair_key_pre(const struct particles *p, uint64_t prefix, int i, int j)
{
    int oj = p->origin[j];
    int s[3];
    for (int k = 0; k < 3; k++)
        s[k] = p->gshift[3 * j + k] - p->image[3 * oj + k] + p->image[3 * i + k];
    return dpd_key_ids(prefix, p->id[i], p->id[oj], s[0], s[1], s[2]);
}

static inline uint64_t dpd_pair_key(const struct dpd *d, int site, int i, int j)
{
    return dpd_pair_key_pre(d->p, dpd_key_prefix(d, site), i, j);
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

static inline uint64_t dpd_pair_key_ab_pre(const struct particles *p, uint64_t prefix, int a, int b)
{
    int s[3];
    for (int k = 0; k < 3; k++)
        s[k] = (dpd_copy_shift(p, b, k) - p->image[3 * b + k]) -
               (dpd_copy_shift(p, a, k) - p->image[3 * a + k]);
    return dpd_key_ids(prefix, p->id[a], p->id[b], s[0], s[1], s[2]);
}

static inline uint64_t dpd_pair_key_ab(const struct dpd *d, int site, int a, int b)
{
    return dpd_pair_key_ab_pre(d->p, dpd_key_prefix(d, site), a, b);
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

/* The vector kernels of dpd_conservative_fast.c, for runs without passive
 * partners or per-particle energies and with integer exponents
 * (dpd_conservative_fast_ok): the density pass (returns the embedding
 * energy, F' sent to the ghosts; *rc an error code) and the force pass
 * (forces into the threads' targets of d->acc_f, not yet reduced). */
int dpd_conservative_fast_ok(const struct dpd *d);
double dpd_density_fast(struct dpd *d, int nt, struct err *e, int *rc);
void dpd_force_fast(struct dpd *d, int nt, double *epot, double virial[6]);

#endif
