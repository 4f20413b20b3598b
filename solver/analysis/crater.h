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

#include <stdint.h>

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

/* crater_measure in two parts, for atoms spread over MPI ranks
 * (md_analysis_bricks.c): each rank maps its own atoms, the maps are
 * reduced (top: maximum; who: the smallest key among the atoms at the
 * global top; rim: maximum), and every rank floods the same map.
 *
 * The height map: nx x ny columns (crater_grid). */
struct crater_map {
    int nx, ny;
    double *top;       /* Å: highest atom of each column (-inf: empty) */
    int64_t *who;      /* key of that atom (smallest key on ties; -1: empty) */
    double rim;        /* Å: highest atom above the surface (-inf: none) */
};

/* Allocate the map of p's grid (ERR_INPUT for a bad bin or extent). */
int crater_map_init(struct crater_map *m, const struct crater_params *p, struct err *e);
void crater_map_free(struct crater_map *m);

/* Add the atoms of x (use, NULL: all) to the map; key[i] names atom i
 * (NULL: its index i; keys >= 0). */
void crater_map_add(struct crater_map *m, const double *x, int n, const unsigned char *use,
                    const int64_t *key, const struct crater_params *p);

/* The crater of a complete map: the statistics, and in_crater[c] (nx ny
 * entries, may be NULL) set to 1 for the crater's columns. */
int crater_flood(const struct crater_map *m, const struct crater_params *p,
                 unsigned char *in_crater, struct crater_stats *out, struct err *e);

/* The column of position x (-1: outside the grid). */
long crater_column(const struct crater_map *m, const struct crater_params *p, const double *x);

#endif
