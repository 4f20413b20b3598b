/*
 * md_timestep: refuse a time step that velocity Verlet cannot integrate.
 *
 * The Einstein frequency omega_E of the actual configuration is measured by
 * displacing a few atoms (md_einstein_frequency).  The highest phonon
 * frequency of a close-packed crystal is about sqrt(2) omega_E, and Verlet
 * is unstable for dt > 2 / omega_max, so dt > sqrt(2) / omega_E is refused
 * with the bound in the message; dt above a tenth of the shortest period
 * 2 pi / omega_max gets a warning on the log.
 */
#ifndef CASCADE_MD_TIMESTEP_H
#define CASCADE_MD_TIMESTEP_H

#include "md/md.h"
#include "util/cfg.h"

/* `path` names the time-step key for the message. */
int md_check_timestep(struct md *md, struct cfg *c, const char *path);

/* Fast projectiles (Guo & Yang 2005, section 3.2: "the changing of atom
 * positions at one step is at least one magnitude smaller than the
 * equilibrium atom spacing"): refuse a time step with which the fastest
 * owned particle moves more than `frac` times the nearest-neighbour
 * distance `dnn` (Å) per step.  The message names the speed, the step
 * length and the largest acceptable time step. */
int md_check_displacement(const struct md *md, double dnn, double frac, struct cfg *c,
                          const char *path);

/* The interaction range against the box and the particle limit (the
 * case's system.max_particles), before md_init builds anything: refuses
 * what md_range_ok refuses with max_ghosts = max_particles.  The message
 * goes to `path` (the potential's file or cutoff key, or md.skin). */
int md_check_range(const struct potential *pot, const struct box *b, long n, double skin,
                   long max_particles, struct cfg *c, const char *path);

#endif
