/* handshake_thermal: the Langevin bath on region II and the thermal
 * bookkeeping of a handshake at a temperature (handshake_thermal.h). */
#include "couple/handshake_thermal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "core/halo.h"
#include "core/rng.h"
#include "core/units.h"
#include "couple/handshake.h"
#include "couple/handshake_bricks.h"

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
    for (long k = 0; k < hs->nlink; k++) {
        int i = hs->link_md[k];
        if (!(p->mask[i] & HS_MASK_II))
            continue;
        const double *row = hs->link_row + HS_LINK_ROW * k;   /* the point's velocity */
        for (int d = 0; d < 3; d++)
            p->v[3 * i + d] += row[3 + d];
    }
}

/* One node of the coarse grid: mass and momentum. */
struct coarse_node {
    double m, p[3];
};

/* Cell and linear weights of x on the coarse grid (origin lo, cell H, n
 * nodes per axis); positions beyond the grid are clamped to its edge. */
static void coarse_stencil(const double lo[3], double H, const long n[3], const double x[3],
                           long cell[3], double w[3])
{
    for (int d = 0; d < 3; d++) {
        double s = (x[d] - lo[d]) / H;
        long c = (long)floor(s);
        if (c < 0)
            c = 0;
        if (c > n[d] - 2)
            c = n[d] - 2;
        w[d] = fmin(1.0, fmax(0.0, s - (double)c));
        cell[d] = c;
    }
}

static void coarse_deposit(struct coarse_node *g, const long n[3], const long cell[3],
                           const double w[3], double m, const double v[3])
{
    for (int k = 0; k < 8; k++) {
        double wk = 1;
        long idx = 0;
        for (int d = 2; d >= 0; d--) {
            int o = (k >> d) & 1;
            wk *= o ? w[d] : 1 - w[d];
            idx = idx * n[d] + cell[d] + o;
        }
        struct coarse_node *nd = g + idx;
        nd->m += wk * m;
        for (int d = 0; d < 3; d++)
            nd->p[d] += wk * m * v[d];
    }
}

int hs_thermal_coarse_velocity(const struct handshake *hs, double H, double **out, struct err *e)
{
    const struct handshake_layout *L = &hs->lay;
    const struct mpm_points *mp = &hs->mpm.pts;
    const struct particles *p = hs->md->p;
    long n[3];
    size_t nn = 1;
    for (int d = 0; d < 3; d++) {
        n[d] = (long)ceil((L->dom_hi[d] - L->dom_lo[d]) / H - 1e-9) + 1;
        if (n[d] < 2)
            n[d] = 2;
        nn *= (size_t)n[d];
    }
    struct coarse_node *g = calloc(nn, sizeof *g);
    double *vs = malloc((size_t)(mp->n > 0 ? mp->n : 1) * 3 * sizeof *vs);
    if (!g || !vs) {
        free(g);
        free(vs);
        return err_nomem(e, "handshake bath: coarse grid");
    }
    long cell[3];
    double w[3];
    /* the projection: every material point and every region I atom (the
     * MD side of the band, whose coarse motion the band continues) */
    for (long q = 0; q < mp->n; q++) {
        coarse_stencil(L->dom_lo, H, n, mp->x + 3 * q, cell, w);
        coarse_deposit(g, n, cell, w, mp->mass[q], mp->v + 3 * q);
    }
    for (long k = 0; k < hs->nI; k++) {
        int i = hs->idxI[k];
        double x[3] = {p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]};
        handshake_wrap(hs, x);
        coarse_stencil(L->dom_lo, H, n, x, cell, w);
        coarse_deposit(g, n, cell, w, p->mass[p->type[i]], p->v + 3 * i);
    }
    /* bricks: each rank deposited its own points and region I atoms; the
     * coarse nodes summed over the ranks (4 doubles a node, contiguous) */
    if (hs->md->halo) {
        if (nn * 4 > (size_t)INT_MAX) {
            free(g);
            free(vs);
            return err_set(e, ERR_RUNTIME, "handshake bath: %zu coarse nodes are too many to "
                                           "sum over the ranks",
                           nn);
        }
        _Static_assert(sizeof(struct coarse_node) == 4 * sizeof(double), "coarse node layout");
        halo_sum(hs->md->halo, (double *)g, (int)(nn * 4));
    }
    /* the coarse field at the band's points */
    for (long q = 0; q < mp->n; q++) {
        double *o = vs + 3 * q;
        o[0] = o[1] = o[2] = 0;
        if (!(mp->mask[q] & (HS_MASK_II | HS_MASK_III)))
            continue;
        coarse_stencil(L->dom_lo, H, n, mp->x + 3 * q, cell, w);
        for (int k = 0; k < 8; k++) {
            double wk = 1;
            long idx = 0;
            for (int d = 2; d >= 0; d--) {
                int off = (k >> d) & 1;
                wk *= off ? w[d] : 1 - w[d];
                idx = idx * n[d] + cell[d] + off;
            }
            const struct coarse_node *nd = g + idx;
            if (nd->m > 0)
                for (int d = 0; d < 3; d++)
                    o[d] += wk * nd->p[d] / nd->m;
        }
    }
    free(g);
    *out = vs;
    return 0;
}

int hs_thermal_bath(struct handshake *hs, struct err *e)
{
    struct hs_thermal *t = hs->thermal;
    t->step++;
    if (!(t->damping_time > 0))
        return 0;
    struct particles *p = hs->md->p;
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
        const double *vp = hs->link_row + HS_LINK_ROW * k + 3;   /* its point's */
        double *v = p->v + 3 * i;
        double before = 0, after = 0;
        for (int d = 0; d < 3; d++) {
            before += v[d] * v[d];
            v[d] = vp[d] + c * (v[d] - vp[d]) + s * rng_gaussian(key, (uint64_t)d);
            after += v[d] * v[d];
        }
        heat += 0.5 * m * UNITS_MVV2E * (before - after);
    }
    /* bricks: each rank's copies (and below each rank's points) */
    if (hs->md->halo)
        halo_sum(hs->md->halo, &heat, 1);
    t->heat_copies += heat;
    double heat_points = 0;
    /* the material points of regions II and III: friction on their motion
     * relative to the coarse field (hs_thermal_coarse_velocity), not on
     * the coarse waves themselves.  The MPM carries the mean displacement
     * field (its constants are those at T); region I's instantaneous
     * thermal stress and momentum drive the grid at every step, mostly at
     * the shortest wavelengths the finest cells hold, and without a sink
     * those grid modes would heat without bound (measured: 634 K after 20
     * ps without the bath).  Noise on the points would not thermalise the
     * grid either: a point keeps its own velocity between steps (FLIP), so
     * noise there is energy the grid does not move with. */
    struct mpm_points *mp = &hs->mpm.pts;
    double *vs = NULL;
    if (t->coarse_cell > 0) {
        int rc = hs_thermal_coarse_velocity(hs, t->coarse_cell * hs->lay.a, &vs, e);
        if (rc)
            return rc;
    }
    for (long q = 0; q < mp->n; q++) {
        if (!(mp->mask[q] & (HS_MASK_II | HS_MASK_III)))
            continue;
        double *v = mp->v + 3 * q;
        const double zero[3] = {0, 0, 0}, *ref = vs ? vs + 3 * q : zero;
        double before = 0, after = 0;
        for (int d = 0; d < 3; d++) {
            before += v[d] * v[d];
            v[d] = ref[d] + c * (v[d] - ref[d]);
            after += v[d] * v[d];
        }
        heat_points += 0.5 * mp->mass[q] * UNITS_MVV2E * (before - after);
    }
    free(vs);
    if (hs->md->halo)
        halo_sum(hs->md->halo, &heat_points, 1);
    t->heat += heat + heat_points;
    return 0;
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
    if (hs->md->halo) {   /* bricks: over the atoms of every rank */
        double s[2] = {sum, (double)n};
        halo_sum(hs->md->halo, s, 2);
        sum = s[0];
        n = (long)s[1];
    }
    double k = 0.5 * sum * UNITS_MVV2E;
    if (ke)
        *ke = k;
    if (temperature)
        *temperature = n > 0 ? 2 * k / (3.0 * n * UNITS_KB) : 0;
    if (count)
        *count = n;
}
