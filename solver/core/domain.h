/*
 * domain: the particle bookkeeping every particle engine (md/, dpd/) does
 * before it builds its neighbour list: drop the ghosts, wrap the owned
 * particles into the box, now and then reorder them along a space-filling
 * walk of link cells (neighbours close in memory), and rebuild the
 * periodic-image ghosts out to the list range.
 */
#ifndef CASCADE_DOMAIN_H
#define CASCADE_DOMAIN_H

#include "core/box.h"
#include "core/particles.h"
#include "core/timers.h"
#include "util/err.h"

/* range: list cutoff plus skin (Å).  sort_now: reorder the owned particles
 * (bins of half the range).  The ghost build is timed as TIMER_COMM when
 * timers is not NULL. */
int domain_rebuild(struct particles *p, struct box *b, double range, int sort_now,
                   struct timers *timers, struct err *e);

/* A fixed order of the owned particles, restored after they migrate
 * between bricks (models whose particle kinds sit in blocks, the DPD/MPM
 * coupling): perm[k] = index of the particle that goes to position k. */
typedef int (*domain_order_fn)(void *ctx, const struct particles *p, int *perm, struct err *e);

/* domain_rebuild without the spatial sort, the owned particles put in
 * order(ctx) after the migration and before the ghosts are built. */
int domain_rebuild_ordered(struct particles *p, struct box *b, double range,
                           domain_order_fn order, void *ctx, struct timers *timers,
                           struct err *e);

#endif
