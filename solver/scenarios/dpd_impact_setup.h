/*
 * dpd_impact_setup: what the flyer/target case types share (Chen et al.
 * 2014, Sec. 4.1.1 and 4.2) -- the `impact` section, the rigid flyer built
 * in front of the target bar, and a copy of a particle set for reference
 * runs.  Used by dpd_impact (DPD-only) and by the DPD/MPM-grid and
 * concurrent DPD/MPM case types (dpd_mpm_impact_case.c).
 *
 *   impact:
 *     axis: x                   propagation axis; the flyer comes from below
 *     flyer_thickness: 15.0     Å: (100) planes of the flyer, round(15 / (a/2)) = 4
 *     flyer_velocity: 5.0       Å/ps toward the target
 *     flyer_motion: free        free: a rigid body that the target slows down;
 *                               prescribed: a piston at constant velocity
 *     lattice_constant: 0       Å of the flyer (0: the parameter file's)
 *     gap: 0.0                  Å added to one plane spacing between flyer and target
 *     regions: [100.0, 150.0]   Å: centres of the reference regions from the impact face
 *     region_thickness: 6.0     Å
 *     arrival_threshold: 0.01   Å of impact-caused displacement (analysis/wave_arrival.h)
 *     reference: true           also run the target without the flyer
 *     sample_every: 1           steps between displacement samples
 *     profile_times: []         ps: displacement profiles along the bar at these times
 *     profile_bin: 0            Å: profile bin width (0: the plane spacing a/2)
 */
#ifndef CASCADE_DPD_IMPACT_SETUP_H
#define CASCADE_DPD_IMPACT_SETUP_H

#include "core/particles.h"
#include "scenarios/dpd_bar.h"
#include "util/cfg.h"

#define DPD_FLYER_BIT (1u << 1)

struct dpd_impact_keys {
    int axis, motion, reference;   /* motion: 0 free, 1 prescribed */
    double thickness, velocity, a, gap, regions[2], half, threshold, bin;
    long sample_every;
    double *ptimes;                /* owned (free()) */
    size_t nptimes;
};

/* Read the `impact` section. */
int dpd_impact_keys_read(struct cfg_obj *root, struct dpd_impact_keys *k);

/* Append the flyer: (100) planes of an fcc lattice of constant a continuing
 * the target's stacking below its impact face, across the target's
 * cross-section, with mask DPD_FLYER_BIT; *nadded gets their number. */
int dpd_impact_add_flyer(struct particles *p, const struct dpd_bar *bar,
                         const struct dpd_impact_keys *k, double a, long *nadded, struct err *e);
/* The same on bricks (h; NULL: as above): p holds this rank's particles,
 * the face's stacking and the first id are taken over every rank, every
 * rank visits every flyer site and stores those of its brick, with the
 * ids of a serial build; *nadded gets the flyer's count over all ranks.
 * Collective when h is given. */
struct halo;
int dpd_impact_add_flyer_over(struct particles *p, const struct dpd_bar *bar,
                              const struct dpd_impact_keys *k, double a, const struct halo *h,
                              long *nadded, struct err *e);

/* A copy of the owned particles (positions, velocities, types, ids, masks,
 * image counts); NULL with e set when out of memory. */
struct particles *dpd_particles_clone(const struct particles *p, struct err *e);

#endif
