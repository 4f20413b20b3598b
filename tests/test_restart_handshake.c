/*
 * Checkpoint and restart of the MPM/MD handshake case types (engine/
 * model_handshake.c): a run killed with SIGKILL at an exact step and
 * restarted from its newest checkpoint ends bitwise where the
 * uninterrupted run ends -- every metric, every thermo row, every row of
 * profile.csv, and the last snapshot of both the MD particles (atoms and
 * the copies of regions II and III) and the material points.  One kill
 * between output steps, one on a snapshot, profile, thermo and checkpoint
 * step.  Small bars, so that each test takes seconds.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_restart.h"

static const char *const md_fields[] = {"position", "velocity", "force", "pe", "stress", "region",
                                        NULL};
static const char *const point_fields[] = {"position", "displacement", "velocity", "stress",
                                           "volume", NULL};

/* The material points of the last snapshot and profile.csv, restarted
 * against uninterrupted (th_kill_and_restart compares the rest). */
static void assert_same_points_and_profile(const char *const *kills)
{
    for (int k = 0; kills[k]; k++) {
        char out[32];
        snprintf(out, sizeof out, "killed-%s", kills[k]);
        th_restart_assert_same_snapshot("full", out, "points", point_fields);
        char pa[512], pb[512];
        snprintf(pa, sizeof pa, "%s/full/profile.csv", th_temp_dir());
        snprintf(pb, sizeof pb, "%s/%s/profile.csv", th_temp_dir(), out);
        char *ta = th_restart_slurp(pa, NULL), *tb = th_restart_slurp(pb, NULL);
        cr_assert_gt(strlen(ta), 1000);
        cr_assert_str_eq(ta, tb, "profile.csv differs after a kill at step %s", kills[k]);
        free(ta);
        free(tb);
    }
}

#define CU                                                                                        \
    "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"                                            \
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"

/* The step wave on a short bar: the front crosses the MD region between
 * the checkpoints. */
Test(restart_handshake, step_wave_continues_bitwise, .timeout = 600)
{
    const char *yaml = "type: handshake_wave\n" CU
                       "bar: {mpm: [16, 16], md: 12, width: 4}\n"
                       "load: {traction: 0.5}\n"
                       "md: {timestep: 0.002, steps: 400}\n"
                       "probes: {every: 10}\n"
                       "profile: {every: 100}\n"
                       "output: {thermo_every: 20, snapshot_every: 100, checkpoint_every: 40}\n";
    /* 130: between outputs and checkpoints; 200: a thermo, snapshot,
     * profile and checkpoint step */
    const char *const kills[] = {"130", "200", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
    assert_same_points_and_profile(kills);
}

/* The quasi-static bar: damping on both sides and the load ramp (the MPM's
 * clock) straddle the checkpoints. */
Test(restart_handshake, damped_static_bar_continues_bitwise, .timeout = 600)
{
    const char *yaml = "type: handshake_static\n" CU
                       "handshake: {levels: 1, fine: 6}\n"
                       "bar: {mpm: [16, 16], md: 16, width: 4}\n"
                       "load: {traction: 0.5, ramp: 0.5}\n"
                       "damping: 0.5\n"
                       "md: {timestep: 0.002, steps: 300}\n"
                       "profile: {every: 100}\n"
                       "output: {thermo_every: 50, snapshot_every: 100, checkpoint_every: 40}\n";
    const char *const kills[] = {"130", "200", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
    assert_same_points_and_profile(kills);
}

/* The packets, measured at step 100: the measured energies come from the
 * checkpoint in the restarted runs. */
Test(restart_handshake, packet_measurement_survives_restart, .timeout = 600)
{
    const char *yaml = "type: handshake_packet\n" CU
                       "bar: {mpm: [16, 0], md: 46, width: 3}\n"
                       "packet: {sigma: 1, center: 14, fixed: 2}\n"
                       "measure_time: 0.1\n"
                       "md: {steps: 300}\n"
                       "profile: {every: 100}\n"
                       "output: {thermo_every: 50, snapshot_every: 100, checkpoint_every: 40}\n";
    const char *const kills[] = {"130", "200", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
    assert_same_points_and_profile(kills);
}
