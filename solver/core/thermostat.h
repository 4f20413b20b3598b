/*
 * thermostat: temperature control of particle dynamics (MD and DPD).
 *
 *   none        NVE
 *   berendsen   velocities scaled by sqrt(1 + dt/tau (T0/T - 1)) each step
 *               (Berendsen et al., J. Chem. Phys. 81, 3684 (1984))
 *   langevin    F += -m v / damp + sqrt(2 m kB T0 / (damp dt)) R, with R
 *               standard normal drawn from a stream keyed on (seed, step,
 *               particle id), so independent of threads and order
 */
#ifndef CASCADE_THERMOSTAT_H
#define CASCADE_THERMOSTAT_H

#include <stdint.h>

#include "core/particles.h"
#include "util/cfg.h"

enum thermostat_style { THERMOSTAT_NONE, THERMOSTAT_BERENDSEN, THERMOSTAT_LANGEVIN };

struct thermostat {
    enum thermostat_style style;
    double temperature;   /* K */
    double tau;           /* ps: Berendsen time constant or Langevin damping time */
    uint32_t group_mask;  /* particles it acts on (default: all) */
};

int thermostat_read(struct cfg_obj *o, struct thermostat *t);

/* Langevin forces added to p->f (owned particles). */
void thermostat_langevin_forces(const struct thermostat *t, struct particles *p, double dt,
                                uint64_t seed, long step);
/* Berendsen rescaling after the step; T is the current temperature. */
void thermostat_berendsen_rescale(const struct thermostat *t, struct particles *p, double dt,
                                  double T);

#endif
