/*
 * velocity: initial velocities.  Maxwell-Boltzmann at T from a seeded GSL
 * generator, drawn in particle-id order (so the same seed gives the same
 * velocities whatever the storage order), total momentum removed, then
 * scaled to exactly T with 3N-3 degrees of freedom.
 *
 * On a brick decomposition each rank holds only its own particles; the
 * k-th draw still goes to the k-th id of all ranks (each rank runs through
 * the sequence up to its last id), so the velocities are the serial ones
 * to round-off (the momentum and temperature sums are summed over ranks).
 */
#ifndef CASCADE_VELOCITY_H
#define CASCADE_VELOCITY_H

#include <stdint.h>

#include "core/particles.h"
#include "util/err.h"

struct halo;

/* Only particles whose mask intersects group_mask get velocities. */
int velocity_maxwell(struct particles *p, double T, uint64_t seed, uint32_t group_mask,
                     struct err *e);
/* The same over the particles of all ranks of h (NULL: this set alone);
 * collective when h is given. */
int velocity_maxwell_split(struct particles *p, double T, uint64_t seed, uint32_t group_mask,
                           const struct halo *h, struct err *e);

#endif
