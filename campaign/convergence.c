/* convergence: Celik et al. (2008) three-grid procedure (see convergence.h). */
#include "convergence.h"

#include <math.h>

const char *const conv_kind_names[] = {"monotone", "oscillatory", "divergent", "indeterminate",
                                       NULL};

double conv_h_from_cells(double ncells, int dim, double volume)
{
    return pow(volume / ncells, 1.0 / dim);
}

int conv_three_grid(const double h_in[3], const double phi_in[3], double safety,
                    struct conv_result *out, struct err *e)
{
    /* sort by grid size, finest first */
    int idx[3] = {0, 1, 2};
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (h_in[idx[b]] < h_in[idx[a]]) {
                int t = idx[a];
                idx[a] = idx[b];
                idx[b] = t;
            }
    for (int k = 0; k < 3; k++) {
        out->h[k] = h_in[idx[k]];
        out->phi[k] = phi_in[idx[k]];
        if (!(out->h[k] > 0) || !isfinite(out->phi[k]))
            return err_set(e, ERR_INPUT, "grid sizes must be positive and values finite "
                                         "(h = %g, phi = %g)",
                           out->h[k], out->phi[k]);
    }
    if (out->h[1] == out->h[0] || out->h[2] == out->h[1])
        return err_set(e, ERR_INPUT, "the three grid sizes must differ (%g, %g, %g)", out->h[0],
                       out->h[1], out->h[2]);
    const double *phi = out->phi;
    out->r21 = out->h[1] / out->h[0];
    out->r32 = out->h[2] / out->h[1];
    double e32 = phi[2] - phi[1], e21 = phi[1] - phi[0];
    out->p = out->phi_ext = out->e_ext21 = out->gci_fine = out->gci_medium = out->asymptotic = NAN;
    out->e_a21 = phi[0] != 0 ? fabs((phi[0] - phi[1]) / phi[0]) : NAN;
    out->iterations = 0;
    if (e32 == 0 || e21 == 0) {
        out->ratio = e32 == 0 ? (e21 == 0 ? NAN : INFINITY) : 0.0;
        out->kind = CONV_INDETERMINATE;
        return 0;
    }
    out->ratio = e21 / e32;
    double s = e32 / e21 > 0 ? 1.0 : -1.0;
    out->kind = fabs(out->ratio) > 1 ? CONV_DIVERGENT : s > 0 ? CONV_MONOTONE : CONV_OSCILLATORY;
    /* Eqs. 5a-5c by fixed-point iteration from the equal-ratio order */
    double lr = log(fabs(e32 / e21)), ln21 = log(out->r21);
    double p = fabs(lr) / ln21;
    int converged = 0;
    for (int it = 1; it <= 500; it++) {
        double num = pow(out->r21, p) - s, den = pow(out->r32, p) - s;
        if (!(num > 0 && den > 0))
            return err_set(e, ERR_INPUT,
                           "observed order undefined: r21^p - s = %g, r32^p - s = %g at p = %g", num,
                           den, p);
        double pn = fabs(lr + log(num / den)) / ln21;
        out->iterations = it;
        if (fabs(pn - p) <= 1e-13 * (1 + fabs(pn))) {
            p = pn;
            converged = 1;
            break;
        }
        p = pn;
    }
    if (!converged)
        return err_set(e, ERR_INPUT, "observed-order iteration did not converge (p ~ %g)", p);
    out->p = p;
    if (out->kind == CONV_DIVERGENT)
        return 0;   /* extrapolation and GCI are meaningless for a diverging sequence */
    double r21p = pow(out->r21, p), r32p = pow(out->r32, p);
    out->phi_ext = (r21p * phi[0] - phi[1]) / (r21p - 1);
    out->e_ext21 = fabs((out->phi_ext - phi[0]) / out->phi_ext);
    out->gci_fine = safety * out->e_a21 / (r21p - 1);
    double e_a32 = fabs((phi[1] - phi[2]) / phi[1]);
    out->gci_medium = safety * e_a32 / (r32p - 1);
    out->asymptotic = out->gci_medium / (r21p * out->gci_fine);
    return 0;
}
