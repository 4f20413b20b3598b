/* handshake_layout: where regions I, II, III and the grid levels lie, and
 * which layouts are refused (Guo & Yang 2005, section 2.2 and Fig. 3). */
#include <math.h>
#include <stdio.h>

#include "couple/handshake.h"

void handshake_layout_period(const struct handshake_layout *L, double p[3])
{
    double basis[8][3];
    hs_cell_basis(L->lattice, L->orient, basis, p);
    for (int d = 0; d < 3; d++)
        p[d] *= L->a;
}

void handshake_layout_cell(const struct handshake_layout *L, double h[3])
{
    double p[3];
    handshake_layout_period(L, p);
    for (int d = 0; d < 3; d++)
        h[d] = d == 0 ? L->h : L->h / p[0] * p[d];
}

int handshake_face_coupled(const struct handshake_layout *L, int f)
{
    int d = f / 2;
    double tol = 1e-6 * L->a;
    return (f & 1) ? L->md_hi[d] < L->mat_hi[d] - tol : L->md_lo[d] > L->mat_lo[d] + tol;
}

enum hs_region handshake_classify(const struct handshake_layout *L, const double x[3])
{
    int inside = 1;
    for (int d = 0; d < 3; d++)
        inside &= x[d] >= L->md_lo[d] && x[d] < L->md_hi[d];
    if (inside) {
        /* distance to the nearest interface */
        double dmin = INFINITY;
        for (int f = 0; f < 6; f++) {
            if (!handshake_face_coupled(L, f))
                continue;
            int d = f / 2;
            double dist = (f & 1) ? L->md_hi[d] - x[d] : x[d] - L->md_lo[d];
            dmin = fmin(dmin, dist);
        }
        return dmin < L->w[0] ? HS_I : HS_CORE;
    }
    /* Chebyshev distance outside the coupled faces */
    double o = 0;
    for (int d = 0; d < 3; d++) {
        if (x[d] < L->md_lo[d])
            o = fmax(o, L->md_lo[d] - x[d]);
        else if (x[d] >= L->md_hi[d])
            o = fmax(o, x[d] - L->md_hi[d]);
    }
    if (o <= L->w[1])
        return HS_II;
    if (o <= L->w[1] + L->w[2])
        return HS_III;
    return HS_MPM;
}

/* x is a whole multiple of q (relative tolerance). */
static int multiple_of(double x, double q)
{
    double r = x / q;
    return fabs(r - round(r)) < 1e-6;
}

int handshake_layout_check(const struct handshake_layout *L, double cutoff,
                           enum hs_layout_key *key, char *why, size_t len)
{
    const double a = L->a;
    static const char *const rname[3] = {"I", "II", "III"};
#define REFUSE(k, ...)                                                                            \
    do {                                                                                          \
        *key = (k);                                                                               \
        snprintf(why, len, __VA_ARGS__);                                                          \
        return ERR_INPUT;                                                                         \
    } while (0)
    if (!(a > 0))
        REFUSE(HS_KEY_GEOMETRY, "the lattice constant must be positive");
    if ((unsigned)L->lattice >= HS_LATTICE_COUNT)
        REFUSE(HS_KEY_GEOMETRY, "unknown lattice %d: fcc, bcc or diamond", (int)L->lattice);
    if ((unsigned)L->orient >= HS_ORIENT_COUNT)
        REFUSE(HS_KEY_GEOMETRY, "unknown orientation %d: 100 or 110", (int)L->orient);
    /* the oriented cell: along [100] a cube of a; along [110] edges a/sqrt2
     * (fcc, diamond) or sqrt2 a (bcc) across and a along z.  Lengths are
     * checked against its edge along each axis (P[d]), cells are the same
     * fraction of it along every axis. */
    double P[3], H[3];
    handshake_layout_period(L, P);
    handshake_layout_cell(L, H);
    const int turned = L->orient != HS_ORIENT_100;
    const char *unit = turned ? "cell edges" : "lattice constants";
    if ((L->lattice != HS_LATTICE_FCC || turned) && fabs(L->h - P[0]) > 1e-9 * P[0])
        REFUSE(HS_KEY_CELL,
               "a %s crystal needs a finest cell of one %s%s (%g Å is %g): in smaller cells "
               "its sites fill only part of the cells, which leaves forces on the grid under a "
               "uniform stress",
               hs_lattice_names[L->lattice], turned ? "cell edge" : "lattice constant",
               turned ? " when turned to [110] (cell: 1)" : "", L->h, L->h / P[0]);
    if (!(fabs(L->h - a) < 1e-9 * a || fabs(L->h - 0.5 * a) < 1e-9 * a) && !turned)
        REFUSE(HS_KEY_CELL,
               "the finest cell must be 1 or 0.5 lattice constants (%g Å is %g): the lattice "
               "sites of regions II and III must sit at the same place in every cell",
               L->h, L->h / a);
    for (int k = 0; k < 3; k++)
        if (L->w[k] < cutoff * (1 - 1e-12))
            REFUSE(HS_KEY_REGIONS,
                   "region %s is %.4g Å (%g %s) wide, narrower than the potential "
                   "cutoff %.4g Å: each handshake region must be at least one cutoff wide",
                   rname[k], L->w[k], L->w[k] / P[0], unit, cutoff);
    for (int d = 0; d < 3; d++) {
        if (!handshake_face_coupled(L, 2 * d) && !handshake_face_coupled(L, 2 * d + 1))
            continue;
        for (int k = 0; k < 3; k++)
            if (!multiple_of(L->w[k], 0.5 * P[d]))
                REFUSE(HS_KEY_REGIONS,
                       "region %s is %g Å wide: across an interface normal to %c widths must "
                       "be multiples of 0.5 %s (%g Å: whole lattice planes)",
                       rname[k], L->w[k], "xyz"[d], turned ? "cell edges" : "lattice constants",
                       0.5 * P[d]);
        if (L->w[0] < 2 * H[d] * (1 - 1e-12))
            REFUSE(HS_KEY_REGIONS,
                   "region I (%g Å) must be at least two cells (%g Å) wide, so that no node "
                   "moving a region II point sees its inner edge",
                   L->w[0], 2 * H[d]);
    }
    if (L->nlevels < 0 || L->nlevels > MPM_MAX_LEVELS)
        REFUSE(HS_KEY_LEVELS, "levels = %d: between 0 and %d", L->nlevels, MPM_MAX_LEVELS);
    if (L->nlevels > 0 && (L->coarsen & 7u) == 0)
        REFUSE(HS_KEY_LEVELS, "coarsening needs at least one direction");
    if (L->nlevels > 1 && !(L->layer > 0))
        REFUSE(HS_KEY_LAYER, "the width of each coarse level must be positive");
    double shell = L->w[1] + L->w[2];
    if (L->nlevels > 0 && L->fine < shell * (1 - 1e-12))
        REFUSE(HS_KEY_FINE,
               "the coarse grid would start %.4g Å (%g lattice constants) from the MD region, "
               "inside regions II and III (%.4g Å): the MD region and its handshake must not "
               "touch the coarse grid",
               L->fine, L->fine / a, shell);
    int ncoupled = 0;
    for (int d = 0; d < 3; d++) {
        double ext = L->dom_hi[d] - L->dom_lo[d];
        if (!(ext > 0) || !multiple_of(ext, H[d]))
            REFUSE(HS_KEY_GEOMETRY, "the MPM domain along %c (%g Å) is not a whole number of "
                   "cells of %g Å", "xyz"[d], ext, H[d]);
        if (L->md_lo[d] < L->dom_lo[d] - 1e-9 * a || L->md_hi[d] > L->dom_hi[d] + 1e-9 * a ||
            !(L->md_hi[d] > L->md_lo[d]))
            REFUSE(HS_KEY_GEOMETRY,
                   "the MD region along %c [%g, %g] Å must lie inside the MPM domain [%g, %g] Å",
                   "xyz"[d], L->md_lo[d], L->md_hi[d], L->dom_lo[d], L->dom_hi[d]);
        if (L->mat_lo[d] < L->dom_lo[d] - 1e-9 * a || L->mat_hi[d] > L->dom_hi[d] + 1e-9 * a ||
            L->md_lo[d] < L->mat_lo[d] - 1e-9 * a || L->md_hi[d] > L->mat_hi[d] + 1e-9 * a)
            REFUSE(HS_KEY_GEOMETRY,
                   "along %c the material [%g, %g] Å must lie inside the grid [%g, %g] Å and "
                   "contain the MD region [%g, %g] Å",
                   "xyz"[d], L->mat_lo[d], L->mat_hi[d], L->dom_lo[d], L->dom_hi[d], L->md_lo[d],
                   L->md_hi[d]);
        double off_frac = hs_cell_offset(L->lattice, L->orient, d);
        double off = L->lat_origin[d] - L->dom_lo[d] - off_frac * P[d];
        if (!multiple_of(off, 0.5 * P[d]))
            REFUSE(HS_KEY_GEOMETRY,
                   "lattice sites must lie %g %s off the grid planes (%s; "
                   "lattice origin %g Å along %c)",
                   off_frac * P[d] / (turned ? P[d] : a), unit, hs_lattice_names[L->lattice],
                   L->lat_origin[d], "xyz"[d]);
        if (!multiple_of(L->md_lo[d] - L->dom_lo[d], 0.5 * P[d]) ||
            !multiple_of(L->md_hi[d] - L->dom_lo[d], 0.5 * P[d]))
            REFUSE(HS_KEY_MD,
                   "the MD region's faces along %c must lie between lattice planes (multiples "
                   "of 0.5 %s, %g Å, from the domain's corner)",
                   "xyz"[d], unit, 0.5 * P[d]);
        for (int s = 0; s < 2; s++) {
            if (!handshake_face_coupled(L, 2 * d + s))
                continue;
            ncoupled++;
            double room = s ? L->mat_hi[d] - L->md_hi[d] : L->md_lo[d] - L->mat_lo[d];
            if (room < shell * (1 - 1e-12))
                REFUSE(HS_KEY_GEOMETRY,
                       "the MPM part beyond the %s face of the MD region along %c is %.4g Å, "
                       "less than regions II and III (%.4g Å)",
                       s ? "upper" : "lower", "xyz"[d], room, shell);
            if (L->md_periodic[d])
                REFUSE(HS_KEY_MD,
                       "the MD region cannot be periodic along %c: it has an interface there",
                       "xyz"[d]);
        }
        double span = L->md_hi[d] - L->md_lo[d];
        int both = handshake_face_coupled(L, 2 * d) && handshake_face_coupled(L, 2 * d + 1);
        if (span < (both ? 2 : 1) * L->w[0] * (1 - 1e-12) &&
            (handshake_face_coupled(L, 2 * d) || handshake_face_coupled(L, 2 * d + 1)))
            REFUSE(HS_KEY_MD,
                   "the MD region along %c (%g Å) is too short for its region I layers (%g Å "
                   "each)",
                   "xyz"[d], span, L->w[0]);
    }
    if (ncoupled == 0)
        REFUSE(HS_KEY_MD, "the MD region has no face inside the MPM material: no interface");
#undef REFUSE
    return 0;
}
