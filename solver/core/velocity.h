/*
 * velocity: initial velocities.  Maxwell-Boltzmann at T from a seeded GSL
 * generator, drawn in particle-id order (so the same seed gives the same
 * velocities whatever the storage order), total momentum removed, then
 * scaled to exactly T with 3N-3 degrees of freedom.
 */
#ifndef CASCADE_VELOCITY_H
#define CASCADE_VELOCITY_H

#include <stdint.h>

#include "core/particles.h"
#include "util/err.h"

/* Only particles whose mask intersects group_mask get velocities. */
int velocity_maxwell(struct particles *p, double T, uint64_t seed, uint32_t group_mask,
                     struct err *e);

#endif
