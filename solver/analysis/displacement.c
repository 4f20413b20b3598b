/* displacement: slab means and profiles of displacements along an axis. */
#include "analysis/displacement.h"

#include <math.h>
#include <stdlib.h>

int displacement_begin(struct particles *p, const struct box *b, struct err *e)
{
    int f = particles_find_field(p, "x_ref");
    if (f < 0)
        f = particles_add_field(p, "x_ref", 3, 0, e);
    if (f < 0)
        return -1;
    double *x0 = particles_field(p, f);
    for (int i = 0; i < p->n_owned; i++)
        box_unwrap(b, p, i, x0 + 3 * i);
    return f;
}

double displacement_slab_mean(const struct particles *p, const struct box *b, int field, int axis,
                              double lo, double hi, uint32_t exclude, long *count)
{
    const double *x0 = p->fields[field].data;
    double sum = 0;
    long n = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double r = x0[3 * i + axis];
        if (r < lo || r >= hi || (p->mask[i] & exclude))
            continue;
        double xu[3];
        box_unwrap(b, p, i, xu);
        sum += xu[axis] - r;
        n++;
    }
    if (count)
        *count = n;
    return n ? sum / n : NAN;
}

void displacement_profile_sums(const struct particles *p, const struct box *b, int field,
                               int axis, double origin, double w, int nbins, uint32_t exclude,
                               double *sum, double *cnt)
{
    const double *x0 = p->fields[field].data;
    for (int k = 0; k < nbins; k++)
        sum[k] = cnt[k] = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & exclude)
            continue;
        double r = x0[3 * i + axis];
        int k = (int)floor((r - origin) / w);
        if (k < 0 || k >= nbins)
            continue;
        double xu[3];
        box_unwrap(b, p, i, xu);
        sum[k] += xu[axis] - r;
        cnt[k] += 1;
    }
}

void displacement_profile(const struct particles *p, const struct box *b, int field, int axis,
                          double origin, double w, int nbins, uint32_t exclude, double *out)
{
    double *cnt = malloc((size_t)(nbins > 0 ? nbins : 1) * sizeof *cnt);
    if (cnt)
        displacement_profile_sums(p, b, field, axis, origin, w, nbins, exclude, out, cnt);
    for (int k = 0; k < nbins; k++)
        out[k] = cnt && cnt[k] ? out[k] / cnt[k] : NAN;
    free(cnt);
}
