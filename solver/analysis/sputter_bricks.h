/*
 * sputter_bricks: the sputtered groups of sputter.h for atoms spread over
 * the ranks of a brick decomposition (core/halo.h), where a group -- the
 * target above all -- spans bricks.
 *
 * Each rank links the pairs of its frame (its own atoms and their ghosts)
 * closer than the connection cutoff (sputter_link).  A group is then
 * named by the smallest atom id in it, found by label propagation across
 * the brick faces: every atom starts with its id; each local group takes
 * the smallest label of its members (owned and ghosts), the owners' labels
 * go to their ghosts (halo_forward), and this repeats until no label
 * changes on any rank -- about as many rounds as bricks a group crosses.
 * A link between atoms of two ranks is in both ranks' frames (each end is
 * a ghost of the other's rank when the ghosts reach the cutoff), so at
 * the fixed point linked atoms hold the same label and every group its
 * smallest id.  Each rank sums size, mass, momentum and lowest height of
 * its own atoms per label; rank 0 merges these short tables (one row per
 * group a rank touches), judges the groups (sputter_judge) and broadcasts
 * the counts and the labels of the groups that left.
 *
 * The counts equal sputter_find's over all atoms.  Two differences, both
 * at round-off or ties: the group sums are added per rank, then over the
 * ranks (only the sign of the momentum is used), and of two largest
 * groups of equal size the one with the smaller id is the target
 * (sputter_find: the one whose first atom comes first).
 */
#ifndef CASCADE_SPUTTER_BRICKS_H
#define CASCADE_SPUTTER_BRICKS_H

#include "analysis/frame.h"
#include "analysis/sputter.h"
#include "core/halo.h"
#include "core/particles.h"

/* q: this rank's atoms (owned first, ghosts from h within at least
 * p->cutoff of every owned atom); f: the frame of all of q's particles
 * (owned and ghosts as frame entries 0..n_owned+n_ghost); mass: of q's
 * owned particles.  state[i] (SPUTTER_*) for q's owned particles; *out is
 * the same on every rank.  Collective. */
int sputter_find_bricks(struct halo *h, struct particles *q, const struct frame *f,
                        const double *mass, const struct sputter_params *p, unsigned char *state,
                        struct sputter_stats *out, struct err *e);

#endif
