#include "helpers/th_handshake.h"

#include <math.h>

double th_hs_md_fmax(const struct particles *p)
{
    double fm = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III))
            continue;
        const double *f = p->f + 3 * i;
        fm = fmax(fm, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    }
    return fm;
}

double th_hs_grid_fmax(const struct handshake *hs, long *nnodes, double *fedge)
{
    const struct handshake_layout *L = &hs->lay;
    const struct mpm_grid *g = &hs->mpm.grid;
    double lo[3], hi[3];
    mpm_grid_bounds(g, lo, hi);
    double fm = 0, fe = 0, tol = 1e-6;
    long n = 0;
    for (long i = 0; i < g->nnodes; i++) {
        if (g->node[i].m <= 0)
            continue;
        double x[3];
        mpm_grid_node_position(g, i, x);
        if (fabs(x[0] - lo[0]) < tol || fabs(x[0] - hi[0]) < tol)
            continue;
        if (x[0] > L->md_lo[0] + L->h + tol && x[0] < L->md_hi[0] - L->h - tol)
            continue;
        double f[3] = {g->node[i].f[0], g->node[i].f[1], g->node[i].f[2]};
        int faces = 0;
        for (int d = 1; d < 3; d++)
            if (fabs(x[d] - lo[d]) < tol || fabs(x[d] - hi[d]) < tol) {
                f[d] = 0;
                faces++;
            }
        double fn = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        if (faces == 2) {
            fe = fmax(fe, fn);
            continue;
        }
        n++;
        fm = fmax(fm, fn);
    }
    *nnodes = n;
    *fedge = fe;
    return fm;
}
