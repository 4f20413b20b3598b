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

/* A dataset of the last snapshot of /collection in out/fields.h5. */
static double *last_snapshot(const char *out, const char *collection, const char *dataset,
                             long *n)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/fields.h5", th_temp_dir(), out);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert_geq(f, 0, "cannot open %s", path);
    hid_t g = H5Gopen2(f, collection, H5P_DEFAULT);
    cr_assert_geq(g, 0, "%s has no /%s", path, collection);
    H5G_info_t info;
    H5Gget_info(g, &info);
    cr_assert_gt(info.nlinks, 0);
    char name[64];
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, info.nlinks - 1, name, sizeof name,
                       H5P_DEFAULT);
    hid_t s = H5Gopen2(g, name, H5P_DEFAULT);
    hid_t ds = H5Dopen2(s, dataset, H5P_DEFAULT);
    cr_assert_geq(ds, 0, "%s: no %s/%s/%s", path, collection, name, dataset);
    hid_t sp = H5Dget_space(ds);
    hssize_t np = H5Sget_simple_extent_npoints(sp);
    double *d = malloc((size_t)np * sizeof *d);
    cr_assert_geq(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d), 0);
    H5Sclose(sp);
    H5Dclose(ds);
    H5Gclose(s);
    H5Gclose(g);
    H5Fclose(f);
    *n = (long)np;
    return d;
}

/* The material points of the last snapshot and profile.csv, restarted
 * against uninterrupted (th_kill_and_restart compares the rest). */
static void assert_same_points_and_profile(const char *const *kills)
{
    for (int k = 0; kills[k]; k++) {
        char out[32];
        snprintf(out, sizeof out, "killed-%s", kills[k]);
        for (int d = 0; point_fields[d]; d++) {
            long na, nb;
            double *a = last_snapshot("full", "points", point_fields[d], &na);
            double *b = last_snapshot(out, "points", point_fields[d], &nb);
            cr_assert_eq(na, nb);
            cr_assert_eq(memcmp(a, b, (size_t)na * sizeof *a), 0,
                         "points: last snapshot's %s differs after a kill at step %s",
                         point_fields[d], kills[k]);
            free(a);
            free(b);
        }
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
