/*
 * handshake_thermal: the MPM/MD handshake at a finite temperature, which
 * Guo & Yang (2005) leave as future work (Conclusions: "thermalised
 * material points", the MPM at the MD temperature).
 *
 * At 0 K the MD copies of regions II and III sit where their material
 * points are (displacement coupling, handshake.h).  A lattice at T carries
 * thermal vibrations at wavelengths down to two planes, which the grid
 * cannot represent: a smooth (cold) region II is a cold wall next to
 * region I, the MD region's heat leaks into it and the short waves of an
 * impact reflect from it or vanish in the mapping.  Here, when a thermal
 * section is given:
 *
 *   - the material points are set on the lattice at a(T), the lattice
 *     constant of zero mean pressure at T, with the elastic constants at T
 *     (type: elastic gives both), so that an MD region at T and the MPM
 *     around it are both stress-free;
 *   - region I hands the grid its full virial stress, kinetic part
 *     included (at 0 K the kinetic part is left out; at T it is the
 *     thermal pressure, n kB T = 0.35 GPa for Cu at 300 K, which the
 *     velocity mapping does not carry: its mean nodal momentum is zero);
 *   - the MD copies of region II become atoms: the MD integrates them,
 *     and a Langevin bath at T acts on their velocity relative to their
 *     material point's, v - v_p (Ornstein-Uhlenbeck step after the MD
 *     kick, exact in dt):
 *         v <- v_p + c (v - v_p) + sqrt((1 - c^2) kB T / m) R,  c = exp(-dt/tau)
 *     so the coarse motion that the MPM carries is not damped, while the
 *     fine-scale motion, which the MPM cannot carry, is absorbed and
 *     replaced by thermal noise at T: region I sees a thermal neighbour
 *     and the short waves leave the MD into a bath instead of reflecting.
 *     Region III stays on its material points (it is region II's
 *     atmosphere; region I does not see it);
 *   - the material points of regions II and III feel friction alone,
 *     v_p <- c v_p: the MPM carries the mean field, and region I's
 *     instantaneous thermal stress drives the grid at every step, whose
 *     modes would otherwise heat without bound.  (It damps the coarse
 *     waves crossing the band as well: an impact's energy goes into the
 *     bath rather than into the MPM beyond; docs/handshake.md, Limits.)
 *
 * tau = 0 switches the bath off (region II then moves by MD alone, tied to
 * the MPM only through its neighbours): the control the bath is measured
 * against (it heats without bound).  The random numbers are keyed on (seed, step, particle id), so
 * runs are independent of thread count and restart bitwise.
 *
 * Checkpoints (handshake_checkpoint_write) store the heat and the step.
 *
 * Energy account: the bath's heat is the kinetic energy it takes out of
 * region II and the band's points, net of what its noise puts in, summed
 * over the steps.
 */
#ifndef CASCADE_HANDSHAKE_THERMAL_H
#define CASCADE_HANDSHAKE_THERMAL_H

#include <stdint.h>

#include "util/cfg.h"

struct handshake;

struct hs_thermal {
    double temperature;    /* K */
    double damping_time;   /* ps; 0: no bath */
    uint64_t seed;
    double heat;           /* eV: net energy the bath took out so far */
    long step;             /* bath steps taken (the key of the random stream) */
};

/* The default damping time (ps), measured in docs/handshake.md. */
#define HS_THERMAL_DAMPING_TIME 0.1

/* Tie the bath to a built and connected handshake: hs->thermal = t, the
 * copies of region II leave the MD's frozen set and take their points'
 * velocities plus Maxwell-Boltzmann velocities at `t_init` K. */
void hs_thermal_attach(struct handshake *hs, struct hs_thermal *t, double t_init);

/* The bath on region II and the band's points: one step of md->dt (above);
 * adds what it took out to t->heat.  Called by handshake_advance_mpm
 * before the MPM step, i.e. after the previous step's second kick. */
void hs_thermal_bath(struct handshake *hs);

/* Kinetic energy (eV) and temperature (K, 3 N degrees of freedom) of the
 * MD particles whose mask has all bits of `all` and none of `none`. */
void hs_thermal_group(const struct handshake *hs, uint32_t all, uint32_t none, double *ke,
                      double *temperature, long *count);

/* Maxwell-Boltzmann velocities at T (K) on the MD particles with none of
 * the bits `none`, keyed on (seed, id): the same draw whatever the order. */
void hs_thermal_velocities(struct handshake *hs, double T, uint64_t seed, uint32_t none);

#endif
