/*
 * handshake_bricks: the handshake's MPM side on the ranks of the MD's
 * bricks (core/halo.h; docs/parallel.md "How the handshake runs on
 * bricks", docs/handshake.md "Under MPI").
 *
 * The MD atoms (target, cluster, and the MD copies of regions II and III,
 * which are ordinary owned or ghost particles) are decomposed like any MD
 * system.  The MPM side is decomposed as mpm_bricks' fixed-owner mode
 * (mpm/mpm_bricks.h): the hierarchical grid is whole on every rank, the
 * material points are dealt out once and never move between ranks, and
 * after every particle-to-grid pass the nodes' sums are reduced over the
 * ranks, so every rank updates every node alike (Guo & Yang's hanging
 * nodes, Eq. (11), need nothing across brick faces).  A point goes to the
 * rank whose MD brick holds its initial position (clamped into the MD
 * box) when it is built, so no rank ever holds every point, and a point
 * of region II or III and its MD copy start on the same rank.
 *
 *   region I -> MPM   each rank maps its own region I atoms (its local
 *                     extra set, as in a serial run); the reduction of the
 *                     node sums adds the other ranks' atoms.  Nothing is
 *                     gathered or broadcast.
 *   MPM -> II/III     each copy takes its point's row (position with the
 *                     internal shift, wrapped; velocity; strain energy);
 *                     a copy whose point another rank holds (the copy
 *                     migrated with the MD, or the cuts moved) gets the row
 *                     from that rank in one all-to-all a step, planned at
 *                     each neighbour-list rebuild (hs_bricks_index).
 *
 * Round-off: the node sums are the ranks' partial sums added on rank 0
 * (parallel_sum), not the serial order, so the MPM agrees with the serial
 * run to round-off, not bitwise (docs/parallel.md gives the measured
 * agreement).  All functions with a halo are collective over its ranks.
 */
#ifndef CASCADE_HANDSHAKE_BRICKS_H
#define CASCADE_HANDSHAKE_BRICKS_H

#include "couple/handshake.h"
#include "mpm/mpm.h"

/* The points are dealt out as they are built (handshake_build.c:
 * every rank passes over all of them and adds those whose initial
 * position lies in its MD brick, so that no rank ever holds them all):
 * owner[q] the rank of the point with id q + 1, for every one of the n
 * points (taken over, also on a failure).  Sets up the MPM step on the
 * whole grid with fixed owners.  Collective over the halo's ranks. */
struct halo;
int hs_bricks_adopt(struct handshake *hs, const struct halo *h, int32_t *owner, long n,
                    struct err *e);

/* After the local lists of region I and the copies are made (at every
 * neighbour-list rebuild): which copies' points another rank holds, and
 * the all-to-all that brings their rows. */
int hs_bricks_index(struct handshake *hs, struct err *e);

/* Fill hs->link_row for every copy of this rank: from its point here, or
 * received from the rank that holds it. */
int hs_bricks_link_rows(struct handshake *hs, struct err *e);

/* The MPM side's collectives on bricks. */
int hs_bricks_mpm_step(struct handshake *hs, double dt, struct err *e);
int hs_bricks_mpm_prepare(struct handshake *hs, struct err *e);
int hs_bricks_map_forces(struct handshake *hs, struct err *e);
void hs_bricks_mpm_totals(const struct handshake *hs, struct mpm_totals *t);

/* Checkpoints on bricks (output/mpm_checkpoint.h): the collect
 * (collective, before rank 0 writes) counts every rank's points -- rank 0
 * lays out hs_bricks_checkpoint_total() rows, each rank writes its own
 * from row hs_bricks_checkpoint_offset() -- and a restart reads the n
 * stored rows in blocks, each rank keeping the points dealt to it
 * (hs_bricks_adopt), in id order.  Collective. */
int hs_bricks_checkpoint_collect(struct handshake *hs, struct err *e);
long hs_bricks_checkpoint_total(const struct handshake *hs);
long hs_bricks_checkpoint_offset(const struct handshake *hs);
int hs_bricks_read_points(struct handshake *hs, struct ckpt *ck, long n, struct err *e);

/* The most copies, over all ranks, whose point another rank held, at any
 * neighbour-list rebuild so far (a diagnostic: the all-to-all of the
 * copies' rows ran when it is not 0). */
long hs_bricks_remote_copies_max(const struct handshake *hs);

/* The MPM grid's shared-node sums (mpm_bricks_shared_counts): the most
 * nodes a rank shares, the plans made.  Collective. */
void hs_bricks_shared_counts(const struct handshake *hs, long *nodes_max, long *plans);

void hs_bricks_free(struct handshake *hs);

/* One region I atom's row for the MPM (handshake_step.c): position wrapped
 * into the grid, velocity, stress (eV/Å^3). */
void handshake_region_I_row(const struct handshake *hs, int i, double x[3], double v[3],
                            double s[6]);

/* The row of this rank's material point with local index q (see
 * HS_LINK_ROW). */
void handshake_point_row(const struct handshake *hs, long q, double row[HS_LINK_ROW]);

#endif
