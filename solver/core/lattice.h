/*
 * lattice: crystal builders with the cube axes along x, y, z ([100]).
 *
 *   sc, bcc, fcc, diamond   cubic cells of edge a
 *   hcp                     orthorhombic cell a x sqrt(3) a x c, c = sqrt(8/3) a
 *                           (ideal), basal plane normal along z, 4 atoms
 *
 * An orientation (x, y, z along crystal directions such as [110] [-110]
 * [001]) rotates the cubic crystal; the repeating cell then has edges
 * a |[hkl]|.  Sites are generated for cells [0, n) along each axis from `origin`;
 * a region (optional) keeps only the sites inside it.
 */
#ifndef CASCADE_LATTICE_H
#define CASCADE_LATTICE_H

#include "core/particles.h"
#include "core/region.h"
#include "util/err.h"

enum lattice_style { LATTICE_SC, LATTICE_BCC, LATTICE_FCC, LATTICE_DIAMOND, LATTICE_HCP };
extern const char *const lattice_style_names[];   /* NULL-terminated, enum order */

struct lattice {
    enum lattice_style style;
    double a;            /* Å */
    double origin[3];
    int orient[3][3];    /* crystal directions along x, y, z (Miller indices of
                          * the cubic cell); all zero means [100] [010] [001] */
};

/* Check that the orientation rows are non-zero, mutually orthogonal and
 * right-handed; returns 0 or -1 with a reason in `why`. */
int lattice_check_orient(const struct lattice *l, char *why, size_t len);

/* Edge lengths of the repeating orthogonal cell (Å): the cubic cell, or
 * a |orient[d]| when oriented (hcp: a, sqrt(3) a, c). */
void lattice_cell(const struct lattice *l, double cell[3]);
/* Number of basis sites and their fractional coordinates (max 8). */
int lattice_basis(const struct lattice *l, double basis[8][3]);

/* Sites in one repeating cell of lattice_cell (oriented lattices have
 * more than the basis); -1 when out of memory. */
int lattice_cell_sites(const struct lattice *l);

/* Append sites of n[0] x n[1] x n[2] cells inside `region` (may be NULL) as
 * owned particles of `type`, ids continuing from *next_id.  Returns count
 * added or -1 (memory, recorded in e). */
long lattice_fill(const struct lattice *l, const long n[3], const struct region *region,
                  struct particles *p, int type, int64_t *next_id, struct err *e);
/* The same, storing only the sites for which keep(keep_ctx, x) is non-zero
 * (keep NULL: all); ids and the count returned run over all the sites of
 * the region, so the stored atoms have the ids a full build gives them (a
 * rank of a brick decomposition builds its own brick this way). */
long lattice_fill_where(const struct lattice *l, const long n[3], const struct region *region,
                        int (*keep)(const void *ctx, const double x[3]), const void *keep_ctx,
                        struct particles *p, int type, int64_t *next_id, struct err *e);

/* The extent of the sites lattice_fill_where visits (those inside
 * `region`, may be NULL) into lo and hi (lo > hi for none), from a pass
 * that stores none: the whole body's extent for a rank that then builds
 * its own brick.  Returns their count, or -1 (memory, recorded in e). */
long lattice_extent(const struct lattice *l, const long n[3], const struct region *region,
                    double lo[3], double hi[3], struct err *e);

/* Nearest-neighbour distance of the lattice (Å). */
double lattice_nn_distance(const struct lattice *l);

#endif
