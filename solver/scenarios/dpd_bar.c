/* dpd_bar: faces and extents of a bar of crystal planes. */
#include "scenarios/dpd_bar.h"

#include <math.h>

void dpd_bar_measure(const struct particles *p, uint32_t exclude, double plane,
                     struct dpd_bar *bar)
{
    bar->plane = plane;
    for (int d = 0; d < 3; d++) {
        double mn = INFINITY, mx = -INFINITY;
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & exclude)
                continue;
            double x = p->x[3 * i + d];
            mn = fmin(mn, x);
            mx = fmax(mx, x);
        }
        double slo = 0, shi = 0;
        long nlo = 0, nhi = 0;
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & exclude)
                continue;
            double x = p->x[3 * i + d];
            if (x < mn + 0.5 * plane) {
                slo += x;
                nlo++;
            }
            if (x > mx - 0.5 * plane) {
                shi += x;
                nhi++;
            }
        }
        bar->face_lo[d] = nlo ? slo / nlo : 0;
        bar->face_hi[d] = nhi ? shi / nhi : 0;
        bar->extent[d] = bar->face_hi[d] - bar->face_lo[d] + plane;
    }
}
