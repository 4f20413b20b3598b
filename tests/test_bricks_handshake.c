/*
 * The cluster impact with the MPM/MD handshake boundary on MPI bricks
 * (docs/parallel.md, docs/handshake.md "Under MPI"): the MD atoms and the
 * MD copies of regions II and III are decomposed like any MD system, the
 * MPM layers are whole on every rank, and region I reaches the MPM of
 * every rank in id order (solver/couple/handshake_bricks.h).
 *
 * A Cu14 cluster at 4 km/s into a 6 x 6 x 5-cell Cu(001) target in 6
 * lattice constants of MPM (720 target atoms, 672 of them in region I,
 * 6336 copies, 7070 MD particles), 100 steps of 1 fs: the thermo series,
 * the metrics (damage counts, MPM energy, coupled energy) and the atoms of
 * the last snapshot agree with the serial run to REL on 1, 2, 4 and 8
 * ranks.  The MD force sums and region I's order in the MPM's mapping run
 * in another order than serially, so the numbers differ in the last bits
 * (measured: 1e-13 and below of the total energy, the MPM energy equal to
 * the 12 printed digits); the MPM step itself is the same arithmetic on
 * every rank count once region I is in id order.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10

/* Brick faces of 2, 4 and 8 ranks cut the impact point, region I and the
 * band of copies (the box is the target plus the copies' 14.5 Å shell). */
static const char *const hs_yaml =
    "title: Cu14 into a handshake target on bricks\n"
    "seed: 1\n"
    "type: cluster_impact\n"
    "target:\n"
    "  lattice: fcc\n"
    "  element: Cu\n"
    "  a: 3.615\n"
    "  cells: [6, 6, 5]\n"
    "  boundary: handshake\n"
    "  handshake: {mpm: 6, fine: 4, levels: 1, layer: 4}\n"
    "cluster: {atoms: 14, speed: 4, gap: 2}\n"
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
    "md: {timestep: 0.001, steps: 100}\n"
    "analysis: {every: 20, structure: {method: fixed}}\n"
    "output: {thermo_every: 10, snapshot_every: 50%s}\n"
    "parallel: {decomposition: bricks}\n";

static const char *const thermo_cols[] = {"pe_eV",   "ke_eV",   "etotal_eV", "temp_K",
                                          "press_GPa", "pxx_GPa", "pyy_GPa",   "pzz_GPa",
                                          NULL};

static const char *const metrics_rel[] = {
    "atoms",           "target_atoms",       "cluster_atoms",       "atoms_region_I",
    "copies_region_II_III", "mpm_points",    "mpm_nodes",           "time",
    "displaced_peak",  "displaced_peak_time", "displaced_final",    "sputtered_atoms",
    "crater_depth",    "temperature",        "mpm_energy",          "mpm_kinetic_energy",
    "coupled_energy_initial", "coupled_energy_final", "energy_account_final", NULL};

static void compare_hs(const char *a, const char *b, const char *tag)
{
    thb_compare_series(a, b, thermo_cols, REL, tag);
    thb_compare_metrics(a, b, metrics_rel, REL, tag);
    /* a difference of two total energies of about -2.4e4 eV, to REL of them */
    json_t *ra = thb_result(a), *rb = thb_result(b);
    double ea = thb_metric(ra, "energy_absorbed"), eb = thb_metric(rb, "energy_absorbed");
    cr_assert_leq(fabs(ea - eb), REL * 2.4e4, "%s energy_absorbed %.17g vs %.17g", tag, ea, eb);
    json_decref(ra);
    json_decref(rb);
    /* every MD particle, copies of regions II and III included */
    static const char *const sets[] = {"position", "velocity", NULL};
    static const int ncomp[] = {3, 3};
    thb_compare_snapshot(a, b, "/particles/00000100", sets, ncomp, REL, tag);
}

static const char *write_case(const char *name, const char *extra_output)
{
    static char yaml[4096];
    snprintf(yaml, sizeof yaml, hs_yaml, extra_output);
    return th_write_temp(0, name, yaml);
}

/* The serial run, then 1 (bricks asked for), 2, 4 and 8 ranks; the copies
 * are spread over the ranks (the parallel record counts every particle
 * once). */
Test(bricks_handshake, cu14_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    const char *path = write_case("hs.yaml", "");
    char d0[600], dk[600];
    snprintf(d0, sizeof d0, "%s/hs-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    /* the comparison is of an impact whose waves reach the MPM */
    json_t *r = thb_result(d0);
    cr_assert_gt(thb_metric(r, "displaced_peak"), 20, "displaced peak %g",
                 thb_metric(r, "displaced_peak"));
    cr_assert_gt(thb_metric(r, "mpm_energy"), 0.05, "the MPM took %g eV",
                 thb_metric(r, "mpm_energy"));
    long natoms = (long)thb_metric(r, "atoms");
    cr_assert_eq(natoms, 720 + 14 + 6336);
    cr_assert_eq((long)thb_metric(r, "atoms_region_I"), 672);
    json_decref(r);
    static const int nps[] = {1, 2, 4, 8};
    for (int k = 0; k < 4; k++) {
        snprintf(dk, sizeof dk, "%s/hs-%d", th_temp_dir(), nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        char tag[64];
        snprintf(tag, sizeof tag, "handshake impact on %d ranks", nps[k]);
        compare_hs(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], natoms);
    }
}

/* A checkpoint written on 2 ranks at step 50 restarts serially and on 4
 * ranks, and a serial one on 2: each ends where the uninterrupted serial
 * run does (the MPM points from the checkpoint's rank-0 copy, the atoms and
 * copies from the collective MD part). */
Test(bricks_handshake, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    const char *path = write_case("hs_ck.yaml", ", checkpoint_every: 50");
    char s1[600], m2[600];
    snprintf(s1, sizeof s1, "%s/hs-ck-serial", th_temp_dir());
    snprintf(m2, sizeof m2, "%s/hs-ck-2", th_temp_dir());
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    compare_hs(s1, m2, "uninterrupted 2 ranks");
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, compare_hs);
}

/* The thermal handshake (a Langevin bath on region II) is not decomposed:
 * asked for bricks it is refused naming the case file, line and key;
 * under `auto` every rank runs the whole case, with a note. */
Test(bricks_handshake, thermal_handshake_is_refused_on_bricks, .timeout = 300)
{
    static char out[16384];
    const char *hs =
        "type: cluster_impact\n"
        "seed: 1\n"
        "target:\n"
        "  lattice: fcc\n"
        "  element: Cu\n"
        "  a: 3.615\n"
        "  cells: [6, 6, 5]\n"
        "  boundary: handshake\n"
        "  handshake: {mpm: 6, fine: 4, levels: 1, layer: 4, thermal: {damping_time: 0.1}}\n"
        "cluster: {atoms: 14, speed: 2}\n"
        "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
        "md: {timestep: 0.002, steps: 2}\n"
        "analysis: {every: 1, structure: {method: fixed}}\n"
        "output: {thermo_every: 1, snapshot_every: 0, hdf5: false}\n"
        "parallel:\n"
        "  decomposition: bricks\n";
    const char *path = th_write_temp(0, "hs_thermal.yaml", hs);
    char dir[600];
    snprintf(dir, sizeof dir, "%s/hs-thermal-2", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "hs_thermal.yaml:16:") && strstr(out, "parallel.decomposition") &&
                  strstr(out, "target.handshake.thermal (the Langevin bath on region II) is not "
                              "decomposed into bricks"),
              "%s", out);
    char autoy[2048];
    snprintf(autoy, sizeof autoy, "%s", hs);
    char *p = strstr(autoy, "decomposition: bricks");
    cr_assert(p);
    memcpy(p, "decomposition: auto  ", 21);
    path = th_write_temp(0, "hs_thermal_auto.yaml", autoy);
    snprintf(dir, sizeof dir, "%s/hs-thermal-auto-2", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 0, "%s", out);
    cr_assert(strstr(out, "note: target.handshake.thermal (the Langevin bath on region II) is "
                          "not decomposed into bricks: each of the 2 ranks runs the whole case"),
              "%s", out);
}
