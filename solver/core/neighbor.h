/*
 * neighbor: link cells + Verlet lists with a skin.
 *
 * Particles (owned and ghost) are binned into cells at least (cutoff + skin)/2
 * wide (cutoff + skin in sparse systems, where those would far outnumber
 * the particles) with a counting sort (CSR layout, no fixed slots per
 * cell); each owned particle's list holds the particles within cutoff +
 * skin, found in the 5 x 5 x 5 (3 x 3 x 3) cells around its own.  The list is
 * reused until some owned particle has moved more than skin/2 since the
 * build, which guarantees that no pair within the cutoff is missed.
 *
 * Half lists ("newton on") hold each pair once: an owned pair (i, j) under
 * the smaller index, an owned-ghost pair under the owned particle when the
 * ghost lies above it in z (ties broken by y, then x).  Each physical pair
 * across a periodic boundary appears as two owned-ghost pairs; the
 * coordinate rule keeps exactly one.  Forces on ghosts are added back to
 * their owners afterwards (ghost_reverse_add).  A kernel may reorder the
 * neighbours of a particle within its range (the EAM density pass moves
 * the ones inside the cutoff to the front); the set never changes.  Full lists hold every
 * neighbour of each owned particle (three-body and structure analysis).
 */
#ifndef CASCADE_NEIGHBOR_H
#define CASCADE_NEIGHBOR_H

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

enum nlist_kind { NLIST_HALF, NLIST_FULL };

struct nlist {
    enum nlist_kind kind;
    double cutoff, skin;     /* Å */
    int n;                   /* owned particles listed */
    int ilo, ihi;            /* only owned particles in [ilo, ihi) get a list (the
                              * slice of this MPI rank); others have none */
    int *offset;             /* n + 1 entries: neighbours of i are neigh[offset[i]..offset[i+1]) */
    int *neigh;
    long cap_neigh;
    int cap_offset;
    double *x_build;         /* owned positions at the last build (3 per particle) */
    int cap_build;
    long nbuilds;
    /* link cells (scratch kept between builds) */
    int *cell_start, *cell_of, *cell_sorted;
    long cap_cells;
    int cap_cell_of;
    double *xs;              /* positions in cell order: x[0..ntot), then y, then z */
    int cap_xs;
};

struct nlist *nlist_create(enum nlist_kind kind, double cutoff, double skin);
void nlist_destroy(struct nlist **nl);

/* Build from the current owned + ghost positions. */
int nlist_build(struct nlist *nl, const struct particles *p, struct err *e);

/* 1 when an owned particle moved more than skin/2 since the last build. */
int nlist_needs_rebuild(const struct nlist *nl, const struct particles *p);

/* Brute-force reference (O(N^2)), for tests: same pair rule as nlist_build. */
int nlist_build_brute(struct nlist *nl, const struct particles *p, struct err *e);

/* Owned-particle order that walks the link cells (a space-filling order for
 * cache locality); perm[k] = old index.  Returns 0 or ERR_RUNTIME. */
int nlist_spatial_order(const struct particles *p, double cell, int *perm, struct err *e);

#endif
