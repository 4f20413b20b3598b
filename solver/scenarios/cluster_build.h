/*
 * cluster_build: clusters cut from a crystal -- a sphere holding exactly N
 * lattice sites (Guo & Yang 2005, section 3.2: "Cu clusters are formed
 * from a spherical cutoff of an FCC lattice").
 *
 * Around a given centre the sites are sorted by distance; N is reachable
 * when the N-th and (N+1)-th distances differ (a sphere never cuts a shell
 * of equidistant sites).  Without a centre the candidates are tried in a
 * fixed order and the first that reaches N wins: the lattice site, the
 * cube centre (octahedral site of fcc), the tetrahedral site (1/4 1/4 1/4),
 * then the points k/8 of the irreducible wedge 1/2 >= fx >= fy >= fz >= 0
 * in lexicographic order.  For fcc this gives 14 atoms around the cube
 * centre and 128 and 1052 around (1/8, 0, 0) a; for diamond 260 around
 * (3/8, 1/8, 0) a.
 */
#ifndef CASCADE_CLUSTER_BUILD_H
#define CASCADE_CLUSTER_BUILD_H

#include "core/lattice.h"
#include "util/err.h"

struct cluster_cut {
    long n;
    double (*pos)[3];     /* n sites relative to the centre (Å), owned */
    double center[3];     /* centre in units of a (fractional cell coordinates) */
    double radius;        /* Å: midway between the last site kept and the first left out */
    double extent;        /* Å: largest distance of a kept site from the centre */
};

/* center_frac: NULL to search as above.  ERR_INPUT with the nearest
 * reachable counts when N cannot be cut. */
int cluster_cut_sphere(enum lattice_style style, double a, long n, const double *center_frac,
                       struct cluster_cut *out, struct err *e);
void cluster_cut_free(struct cluster_cut *c);

#endif
