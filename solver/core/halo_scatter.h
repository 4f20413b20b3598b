/*
 * halo_scatter: a particle set that rank 0 alone built (a data or XYZ file
 * it read and checked, input/md_system.c) sent to the other ranks in
 * blocks, so that no other rank ever holds the whole set.
 *
 *   halo_scatter_header   the box and the set's type table and fields from
 *                         rank 0 to every rank (an empty set there), and the
 *                         count of rank 0's particles;
 *   halo_scatter          rank 0's particles to their owners, a block of
 *                         HALO_SCATTER_BLOCK at a time in the set's order:
 *                         with a brick decomposition each rank receives the
 *                         particles of its brick only (its peak memory: its
 *                         brick plus one block) and rank 0 then drops those
 *                         that are not its own; without one (replicated
 *                         data) every rank receives every particle.
 *
 * The order within a rank is rank 0's order, as halo_distribute keeps it,
 * so a run is the one every rank reading the file whole gave.
 */
#ifndef CASCADE_HALO_SCATTER_H
#define CASCADE_HALO_SCATTER_H

#include "core/box.h"
#include "core/halo.h"
#include "core/parallel.h"
#include "core/particles.h"
#include "util/err.h"

/* particles per block, as a checkpoint's blocked read (output/checkpoint_split.c):
 * 2.8 MB of MD records (168 bytes each, core/halo_pack.h) */
#define HALO_SCATTER_BLOCK 16384

/* *b and p's types, masses and fields from rank 0 to every rank (p holds
 * no particle there); *n: rank 0's owned count, on every rank.  Collective. */
int halo_scatter_header(const struct parallel *par, struct particles *p, struct box *b, long *n,
                        struct err *e);

/* Rank 0's n owned particles of p to the ranks (above); h NULL: to every
 * rank.  Collective; a failure on any rank (memory) fails every rank.  The
 * caller counts the bricks' particles (halo_adopt). */
int halo_scatter(const struct parallel *par, struct halo *h, struct particles *p, long n,
                 struct err *e);

#endif
