/* eam_table: LAMMPS-compatible cubic interpolation of EAM tables. */
#include "md/eam_table.h"

#include <stdlib.h>

int eam_spline_build(struct eam_spline *s, const double *f, int n, double delta)
{
    s->n = n;
    s->delta = delta;
    s->rdelta = 1.0 / delta;
    s->c = calloc((size_t)7 * n, sizeof(double));
    if (!s->c || n < 5)
        return -1;
    double *c = s->c;
#define C(m, k) c[7 * (m) + (k)]
    for (int m = 0; m < n; m++)
        C(m, 6) = f[m];
    /* knot slopes (per interval) */
    C(0, 5) = f[1] - f[0];
    C(1, 5) = 0.5 * (f[2] - f[0]);
    C(n - 2, 5) = 0.5 * (f[n - 1] - f[n - 3]);
    C(n - 1, 5) = f[n - 1] - f[n - 2];
    for (int m = 2; m <= n - 3; m++)
        C(m, 5) = ((f[m - 2] - f[m + 2]) + 8.0 * (f[m + 1] - f[m - 1])) / 12.0;
    /* Hermite cubic on each interval */
    for (int m = 0; m < n - 1; m++) {
        C(m, 4) = 3.0 * (f[m + 1] - f[m]) - 2.0 * C(m, 5) - C(m + 1, 5);
        C(m, 3) = C(m, 5) + C(m + 1, 5) - 2.0 * (f[m + 1] - f[m]);
    }
    C(n - 1, 4) = 0.0;
    C(n - 1, 3) = 0.0;
    /* derivative with respect to the table variable */
    for (int m = 0; m < n; m++) {
        C(m, 2) = C(m, 5) / delta;
        C(m, 1) = 2.0 * C(m, 4) / delta;
        C(m, 0) = 3.0 * C(m, 3) / delta;
    }
#undef C
    return 0;
}

void eam_spline_free(struct eam_spline *s)
{
    free(s->c);
    s->c = NULL;
    s->n = 0;
}
