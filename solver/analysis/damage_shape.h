/*
 * damage_shape: the top-view shape of a set of damaged atoms -- Guo & Yang
 * 2005, section 3.3 (Figs. 13-19) describe it in pictures: Cu damage first
 * spreads isotropically, then along the intersections of {111} slip planes
 * ([10-1], [-10-1], [01-1], [0-1-1]: seen from above, along <100>); Si
 * damage runs along [110] and [1-10] at mid-times and turns isotropic late.
 * Two numbers tell these apart:
 *
 *   The in-plane second-moment tensor (x = [100], y = [010]) of the atoms
 *   about their centroid,
 *       M = (1/N) sum_i (r_i - c)(r_i - c)^T,
 *   its eigenvalues lmax >= lmin, their ratio lmin/lmax (1: no preferred
 *   direction; 0: a line) and the direction of the major axis (degrees from
 *   [100]; 45 is [110], -45 is [1-10]).  A second-rank tensor cannot see a
 *   four-fold pattern -- four arms along <100> and a disc have the same M --
 *   so it measures two-fold anisotropy ([110] against [1-10]).
 *
 *   The extents along <100> and <110>: the width 2 Q_q(|u . (r - c)|),
 *   where Q_q is the q-quantile (q = DAMAGE_SHAPE_QUANTILE) of the
 *   distances from the centroid projected on u, pooled over the two
 *   directions of the family ([100] and [010]; [110] and [1-10]).  The
 *   ratio extent_110 / extent_100 sees the four-fold pattern: 1 for a disc,
 *   1.075 for a filled square with [100] edges, about 0.80 for four thin
 *   arms along <100> (damage along the slip-plane intersections) and about
 *   1.26 for four arms along <110>.  A quantile rather than the largest
 *   projection keeps a few stray atoms from setting the width.
 */
#ifndef CASCADE_DAMAGE_SHAPE_H
#define CASCADE_DAMAGE_SHAPE_H

#include "util/err.h"

/* the fraction of projected distances inside the extent */
#define DAMAGE_SHAPE_QUANTILE 0.9

struct damage_shape {
    long n;                 /* atoms measured */
    double centroid[2];     /* Å */
    double m[3];            /* Mxx, Myy, Mxy (Å^2) */
    double lmax, lmin;      /* eigenvalues of M (Å^2) */
    double eig_ratio;       /* lmin / lmax */
    double axis_deg;        /* major axis from [100], in (-90, 90] degrees */
    double extent_100, extent_110;   /* Å */
    double extent_ratio;    /* extent_110 / extent_100 */
};

/* Measure the atoms i with use[i] != 0 (use NULL: all) of the n positions x
 * (3 per atom; only x and y are read).  With fewer than three atoms, or
 * all of them on one point, the ratios and the axis are NaN.  scratch
 * holds 2n doubles (NULL: allocated here). */
int damage_shape_measure(const double *x, int n, const unsigned char *use, double *scratch,
                         struct damage_shape *out, struct err *e);

#endif
