/*
 * handshake_bricks: the handshake band when the MD runs on MPI bricks
 * (core/halo.h; docs/parallel.md, docs/handshake.md "Under MPI").
 *
 * The scheme: the MD atoms (target, cluster, and the MD copies of regions
 * II and III, which are ordinary owned or ghost particles) are decomposed
 * like any MD system; the MPM side of the handshake (grid and every
 * material point) is whole and identical on every rank.  The band needs
 * two exchanges:
 *
 *   region I -> MPM   every step each rank packs the rows of its own region
 *                     I atoms (position, velocity, virial stress: 12
 *                     doubles), rank 0 gathers them and puts them in id
 *                     order, and broadcasts the whole set; every rank then
 *                     runs the same MPM step on the same input, so the MPM
 *                     state stays identical on every rank (and independent
 *                     of the rank count) without a reduction of nodal sums;
 *   MPM -> II/III     local: each rank places the copies it owns on their
 *                     points (the MPM is whole on every rank); the copies'
 *                     ghosts follow by the MD's forward communication.
 *
 * The id order of region I is found at every neighbour-list rebuild (when
 * atoms migrate), with the atoms' masses: hs_bricks_index.  Both
 * functions are collective over the ranks of hs->md->halo.
 */
#ifndef CASCADE_HANDSHAKE_BRICKS_H
#define CASCADE_HANDSHAKE_BRICKS_H

#include "couple/handshake.h"

/* After the local lists of region I (hs->idxI, hs->nI) are made: the
 * place of every region I atom of every rank in id order, the extra set
 * of the MPM sized for all of them, their masses and volumes. */
int hs_bricks_index(struct handshake *hs, struct err *e);

/* Region I of every rank into the MPM's extra set (hs->xI, vI, sI), in id
 * order, on every rank. */
int hs_bricks_gather(struct handshake *hs, struct err *e);

void hs_bricks_free(struct handshake *hs);

/* One region I atom's row for the MPM (handshake_step.c): position wrapped
 * into the grid, velocity, stress (eV/Å^3). */
void handshake_region_I_row(const struct handshake *hs, int i, double x[3], double v[3],
                            double s[6]);

#endif
