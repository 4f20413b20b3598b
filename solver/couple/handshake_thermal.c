/* handshake_thermal: the Langevin bath on region II and the thermal
 * bookkeeping of a handshake at a temperature (handshake_thermal.h). */
#include "couple/handshake_thermal.h"

#include <math.h>

#include "core/rng.h"
#include "core/units.h"
#include "couple/handshake.h"

/* Call sites of the counter-based stream (core/rng.h): beyond the ones it
 * lists, so that no other stream draws the same numbers. */
enum { HS_RNG_BATH = 40, HS_RNG_VELOCITY = 41 };

void hs_thermal_velocities(struct handshake *hs, double T, uint64_t seed, uint32_t none)
{
    struct particles *p = hs->md->p;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & none)
            continue;
        double s = sqrt(UNITS_KB * T / (p->mass[p->type[i]] * UNITS_MVV2E));
        uint64_t key = rng_key(seed, HS_RNG_VELOCITY, 0, (uint64_t)p->id[i], 0);
        for (int d = 0; d < 3; d++)
            p->v[3 * i + d] = s * rng_gaussian(key, (uint64_t)d);
    }
}

void hs_thermal_attach(struct handshake *hs, struct hs_thermal *t, double t_init)
{
    hs->thermal = t;
    struct md *md = hs->md;
    md->frozen_mask &= ~(uint32_t)HS_MASK_II;
    /* the copies start with their points' velocities plus thermal noise */
    hs_thermal_velocities(hs, t_init, t->seed, ~(uint32_t)HS_MASK_II);
    struct particles *p = md->p;
    const struct mpm_points *pt = &hs->mpm.pts;
    for (long k = 0; k < hs->nlink; k++) {
        int i = hs->link_md[k];
        if (!(p->mask[i] & HS_MASK_II))
            continue;
        for (int d = 0; d < 3; d++)
            p->v[3 * i + d] += pt->v[3 * hs->link_pt[k] + d];
    }
}

void hs_thermal_bath(struct handshake *hs)
{
    struct hs_thermal *t = hs->thermal;
    t->step++;
    if (!(t->damping_time > 0))
        return;
    struct particles *p = hs->md->p;
    const struct mpm_points *pt = &hs->mpm.pts;
    const double c = exp(-hs->md->dt / t->damping_time);
    const double kT = UNITS_KB * t->temperature;
    double heat = 0;
    for (long k = 0; k < hs->nlink; k++) {
        int i = hs->link_md[k];
        if (!(p->mask[i] & HS_MASK_II))
            continue;
        double m = p->mass[p->type[i]];
        double s = sqrt((1 - c * c) * kT / (m * UNITS_MVV2E));
        uint64_t key = rng_key(t->seed, HS_RNG_BATH, (uint64_t)t->step, (uint64_t)p->id[i], 0);
        const double *vp = pt->v + 3 * hs->link_pt[k];
        double *v = p->v + 3 * i;
        double before = 0, after = 0;
        for (int d = 0; d < 3; d++) {
            before += v[d] * v[d];
            v[d] = vp[d] + c * (v[d] - vp[d]) + s * rng_gaussian(key, (uint64_t)d);
            after += v[d] * v[d];
        }
        heat += 0.5 * m * UNITS_MVV2E * (before - after);
    }
    /* the material points of regions II and III: friction alone.  The MPM
     * carries the mean displacement field (its constants are those at T);
     * region I's instantaneous thermal stress and momentum drive the grid
     * at every step, and without a sink the grid's modes would heat
     * without bound (measured: 634 K after 20 ps without the bath).  Noise
     * on the points would not thermalise the grid either: a point keeps
     * its own velocity between steps (FLIP), so noise there is energy the
     * grid does not move with. */
    struct mpm_points *mp = &hs->mpm.pts;
    for (long q = 0; q < mp->n; q++) {
        if (!(mp->mask[q] & (HS_MASK_II | HS_MASK_III)))
            continue;
        double *v = mp->v + 3 * q;
        double before = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        for (int d = 0; d < 3; d++)
            v[d] *= c;
        heat += 0.5 * mp->mass[q] * UNITS_MVV2E * (1 - c * c) * before;
    }
    t->heat += heat;
}

void hs_thermal_group(const struct handshake *hs, uint32_t all, uint32_t none, double *ke,
                      double *temperature, long *count)
{
    const struct particles *p = hs->md->p;
    double sum = 0;
    long n = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if ((p->mask[i] & all) != all || (p->mask[i] & none))
            continue;
        const double *v = p->v + 3 * i;
        sum += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        n++;
    }
    double k = 0.5 * sum * UNITS_MVV2E;
    if (ke)
        *ke = k;
    if (temperature)
        *temperature = n > 0 ? 2 * k / (3.0 * n * UNITS_KB) : 0;
    if (count)
        *count = n;
}
