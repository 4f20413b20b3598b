/*
 * md_settings: the `md` section of a case, read by one function for every
 * case type that runs MD, with one table of defaults.
 *
 *   md:
 *     timestep: 0.001          ps
 *     steps: 1000
 *     temperature: 0           K, Maxwell-Boltzmann initial velocities (0: at rest)
 *     skin: 1.0                Å, neighbour-list skin
 *     max_energy_change: 1.0   eV/atom: an NVE run whose total energy moves
 *                              more than this has diverged
 *     max_displacement: 0.1    largest step of the fastest atom, as a
 *                              fraction of the nearest-neighbour distance
 *     thermostat: {style: none | berendsen | langevin, temperature, tau}
 *
 * A case type names the keys it accepts (MD_KEY_* bits; any other key in
 * `md` is an error) and may change a default only by declaring its own
 * copy of md_settings_defaults next to its reader, e.g. the cluster impact:
 *     struct md_settings def = md_settings_defaults;
 *     def.steps = 10000;   -- 10 ps, the paper's run
 * `cascade-solver resolve` shows every value used.
 */
#ifndef CASCADE_MD_SETTINGS_H
#define CASCADE_MD_SETTINGS_H

#include "core/thermostat.h"
#include "util/cfg.h"

enum md_key {
    MD_KEY_TIMESTEP = 1u << 0,
    MD_KEY_STEPS = 1u << 1,
    MD_KEY_TEMPERATURE = 1u << 2,
    MD_KEY_SKIN = 1u << 3,
    MD_KEY_MAX_ENERGY_CHANGE = 1u << 4,
    MD_KEY_MAX_DISPLACEMENT = 1u << 5,
    MD_KEY_THERMOSTAT = 1u << 6,
};

struct md_settings {
    double timestep;            /* ps */
    long steps;
    double temperature;         /* K */
    double skin;                /* Å */
    double max_energy_change;   /* eV/atom */
    double max_displacement;    /* fraction of the nearest-neighbour distance */
    struct thermostat thermostat;
};

extern const struct md_settings md_settings_defaults;

/* Read the `md` section of root: the keys in `keys`, defaults from def. */
int md_settings_read(struct cfg_obj *root, unsigned keys, const struct md_settings *def,
                     struct md_settings *out);

#endif
