/* handshake_profile: slab averages of stress, displacement and velocity
 * from the MD atoms and the material points, in one series. */
#include "couple/handshake_profile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"

int hs_profile_init(struct hs_profile *pr, const struct handshake *hs, int axis, double width,
                    struct err *e)
{
    memset(pr, 0, sizeof *pr);
    pr->axis = axis;
    pr->width = width;
    pr->x0 = hs->lay.dom_lo[axis];
    pr->nbins = (long)ceil((hs->lay.dom_hi[axis] - pr->x0) / width - 1e-9);
    if (pr->nbins < 1)
        pr->nbins = 1;
    pr->md = calloc((size_t)pr->nbins, sizeof *pr->md);
    pr->mpm = calloc((size_t)pr->nbins, sizeof *pr->mpm);
    pr->sums = malloc((size_t)pr->nbins * HS_SLAB_SUMS_MPM * sizeof *pr->sums);
    if (!pr->md || !pr->mpm || !pr->sums) {
        hs_profile_free(pr);
        return err_nomem(e, "handshake profile");
    }
    return 0;
}

void hs_profile_free(struct hs_profile *pr)
{
    free(pr->md);
    free(pr->mpm);
    free(pr->sums);
    memset(pr, 0, sizeof *pr);
}

static long bin_of(const struct hs_profile *pr, double x)
{
    long k = (long)floor((x - pr->x0) / pr->width);
    return k < 0 || k >= pr->nbins ? -1 : k;
}

/* Bricks: each rank summed the atoms it owns; the slabs' sums (count,
 * virial and kinetic stress, displacement and velocity) over the ranks,
 * before the means and the volumes.  Collective. */
static void sum_md_slabs(struct hs_profile *pr, const struct halo *h)
{
    double *buf = pr->sums;
    for (long k = 0; k < pr->nbins; k++) {
        const struct hs_slab *s = &pr->md[k];
        double *b = buf + HS_SLAB_SUMS * k;
        b[0] = (double)s->n;
        for (int c = 0; c < 6; c++)
            b[1 + c] = s->stress[c];
        b[7] = s->u;
        b[8] = s->v;
    }
    halo_sum(h, buf, (int)(pr->nbins * HS_SLAB_SUMS));
    for (long k = 0; k < pr->nbins; k++) {
        struct hs_slab *s = &pr->md[k];
        const double *b = buf + HS_SLAB_SUMS * k;
        s->n = (long)b[0];
        for (int c = 0; c < 6; c++)
            s->stress[c] = b[1 + c];
        s->u = b[7];
        s->v = b[8];
    }
}

/* Bricks: each rank summed the material points it holds (the handshake's
 * points are dealt out over the ranks, handshake_bricks.h); the MPM slabs'
 * sums over the ranks, before the means.  Collective. */
static void sum_mpm_slabs(struct hs_profile *pr, const struct halo *h)
{
    double *buf = pr->sums;
    for (long k = 0; k < pr->nbins; k++) {
        const struct hs_slab *s = &pr->mpm[k];
        double *b = buf + HS_SLAB_SUMS_MPM * k;
        b[0] = (double)s->n;
        for (int c = 0; c < 6; c++)
            b[1 + c] = s->stress[c];
        b[7] = s->volume;
        b[8] = s->u;
        b[9] = s->v;
        b[10] = s->mass;
    }
    halo_sum(h, buf, (int)(pr->nbins * HS_SLAB_SUMS_MPM));
    for (long k = 0; k < pr->nbins; k++) {
        struct hs_slab *s = &pr->mpm[k];
        const double *b = buf + HS_SLAB_SUMS_MPM * k;
        s->n = (long)b[0];
        for (int c = 0; c < 6; c++)
            s->stress[c] = b[1 + c];
        s->volume = b[7];
        s->u = b[8];
        s->v = b[9];
        s->mass = b[10];
    }
}

void hs_profile_compute(struct hs_profile *pr, const struct handshake *hs)
{
    const int ax = pr->axis;
    memset(pr->md, 0, (size_t)pr->nbins * sizeof *pr->md);
    memset(pr->mpm, 0, (size_t)pr->nbins * sizeof *pr->mpm);
    /* MD atoms of the box (not the copies, not held atoms) */
    const struct particles *p = hs->md->p;
    const double *x0 = p->fields[hs->f_x0].data;
    const uint32_t skip = HS_MASK_II | HS_MASK_III | HS_MASK_FIXED;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & skip)
            continue;
        long k = bin_of(pr, x0[3 * i + ax]);
        if (k < 0)
            continue;
        struct hs_slab *s = &pr->md[k];
        const double *v = p->v + 3 * i, *w = p->virial + 6 * i;
        double m = p->mass[p->type[i]] * UNITS_MVV2E;
        double kv[6] = {v[0] * v[0], v[1] * v[1], v[2] * v[2], v[0] * v[1], v[0] * v[2], v[1] * v[2]};
        for (int c = 0; c < 6; c++)
            s->stress[c] -= w[c] + m * kv[c];
        double du = p->x[3 * i + ax] - x0[3 * i + ax];
        if (hs->md->box.bc[ax] == BOUNDARY_PERIODIC) {   /* undo a wrap */
            double L = box_length(&hs->md->box, ax);
            du -= L * round(du / L);
        }
        s->u += du;
        s->v += v[ax];
        s->n++;
    }
    if (hs->md->halo)
        sum_md_slabs(pr, hs->md->halo);
    for (long k = 0; k < pr->nbins; k++) {
        struct hs_slab *s = &pr->md[k];
        if (s->n == 0)
            continue;
        s->u /= s->n;
        s->v /= s->n;
    }
    /* current volume: stretch along the axis from the mean displacements of
     * the neighbouring MD slabs */
    for (long k = 0; k < pr->nbins; k++) {
        struct hs_slab *s = &pr->md[k];
        if (s->n == 0)
            continue;
        long a = k > 0 && pr->md[k - 1].n > 0 ? k - 1 : k;
        long b = k + 1 < pr->nbins && pr->md[k + 1].n > 0 ? k + 1 : k;
        double grad = b > a ? (pr->md[b].u - pr->md[a].u) / ((b - a) * pr->width) : 0.0;
        s->volume = s->n * hs->omega0 * (1.0 + grad);
        for (int c = 0; c < 6; c++)
            s->stress[c] /= s->volume;
    }
    /* material points by initial position */
    const struct mpm_points *pt = &hs->mpm.pts;
    for (long q = 0; q < pt->n; q++) {
        long k = bin_of(pr, pt->x0[3 * q + ax]);
        if (k < 0)
            continue;
        struct hs_slab *s = &pr->mpm[k];
        double V = pt->vol[q];
        for (int c = 0; c < 6; c++)
            s->stress[c] += V * pt->stress[6 * q + c];
        s->volume += V;
        s->u += pt->mass[q] * (pt->x[3 * q + ax] - pt->x0[3 * q + ax]);
        s->v += pt->mass[q] * pt->v[3 * q + ax];
        s->mass += pt->mass[q];
        s->n++;
    }
    if (hs->md->halo)
        sum_mpm_slabs(pr, hs->md->halo);
    for (long k = 0; k < pr->nbins; k++) {
        struct hs_slab *s = &pr->mpm[k];
        if (s->n == 0)
            continue;
        for (int c = 0; c < 6; c++)
            s->stress[c] /= s->volume;
        s->u /= s->mass;
        s->v /= s->mass;
    }
}

long hs_profile_mean(const struct hs_profile *pr, int source, int c, double lo, double hi,
                     double *mean)
{
    const struct hs_slab *s = source == HS_SRC_MD ? pr->md : pr->mpm;
    double sum = 0;
    long n = 0;
    for (long k = 0; k < pr->nbins; k++) {
        double x = hs_profile_x(pr, k);
        if (s[k].n == 0 || x < lo || x >= hi)
            continue;
        sum += s[k].stress[c];
        n++;
    }
    *mean = n ? sum / n : NAN;
    return n;
}
