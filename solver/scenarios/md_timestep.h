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

#endif
