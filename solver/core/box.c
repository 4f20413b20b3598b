/* box: boundary handling of an orthogonal box. */
#include "core/box.h"

#include <math.h>

const char *const boundary_names[] = {"periodic", "free", "fixed", NULL};

double box_volume(const struct box *b)
{
    return box_length(b, 0) * box_length(b, 1) * box_length(b, 2);
}

int box_remap(struct box *b, struct particles *p, double margin, struct err *e)
{
    for (int d = 0; d < 3; d++) {
        double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
        if (b->bc[d] == BOUNDARY_PERIODIC) {
            for (int i = 0; i < p->n_owned; i++) {
                double *x = &p->x[3 * i + d];
                if (*x < lo || *x >= hi) {
                    double k = floor((*x - lo) / len);
                    /* a NaN or a particle a million boxes away is a runaway,
                     * not an image to count (and (int)k would overflow) */
                    if (!(fabs(k) < 1.0e6))
                        return err_set(e, ERR_DIVERGED,
                                       "particle id %lld has %c = %g, %s the periodic box "
                                       "[%g, %g)", (long long)p->id[i], "xyz"[d], *x,
                                       isfinite(*x) ? "a million box lengths outside" : "not inside",
                                       lo, hi);
                    *x -= k * len;
                    if (*x >= hi) {
                        /* round-off at the upper face: an atom a hair below
                         * lo lands on hi, which is lo of the next image, so
                         * the image count is one more (else the unwrapped
                         * position jumps by a box length) */
                        *x = lo;
                        k += 1;
                    }
                    p->image[3 * i + d] += (int)k;
                }
            }
        } else if (b->bc[d] == BOUNDARY_FREE) {
            double mn = INFINITY, mx = -INFINITY;
            for (int i = 0; i < p->n_owned; i++) {
                double x = p->x[3 * i + d];
                if (x < mn) mn = x;
                if (x > mx) mx = x;
            }
            if (p->n_owned > 0) {
                b->lo[d] = mn - margin;
                b->hi[d] = mx + margin;
            }
        } else {
            for (int i = 0; i < p->n_owned; i++) {
                double x = p->x[3 * i + d];
                if (!(x >= lo && x <= hi))
                    return err_set(e, ERR_RUNTIME,
                                   "particle %lld left the box through the fixed %c boundary "
                                   "(%c = %g Å, box [%g, %g])",
                                   (long long)p->id[i], "xyz"[d], "xyz"[d], x, lo, hi);
            }
        }
    }
    return 0;
}

void box_unwrap(const struct box *b, const struct particles *p, int i, double out[3])
{
    for (int d = 0; d < 3; d++)
        out[d] = p->x[3 * i + d] + p->image[3 * i + d] * box_length(b, d);
}
