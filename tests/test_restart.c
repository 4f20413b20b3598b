/*
 * Checkpoint and restart (engine/sim.h, output/checkpoint.h).
 *
 * The promise: a run killed with SIGKILL at any step and restarted from its
 * newest checkpoint ends in the same state as the uninterrupted run, bitwise
 * on the same thread count -- every metric of result.json, every thermo row,
 * and the positions, velocities and forces of the last snapshot compared
 * with ==, not with a tolerance.  The kill comes from the solver itself
 * (CASCADE_SOLVER_KILL_AT_STEP) so that it lands on an exact step: one
 * between output steps and one on an output step.
 *
 * And the refusals: a checkpoint of another case (job key), of another
 * format version, a truncated and a corrupted file, each named in the
 * message; checkpoints asked of a case type that cannot write them.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/th.h"
#include "helpers/th_restart.h"

static const char *const md_fields[] = {"position", "velocity", "force", NULL};

/* EAM copper with a Langevin thermostat: the random forces are keyed on
 * (seed, step, atom id), so the stream continues exactly. */
Test(restart, md_eam_langevin_continues_bitwise, .timeout = 300)
{
    const char *yaml = "seed: 7\n"
                       "system: {lattice: {style: fcc, a: 3.615, cells: [4, 4, 4]}, element: Cu}\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md:\n"
                       "  timestep: 0.002\n"
                       "  steps: 300\n"
                       "  temperature: 600\n"
                       "  thermostat: {style: langevin, temperature: 500, tau: 0.1}\n"
                       "output: {thermo_every: 25, snapshot_every: 100, checkpoint_every: 40}\n";
    /* 130: between output and checkpoint steps; 200: a snapshot, thermo
     * and checkpoint step */
    const char *const kills[] = {"130", "200", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
}

static const char *md_case = "seed: 3\n"
                             "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                             "element: Cu}\n"
                             "potential: {style: sutton_chen}\n"
                             "md: {timestep: 0.002, steps: 60, temperature: 300}\n"
                             "output: {checkpoint_every: 20, hdf5: false}\n";

static const char *checkpoint_path(const char *out, long step)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s/checkpoint-%010ld.h5", th_temp_dir(), out, step);
    return path;
}

Test(restart, keeps_the_newest_two_checkpoints)
{
    const char *path = th_write_temp(1, "case.yaml", md_case);
    char msg[4096];
    cr_assert_eq(th_restart_solve("ck", path, NULL, NULL, msg, sizeof msg), 0, "%s", msg);
    struct stat sb;
    cr_assert_eq(stat(checkpoint_path("ck", 20), &sb), 0, "checkpoint of step 20 missing");
    cr_assert_eq(stat(checkpoint_path("ck", 40), &sb), 0, "checkpoint of step 40 missing");
    /* the last step needs none: the run is complete */
    cr_assert_neq(stat(checkpoint_path("ck", 60), &sb), 0);
}

Test(restart, refuses_another_case_version_truncated_and_corrupt)
{
    const char *path = th_write_temp(1, "case.yaml", md_case);
    char msg[4096];
    cr_assert_eq(th_restart_solve("ck", path, "50", NULL, msg, sizeof msg), 128 + SIGKILL, "%s", msg);
    /* another case: the job key differs */
    const char *other = th_write_temp(2, "other.yaml",
                                      "seed: 4\n"
                                      "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                                      "element: Cu}\n"
                                      "potential: {style: sutton_chen}\n"
                                      "md: {timestep: 0.002, steps: 60, temperature: 300}\n"
                                      "output: {checkpoint_every: 20, hdf5: false}\n");
    char ck40[512];
    snprintf(ck40, sizeof ck40, "%s", checkpoint_path("ck", 40));
    int rc = th_restart_solve("other", other, NULL, ck40, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, ck40) && strstr(msg, "checkpoint of another case"), "%s", msg);

    /* another format version */
    char copy[512];
    snprintf(copy, sizeof copy, "%s/v99.h5", th_temp_dir());
    long n;
    char *bytes = th_restart_slurp(ck40, &n);
    FILE *f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n, f);
    fclose(f);
    hid_t h = H5Fopen(copy, H5F_ACC_RDWR, H5P_DEFAULT);
    cr_assert_geq(h, 0);
    hid_t a = H5Aopen(h, "version", H5P_DEFAULT);
    double v = 99;
    H5Awrite(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
    H5Fclose(h);
    rc = th_restart_solve("v", path, NULL, copy, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "v99.h5") && strstr(msg, "format version 99"), "%s", msg);

    /* truncated: half the file */
    snprintf(copy, sizeof copy, "%s/half.h5", th_temp_dir());
    f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n / 2, f);
    fclose(f);
    rc = th_restart_solve("half", path, NULL, copy, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "half.h5") && strstr(msg, "corrupt"), "%s", msg);

    /* corrupt: bytes flipped inside the particle data (checksummed) */
    snprintf(copy, sizeof copy, "%s/flip.h5", th_temp_dir());
    for (long k = n / 2; k < n / 2 + 64; k++)
        bytes[k] ^= 0x5a;
    f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n, f);
    fclose(f);
    rc = th_restart_solve("flip", path, NULL, copy, msg, sizeof msg);
    cr_assert_neq(rc, 0, "a corrupted checkpoint was accepted: %s", msg);
    cr_assert(strstr(msg, "flip.h5"), "%s", msg);
    free(bytes);

    /* a directory without checkpoints */
    char empty[512];
    snprintf(empty, sizeof empty, "%s/empty", th_temp_dir());
    mkdir(empty, 0755);
    rc = th_restart_solve("e", path, NULL, empty, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "no checkpoint-*.h5 file"), "%s", msg);
}

Test(restart, checkpoints_refused_for_a_case_type_off_the_engine)
{
    const char *path = th_write_temp(1, "case.yaml",
                                      "type: crystal\n"
                                      "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                                      "element: Cu}\n"
                                      "potential: {style: sutton_chen}\n"
                                      "output: {checkpoint_every: 20}\n");
    const char *argv[] = {th_solver(), "check", path, NULL};
    char msg[4096];
    int rc = th_run(argv, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "case.yaml:4:") && strstr(msg, "output.checkpoint_every") &&
                  strstr(msg, "does not write checkpoints"),
              "%s", msg);
}

/* A cluster impact on a target with fixed and Langevin-damped layers: the
 * damage analysis (displaced peak, sputter, crater series) and the thermo
 * rows continue exactly. */
Test(restart, cluster_impact_continues_bitwise, .timeout = 300)
{
    const char *yaml = "seed: 1\n"
                       "type: cluster_impact\n"
                       "target: {lattice: fcc, element: Cu, a: 3.615, cells: [10, 10, 7], "
                       "damped_thickness: 4.0}\n"
                       "cluster: {atoms: 14, speed: 10.0}\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {timestep: 0.001, steps: 120}\n"
                       "analysis: {every: 20}\n"
                       "output: {thermo_every: 30, snapshot_every: 60, checkpoint_every: 25}\n";
    const char *const kills[] = {"55", "90", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
}

/* The same impact with the MD target inside MPM layers (the handshake
 * boundary): the material points, the handshake's counters and the atoms
 * all continue exactly. */
Test(restart, cluster_impact_with_handshake_boundary_continues_bitwise, .timeout = 300)
{
    const char *yaml = "seed: 1\n"
                       "type: cluster_impact\n"
                       "target: {lattice: fcc, element: Cu, a: 3.615, cells: [10, 10, 8], "
                       "temperature: 0, boundary: handshake,\n"
                       "         handshake: {mpm: 6, regions: [2, 2, 2], cell: 1, fine: 4, "
                       "levels: 1, coarsen: xyz, layer: 2}}\n"
                       "cluster: {atoms: 14, speed: 10.0}\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {timestep: 0.001, steps: 60}\n"
                       "analysis: {every: 20, structure: {method: fixed}}\n"
                       "output: {thermo_every: 10, snapshot_every: 30, checkpoint_every: 20}\n";
    const char *const kills[] = {"45", "30", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", md_fields);
}

static void key_of(const char *yaml, char *key, size_t len)
{
    const char *path = th_write_temp(3, "key.yaml", yaml);
    const char *argv[] = {th_solver(), "resolve", "--key", path, NULL};
    char out[4096];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    snprintf(key, len, "%.16s", out);
}

/* Asking for no checkpoints keeps the job key a case had before
 * checkpoints existed (a campaign does not rerun its jobs); asking for
 * them makes another job, since the extra neighbour rebuilds change
 * round-off. */
Test(restart, checkpoint_setting_and_the_job_key)
{
    char k0[32], k1[32], k2[32];
    key_of("md: {steps: 10}\npotential: {style: sutton_chen}\n"
           "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n",
           k0, sizeof k0);
    key_of("md: {steps: 10}\npotential: {style: sutton_chen}\n"
           "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n"
           "output: {checkpoint_every: 0}\n",
           k1, sizeof k1);
    key_of("md: {steps: 10}\npotential: {style: sutton_chen}\n"
           "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, element: Cu}\n"
           "output: {checkpoint_every: 5}\n",
           k2, sizeof k2);
    cr_assert_str_eq(k0, k1);
    cr_assert_str_neq(k0, k2);
}

/* A checkpoint whose checksums hold but whose values no run can have: a
 * NaN position, a duplicated atom id.  Each is refused naming the file
 * and the dataset. */
Test(restart, refuses_nonfinite_and_duplicate_values_in_a_checkpoint)
{
    const char *path = th_write_temp(1, "case.yaml", md_case);
    char msg[4096];
    cr_assert_eq(th_restart_solve("ck", path, "50", NULL, msg, sizeof msg), 128 + SIGKILL, "%s",
                 msg);
    long n;
    char *bytes = th_restart_slurp(checkpoint_path("ck", 40), &n);
    const char *names[] = {"nan.h5", "dup.h5"};
    char copy[2][512];
    for (int k = 0; k < 2; k++) {
        snprintf(copy[k], sizeof copy[k], "%s/%s", th_temp_dir(), names[k]);
        FILE *f = fopen(copy[k], "wb");
        fwrite(bytes, 1, (size_t)n, f);
        fclose(f);
    }
    free(bytes);
    double nan = NAN;
    th_ckpt_poke(copy[0], "/model/md/atoms/x", H5T_NATIVE_DOUBLE, &nan);
    int64_t id2 = 2;   /* the first stored atom (not id 2 in this run) takes id 2 */
    th_ckpt_poke(copy[1], "/model/md/atoms/id", H5T_NATIVE_INT64, &id2);
    int rc = th_restart_solve("nan", path, NULL, copy[0], msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "nan.h5: checkpoint model/md/atoms/x/v/f: a non-finite position"), "%s",
              msg);
    rc = th_restart_solve("dup", path, NULL, copy[1], msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "dup.h5: checkpoint model/md/atoms/id: id 2 given twice"), "%s", msg);
}
