/*
 * Checkpoint and restart of the DPD case types (engine/model_dpd.c): a run
 * killed with SIGKILL at an exact step and restarted from its newest
 * checkpoint ends bitwise where the uninterrupted run (with the same
 * checkpoints) ends -- every metric and series point of result.json, every
 * thermo row, and the last snapshot's positions, velocities, forces and
 * per-particle fields compared with ==.  One kill between output steps,
 * one on a thermo + snapshot + checkpoint step.
 *
 * What has to carry over: the pair sweep's random numbers are keyed on
 * (seed, step, pair ids), so the step counter suffices; the DPDE internal
 * energies are a particle field; the free flyer's velocity, the grips'
 * forces and the case's accumulators (samples, profiles, stress-strain
 * points, CNA start counts, thermo rows) are stored; ghosts and lists are
 * rebuilt at every checkpoint in both runs (the sweep's pair order).
 */
#include <criterion/criterion.h>

#include "helpers/th.h"
#include "helpers/th_restart.h"

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.1\nc: 39.0\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\nmass: 508.368\n"    \
    "atoms_per_particle: 8\nlattice_constant: 7.23\n"

static const char *const dpde_fields[] = {"position", "velocity", "force", "u_internal", NULL};

/* DPDE flyer/target impact with its reference run (two DPD models of one
 * case, canonical lists), the free flyer, profiles, CNA: 160 steps. */
Test(restart_dpd, dpde_impact_with_reference_continues_bitwise, .timeout = 300)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *yaml = "type: dpd_impact\n"
                       "seed: 5\n"
                       "system:\n"
                       "  lattice: {style: fcc, a: 7.05, cells: [10, 3, 3]}\n"
                       "  element: Cu\n"
                       "  boundary: [free, periodic, periodic]\n"
                       "dpd: {parameters: cg.yaml, variant: dpde, gamma: 0.5, steps: 160,\n"
                       "      initial_temperature: 300}\n"
                       "impact: {regions: [20.0, 45.0], sample_every: 2, profile_times: [0.4],\n"
                       "         reference: true}\n"
                       "output: {thermo_every: 20, snapshot_every: 60, checkpoint_every: 30}\n";
    static const char *const fields[] = {"position", "velocity", "force", "u_internal",
                                         "structure", NULL};
    /* 70: between outputs (continues from 60); 120: thermo, snapshot and
     * checkpoint step */
    const char *const kills[] = {"70", "120", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", fields);
}

/* Isothermal DPD with the Berendsen thermostat on a periodic crystal (the
 * equilibration of Chen 2014 Sec. 4.1.1), spatially sorted storage. */
Test(restart_dpd, dpd_berendsen_continues_bitwise, .timeout = 300)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *yaml = "type: dpd\n"
                       "seed: 9\n"
                       "system: {lattice: {style: fcc, a: 7.23, cells: [4, 4, 4]}, element: Cu}\n"
                       "dpd: {parameters: cg.yaml, variant: dpd, gamma: 2.0, steps: 200,\n"
                       "      temperature: 298, initial_temperature: 600,\n"
                       "      thermostat: {style: berendsen, temperature: 298, tau: 0.2}}\n"
                       "output: {thermo_every: 25, snapshot_every: 100, checkpoint_every: 40,\n"
                       "         final_state: final.data}\n";
    static const char *const fields[] = {"position", "velocity", "force", NULL};
    const char *const kills[] = {"130", "200", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", fields);
}

/* DPDE tensile rod: prescribed grips, the stress-strain points averaged
 * over sample_every steps across the checkpoint. */
Test(restart_dpd, dpde_tensile_continues_bitwise, .timeout = 300)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *yaml = "type: dpd_tensile\n"
                       "seed: 4\n"
                       "system:\n"
                       "  lattice: {style: fcc, a: 7.23, cells: [10, 3, 3]}\n"
                       "  element: Cu\n"
                       "  boundary: [free, free, free]\n"
                       "dpd: {parameters: cg.yaml, variant: dpde, gamma: 0.5, steps: 160,\n"
                       "      initial_temperature: 200}\n"
                       "tensile: {velocity: 1.0, sample_every: 7}\n"
                       "output: {thermo_every: 20, snapshot_every: 60, checkpoint_every: 30}\n";
    const char *const kills[] = {"70", "120", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", dpde_fields);
}
