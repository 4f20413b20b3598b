/*
 * displacement: displacements of particles from a reference configuration,
 * averaged over slabs of material (reference regions of a wave-speed
 * measurement, Chen 2014 Sec. 4.1.1) or over bins along a bar
 * (displacement profiles, Chen 2014 Fig. 8).
 *
 * The reference (unwrapped) position of every particle is stored as the
 * per-particle field "x_ref", so it travels with the particle through
 * spatial sorts and is selected by where the material was (Lagrangian
 * regions), not by where it is now.
 */
#ifndef CASCADE_DISPLACEMENT_H
#define CASCADE_DISPLACEMENT_H

#include <stdint.h>

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

/* Record the current unwrapped positions as the reference; returns the
 * field index (>= 0) or -1 with e set.  Calling again resets the reference. */
int displacement_begin(struct particles *p, const struct box *b, struct err *e);

/* Mean displacement along `axis` (Å) of the owned particles whose reference
 * coordinate along `axis` lies in [lo, hi) and whose mask has no bit of
 * `exclude`; *count (may be NULL) gets their number.  NAN when empty. */
double displacement_slab_mean(const struct particles *p, const struct box *b, int field, int axis,
                              double lo, double hi, uint32_t exclude, long *count);

/* Profile: out[k] = mean displacement along `axis` of the particles whose
 * reference coordinate lies in [origin + k w, origin + (k+1) w), k < nbins;
 * NAN for empty bins. */
void displacement_profile(const struct particles *p, const struct box *b, int field, int axis,
                          double origin, double w, int nbins, uint32_t exclude, double *out);

/* The sums behind displacement_profile: sum[k] of the displacements and
 * cnt[k] of the particles of bin k (for sums over the ranks of a brick
 * decomposition before the division). */
void displacement_profile_sums(const struct particles *p, const struct box *b, int field,
                               int axis, double origin, double w, int nbins, uint32_t exclude,
                               double *sum, double *cnt);

#endif
