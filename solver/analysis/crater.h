/*
 * crater: depth, volume and top-view shape of a crater in a surface whose
 * normal is +z (Guo & Yang 2005, Figs. 17-18: the crater's top view turns
 * from a circle into a square, or a square rotated by 45 degrees).
 *
 * The surface is cut into square columns of edge `bin` (one cubic cell is
 * a good choice for fcc(001): every column then holds atoms of every
 * layer; start the grid a quarter cell off the lattice planes so that no
 * atom of the perfect surface sits on a column edge).  The top of a column is its highest atom; its depth is the
 * original surface height minus that.  The crater is the set of columns,
 * connected edge to edge, deeper than `threshold` (half the layer spacing
 * is a good choice) that grows from the deepest column within two bins of
 * the impact point.  Reported:
 *   depth       deepest column of the crater (Å)
 *   volume      sum of column depths times the column area (Å^3)
 *   extent[4]   top-view width of the crater along [100], [010], [110],
 *               [1-10] (x, y and the diagonals): the spread of the crater
 *               column centres projected on the direction plus the width of
 *               one column seen along it (Å)
 *   rim         highest atom above the original surface (Å)
 * A square crater with edges along [100] is wider along [110] than along
 * [100] (ratio sqrt 2); a circle is as wide along both; a square rotated
 * by 45 degrees is wider along [100].
 */
#ifndef CASCADE_CRATER_H
#define CASCADE_CRATER_H

#include "util/err.h"

struct crater_params {
    double surface;     /* Å: original surface height (z) */
    double center[2];   /* Å: impact point (x, y) */
    double lo[2], hi[2];/* Å: lateral extent of the surface analysed */
    double bin;         /* Å: column edge */
    double threshold;   /* Å: depth for a column to be part of the crater */
};

struct crater_stats {
    double depth, volume;
    double extent[4];   /* [100], [010], [110], [1-10] */
    double rim;
    long columns;       /* columns in the crater */
};

/* x: positions (3 per particle); use[i] selects the atoms that belong to
 * the target (NULL: all).  floor_atom[i] (may be NULL) is set to 1 for the
 * top atom of every crater column, 0 otherwise. */
int crater_measure(const double *x, int n, const unsigned char *use, const struct crater_params *p,
                   unsigned char *floor_atom, struct crater_stats *out, struct err *e);

#endif
