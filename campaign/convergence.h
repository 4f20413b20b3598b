/*
 * convergence: grid-convergence analysis of a metric along a resolution
 * axis -- the procedure of Celik et al., "Procedure for estimation and
 * reporting of uncertainty due to discretization in CFD applications",
 * J. Fluids Eng. 130, 078001 (2008), which builds on Roache's Grid
 * Convergence Index.
 *
 * Three solutions phi_1, phi_2, phi_3 on grids h_1 < h_2 < h_3 (1 = finest):
 *   r21 = h2/h1, r32 = h3/h2, eps32 = phi3 - phi2, eps21 = phi2 - phi1,
 *   s = sign(eps32 / eps21)
 *   p = | ln|eps32/eps21| + q(p) | / ln r21,  q(p) = ln((r21^p - s)/(r32^p - s))
 *     (Celik Eqs. 5a-5c, solved by fixed-point iteration)
 *   phi_ext21 = (r21^p phi1 - phi2) / (r21^p - 1)                  (Eq. 6a)
 *   e_a21 = |(phi1 - phi2)/phi1|, e_ext21 = |(phi_ext21 - phi1)/phi_ext21|
 *   GCI_fine21 = Fs e_a21 / (r21^p - 1), Fs = 1.25                 (Eq. 8)
 *   GCI_32 = Fs e_a32 / (r32^p - 1); asymptotic range when
 *   GCI_32 / (r21^p GCI_21) is close to 1.
 * The convergence ratio R = eps21/eps32 classifies the sequence:
 *   0 < R < 1 monotone, -1 < R < 0 oscillatory, |R| > 1 divergent.
 */
#ifndef CASCADE_CONVERGENCE_H
#define CASCADE_CONVERGENCE_H

#include "util/err.h"

enum conv_kind {
    CONV_MONOTONE,
    CONV_OSCILLATORY,
    CONV_DIVERGENT,        /* |R| > 1: the difference grows as the grid is refined */
    CONV_INDETERMINATE,    /* two equal solutions: no order can be estimated */
};

extern const char *const conv_kind_names[];

struct conv_result {
    double h[3], phi[3];       /* sorted: index 0 finest */
    double r21, r32;
    double ratio;              /* R = eps21 / eps32 */
    enum conv_kind kind;
    double p;                  /* observed order (NaN when indeterminate) */
    double phi_ext;            /* Richardson-extrapolated value (NaN unless convergent) */
    double e_a21, e_ext21;     /* relative errors */
    double gci_fine, gci_medium;   /* fractions (multiply by 100 for %) */
    double asymptotic;         /* GCI_32 / (r21^p GCI_21), about 1 in the asymptotic range */
    int iterations;            /* fixed-point iterations used */
};

/* Three grid sizes (any order) and their solutions.  `safety` is the factor
 * Fs (1.25 for three grids).  Returns ERR_INPUT for non-positive or equal
 * grid sizes, or when the order iteration does not converge. */
int conv_three_grid(const double h[3], const double phi[3], double safety, struct conv_result *out,
                    struct err *e);

/* Representative grid size from a cell count: h = (volume / N)^(1/dim). */
double conv_h_from_cells(double ncells, int dim, double volume);

#endif
