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
 *   - the material points of regions II and III feel friction alone, on
 *     their velocity relative to the coarse field v_c (the bridging-scale
 *     split of Wagner & Liu 2003, u = N u_nodes + u'): v_c = N_H (M_H^-1
 *     N_H^T m v), the lumped projection of the points' and region I's
 *     momenta on a grid of cell H = coarse_cell lattice constants with
 *     linear shape functions, interpolated back to the point:
 *         v_p <- v_c + c (v_p - v_c)
 *     Region I's instantaneous thermal stress and momentum drive the grid
 *     at every step; without a sink the band's motion would heat without
 *     bound.  What the friction removes is the part of the points' motion
 *     that a grid of cell H does not carry: at the default H = a (the
 *     finest cell of the usual layouts) a wave of 2 a keeps 6 % of its
 *     mean square in v_c and is damped almost in full, one of 8 a keeps
 *     79 %, one of 40 a 99 % (tests/test_handshake_bath.c), so a wave the
 *     MPM carries passes the band nearly undamped.  (By Jensen's
 *     inequality the projection holds no more kinetic energy than the
 *     points and atoms it is made of.)  coarse_cell = 0 is the friction of earlier
 *     versions, on the points' whole velocity (v_c = 0): it damps the
 *     coarse waves crossing the band as well, so an impact's energy goes
 *     into the bath rather than into the MPM beyond (docs/handshake.md, At
 *     a temperature, which gives both);
 *
 * tau = 0 switches the bath off (region II then moves by MD alone, tied to
 * the MPM only through its neighbours): the control the bath is measured
 * against (it heats without bound).  The random numbers are keyed on (seed, step, particle id), so
 * runs are independent of thread count and restart bitwise.
 *
 * Checkpoints (handshake_checkpoint_write) store the heat, its part taken
 * from region II's atoms and the step; v_c is recomputed at every step.
 *
 * On MPI bricks (handshake_bricks.h) the copies of region II are the
 * owning rank's particles and the bath acts on each rank's own (keyed on
 * id: the serial draws), with the velocity of its point from the copy's
 * row (the point may be on another rank); the friction acts on each
 * rank's points.  Both parts of the heat are summed over the ranks, so
 * t->heat is the same on every rank.  The coarse field is the sum over
 * the ranks of each rank's deposit of its points and region I atoms.
 *
 * Energy account: the bath's heat is the kinetic energy it takes out of
 * region II and the band's points, net of what its noise puts in, summed
 * over the steps.
 */
#ifndef CASCADE_HANDSHAKE_THERMAL_H
#define CASCADE_HANDSHAKE_THERMAL_H

#include <stdint.h>

#include "util/cfg.h"
#include "util/err.h"

struct handshake;

struct hs_thermal {
    double temperature;    /* K */
    double damping_time;   /* ps; 0: no bath */
    double coarse_cell;    /* lattice constants: the grid of the coarse field v_c the
                              band's friction spares; 0: friction on the whole velocity */
    uint64_t seed;
    double heat;           /* eV: net energy the bath took out so far */
    double heat_copies;    /* eV: the part of it taken from region II's atoms (the
                              rest from the band's points) */
    long step;             /* bath steps taken (the key of the random stream) */
};

/* The default damping time (ps) and coarse cell (lattice constants),
 * measured in docs/handshake.md. */
#define HS_THERMAL_DAMPING_TIME 0.1
#define HS_THERMAL_COARSE_CELL 1.0

/* Tie the bath to a built and connected handshake: hs->thermal = t, the
 * copies of region II leave the MD's frozen set and take their points'
 * velocities plus Maxwell-Boltzmann velocities at `t_init` K. */
void hs_thermal_attach(struct handshake *hs, struct hs_thermal *t, double t_init);

/* The bath on region II and the band's points: one step of md->dt (above);
 * adds what it took out to t->heat.  Called by handshake_advance_mpm
 * after region I's gather and before the MPM step, i.e. after the
 * previous step's second kick.  Collective on bricks.  Fails only when out
 * of memory. */
int hs_thermal_bath(struct handshake *hs, struct err *e);

/* The coarse velocity field v_c (above) at every material point of regions
 * II and III (zero at the others): *out is a new array of 3 per point,
 * which the caller frees.  H is the coarse cell in Å.  Serially region I
 * is taken from the MD as it is; on bricks from the rows gathered for the
 * MPM (hs->xI, vI, mI: region I of every rank), which must be current. */
int hs_thermal_coarse_velocity(const struct handshake *hs, double H, double **out,
                               struct err *e);

/* Kinetic energy (eV) and temperature (K, 3 N degrees of freedom) of the
 * MD particles whose mask has all bits of `all` and none of `none`; on
 * bricks over every rank's (collective). */
void hs_thermal_group(const struct handshake *hs, uint32_t all, uint32_t none, double *ke,
                      double *temperature, long *count);

/* Maxwell-Boltzmann velocities at T (K) on the MD particles with none of
 * the bits `none`, keyed on (seed, id): the same draw whatever the order. */
void hs_thermal_velocities(struct handshake *hs, double T, uint64_t seed, uint32_t none);

#endif
