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
 *
 * The same target at 300 K with the Langevin bath on region II
 * (target.handshake.thermal, couple/handshake_thermal.h: the copies of
 * region II move by MD on the ranks that own them, the bath's draws are
 * keyed on id and step, its heat from the copies is summed over the
 * ranks, its coarse field takes region I from the gathered rows): 100
 * steps on 1, 2 and 4 ranks agree with the serial run to REL as well,
 * the bath's heat, region II's fine-scale energy and the target's
 * temperature included, and checkpoints move between 1 and 2 ranks.
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
    "  a: %s\n"
    "  cells: [6, 6, 5]\n"
    "  boundary: handshake\n"
    "%s"
    "cluster: {atoms: 14, speed: 4, gap: 2}\n"
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
    "md: {timestep: 0.001, steps: 100}\n"
    "analysis: {every: 20, structure: {method: fixed}}\n"
    "output: {thermo_every: 10, snapshot_every: 50%s}\n"
    "parallel: {decomposition: bricks%s}\n";

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

/* The target at 0 K, and at 300 K (a(300 K) and the constants at 300 K,
 * docs/handshake.md "At a temperature") with the bath. */
static const char *const hs_athermal = "  handshake: {mpm: 6, fine: 4, levels: 1, layer: 4}\n";
static const char *const hs_thermal =
    "  temperature: 300\n"
    "  handshake:\n"
    "    mpm: 6\n"
    "    fine: 4\n"
    "    levels: 1\n"
    "    layer: 4\n"
    "    elastic: {c11: 164.20, c12: 119.25, c44: 68.27}\n"
    "    thermal: {damping_time: 0.1, coarse_cell: 1, seed: 3}\n";

/* parallel: extra keys of the parallel section ("" none). */
static const char *write_target_on(const char *name, int thermal, const char *extra_output,
                                   const char *parallel)
{
    static char yaml[4096];
    snprintf(yaml, sizeof yaml, hs_yaml, thermal ? "3.63176" : "3.615",
             thermal ? hs_thermal : hs_athermal, extra_output, parallel);
    return th_write_temp(0, name, yaml);
}

static const char *write_target(const char *name, int thermal, const char *extra_output)
{
    return write_target_on(name, thermal, extra_output, "");
}

static const char *write_case(const char *name, const char *extra_output)
{
    return write_target(name, 0, extra_output);
}

/* Runs of the case at path on each of the n rank counts nps (into
 * TEMP/stem-N), each checked against the serial run in d0. */
static void ranks_match_serial(const char *path, const char *d0, const char *stem,
                               const int *nps, int n, long natoms, thb_check_fn check)
{
    char dk[600], tag[96];
    for (int k = 0; k < n; k++) {
        snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), stem, nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        snprintf(tag, sizeof tag, "%s on %d ranks", stem, nps[k]);
        check(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], natoms);
    }
}

/* The checkpoint tests' uninterrupted runs: serially into s1 and on 2
 * ranks into m2 (TEMP/stem-serial, TEMP/stem-2), which agree. */
static void serial_and_2_ranks(const char *path, const char *stem, char *s1, char *m2,
                               size_t len, thb_check_fn check)
{
    snprintf(s1, len, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(m2, len, "%s/%s-2", th_temp_dir(), stem);
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    check(s1, m2, "uninterrupted 2 ranks");
}

/* The serial run, then 1 (bricks asked for), 2, 4 and 8 ranks; the copies
 * are spread over the ranks (the parallel record counts every particle
 * once). */
Test(bricks_handshake, cu14_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    const char *path = write_case("hs.yaml", "");
    char d0[600];
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
    ranks_match_serial(path, d0, "hs", nps, 4, natoms, compare_hs);
}

/* A checkpoint written on 2 ranks at step 50 restarts serially and on 4
 * ranks, and a serial one on 2: each ends where the uninterrupted serial
 * run does (the MPM points from the checkpoint, each rank its share, the atoms and
 * copies from the collective MD part). */
Test(bricks_handshake, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    const char *path = write_case("hs_ck.yaml", ", checkpoint_every: 50");
    char s1[600], m2[600];
    serial_and_2_ranks(path, "hs-ck", s1, m2, sizeof s1, compare_hs);
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, compare_hs);
}

/* The thermal handshake's own metrics, to REL (the bath's heat and region
 * II's fine-scale energy are sums of terms of both signs: to REL of their
 * magnitude or of 1 eV, whichever is larger). */
static const char *const metrics_thermal[] = {"energy_account_initial", "target_temperature_final",
                                              NULL};

static void compare_thermal(const char *a, const char *b, const char *tag)
{
    compare_hs(a, b, tag);
    thb_compare_metrics(a, b, metrics_thermal, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    static const char *const sums[] = {"bath_heat", "region_II_fine_energy", NULL};
    for (int k = 0; sums[k]; k++) {
        double x = thb_metric(ra, sums[k]), y = thb_metric(rb, sums[k]);
        cr_assert_leq(fabs(x - y), REL * fmax(fabs(x), 1.0), "%s %s %.17g vs %.17g", tag, sums[k],
                      x, y);
    }
    json_decref(ra);
    json_decref(rb);
}

/* The target at 300 K with the bath: serially, then on 1 (bricks asked
 * for), 2 and 4 ranks. */
Test(bricks_handshake, thermal_cu14_matches_serial_on_1_2_4_ranks, .timeout = 900)
{
    const char *path = write_target("hs_th.yaml", 1, "");
    char d0[600];
    snprintf(d0, sizeof d0, "%s/hs-th-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    /* a hot target whose bath works: the bath takes heat, the MPM is driven */
    json_t *r = thb_result(d0);
    double T = thb_metric(r, "target_temperature_final");
    cr_assert(T > 150 && T < 900, "target at %g K", T);
    cr_assert_gt(fabs(thb_metric(r, "bath_heat")), 0.1, "bath heat %g eV",
                 thb_metric(r, "bath_heat"));
    cr_assert_gt(thb_metric(r, "mpm_energy"), 0.05, "the MPM took %g eV",
                 thb_metric(r, "mpm_energy"));
    long natoms = (long)thb_metric(r, "atoms");
    cr_assert_eq(natoms, 720 + 14 + 6336);
    json_decref(r);
    static const int nps[] = {1, 2, 4};
    ranks_match_serial(path, d0, "hs-th", nps, 3, natoms, compare_thermal);
}

/* A checkpoint of the thermal run written on 2 ranks at step 50 restarts
 * serially, and a serial one on 2 ranks: both end where the uninterrupted
 * serial run does (the bath's heat and step from the checkpoint, its
 * draws keyed on the step). */
Test(bricks_handshake, thermal_checkpoint_moves_between_1_and_2_ranks, .timeout = 900)
{
    const char *path = write_target("hs_th_ck.yaml", 1, ", checkpoint_every: 50");
    char s1[600], m2[600];
    serial_and_2_ranks(path, "hs-th-ck", s1, m2, sizeof s1, compare_thermal);
    const struct thb_restart cases[] = {{m2, 0, "thermal 2 to 1", NULL},
                                        {s1, 2, "thermal 1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 2, s1, compare_thermal);
}

/* Bricks across z (grid 1 x 1 x 2): the box's free top shrink-wraps as the
 * cluster comes down, so the cut moves, and copies of the side bands
 * migrate to the lower brick while their material points stay on the rank
 * they were dealt to: those copies' rows come by the all-to-all
 * (handshake_bricks.h).  The parallel record shows the points divided
 * over the ranks and such copies; the run matches the serial one, at 0 K
 * and with the bath at 300 K (which takes the points' velocities from the
 * same rows).  The grid's node sums went only between the two ranks' shared
 * nodes, fewer than half the grid's (solver/mpm/mpm_shared.h), and each
 * rank made the node tables of its particles' cells, not the grid's
 * (solver/mpm/mpm_hgrid.h). */
Test(bricks_handshake, copies_apart_from_their_points_match_serial, .timeout = 900)
{
    for (int thermal = 0; thermal < 2; thermal++) {
        const char *path = write_target_on(thermal ? "hs_zt.yaml" : "hs_z.yaml", thermal, "",
                                           ", grid: [1, 1, 2]");
        char s1[600], m2[600];
        serial_and_2_ranks(path, thermal ? "hs-zt" : "hs-z", s1, m2, sizeof s1,
                           thermal ? compare_thermal : compare_hs);
        json_t *r = thb_result(m2);
        json_t *par = json_object_get(r, "parallel");
        cr_assert_not_null(par);
        json_t *g = json_object_get(par, "grid");
        cr_assert_eq(json_integer_value(json_array_get(g, 2)), 2);
        long remote = (long)json_integer_value(json_object_get(par, "handshake_remote_copies_max"));
        cr_assert_gt(remote, 0, "no copy's point was on another rank (thermal %d)", thermal);
        long npts = (long)thb_metric(r, "mpm_points"), sum = 0;
        json_t *per = json_object_get(par, "mpm_points_per_rank");
        cr_assert_eq((long)json_array_size(per), 2);
        for (size_t k = 0; k < 2; k++) {
            long n = (long)json_integer_value(json_array_get(per, k));
            cr_assert(n > 0 && n < npts, "rank %zu holds %ld of %ld points", k, n, npts);
            sum += n;
        }
        cr_assert_eq(sum, npts, "points per rank add up to %ld, not %ld", sum, npts);
        /* the grid's sums went only between ranks that share nodes */
        long nodes = (long)thb_metric(r, "mpm_nodes");
        long shared = (long)json_integer_value(json_object_get(par, "mpm_shared_nodes_max"));
        cr_assert(shared > 0 && 2 * shared < nodes, "%ld of %ld nodes shared (thermal %d)",
                  shared, nodes, thermal);
        /* each rank made the node tables of its particles' cells only
         * (0.56 of the grid's at 0 K, 0.47 at 300 K when written) */
        thb_check_cell_tables(m2, 2, 0.7);
        json_decref(r);
    }
}

/* Dynamic balance with a handshake target (parallel.balance_every): the
 * MD's cuts move at the checks (threshold 1: at every check with any
 * imbalance left), the copies of regions II and III move with the atoms
 * while their material points stay on the ranks they were dealt to, and
 * their rows come by the all-to-all the copies apart from their points
 * already use.  The target at 300 K with the bath (its atoms' spread, and
 * so the cuts, change from check to check).  On 1 x 1 x 2 bricks the run
 * matches the serial one, and a checkpoint at step 50 (the cuts moved to
 * the stored atoms, in the continuing run too) restarts 2 to 2 with the
 * same thermo and the last snapshot's particles bit for bit (a restart
 * that kept the set-up's cuts differs), and 2 to 1 and 1 to 2 onto the
 * serial run. */
Test(bricks_handshake, dynamic_balance_matches_serial_and_restarts, .timeout = 900)
{
    const char *path = write_target_on("hs_dyn.yaml", 1, ", checkpoint_every: 50",
                                       ", grid: [1, 1, 2], balance: shift, balance_every: 10, "
                                       "balance_threshold: 1.0");
    char s1[600], m2[600];
    serial_and_2_ranks(path, "hs-dyn", s1, m2, sizeof s1, compare_thermal);
    long checks = 0, shifts = 0;
    thb_balance_record(m2, &checks, &shifts, NULL);
    cr_assert_geq(checks, 5, "%ld checks in 100 steps, every 10", checks);
    cr_assert_geq(shifts, 3, "%ld shifts at threshold 1", shifts);
    json_t *r = thb_result(m2);
    long remote = (long)json_integer_value(
        json_object_get(json_object_get(r, "parallel"), "handshake_remote_copies_max"));
    json_decref(r);
    cr_assert_gt(remote, 0, "no copy's point was on another rank");
    const struct thb_restart cases[] = {
        {m2, 2, "2 to 2", m2}, {m2, 0, "2 to 1", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, compare_thermal);
    char r0[700];
    snprintf(r0, sizeof r0, "%s/ck-restart-0", th_temp_dir());
    static const char *const sets[] = {"position", "velocity", NULL};
    static const int ncomp[] = {3, 3};
    thb_compare_snapshot(m2, r0, "/particles/00000100", sets, ncomp, 0.0, "2 to 2, bit for bit");
}
