/* dpd_bar: faces and extents of a bar of crystal planes. */
#include "scenarios/dpd_bar.h"

#include <math.h>

#include "core/halo.h"

void dpd_bar_measure(const struct particles *p, uint32_t exclude, double plane,
                     struct dpd_bar *bar)
{
    dpd_bar_measure_over(p, exclude, plane, NULL, bar);
}

void dpd_bar_measure_over(const struct particles *p, uint32_t exclude, double plane,
                          const struct halo *h, struct dpd_bar *bar)
{
    bar->plane = plane;
    for (int d = 0; d < 3; d++) {
        double ext[2] = {-INFINITY, -INFINITY};   /* -min, max */
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & exclude)
                continue;
            double x = p->x[3 * i + d];
            ext[0] = fmax(ext[0], -x);
            ext[1] = fmax(ext[1], x);
        }
        if (h)   /* the outermost particles of every rank */
            halo_max(h, ext, 2);
        double mn = -ext[0], mx = ext[1];
        double sum[4] = {0, 0, 0, 0};   /* slo, shi, nlo, nhi */
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & exclude)
                continue;
            double x = p->x[3 * i + d];
            if (x < mn + 0.5 * plane) {
                sum[0] += x;
                sum[2] += 1;
            }
            if (x > mx - 0.5 * plane) {
                sum[1] += x;
                sum[3] += 1;
            }
        }
        if (h)   /* the face planes' particles of every rank */
            halo_sum(h, sum, 4);
        bar->face_lo[d] = sum[2] > 0 ? sum[0] / sum[2] : 0;
        bar->face_hi[d] = sum[3] > 0 ? sum[1] / sum[3] : 0;
        bar->extent[d] = bar->face_hi[d] - bar->face_lo[d] + plane;
    }
}
