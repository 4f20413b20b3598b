/*
 * The handshake bar case types on MPI bricks (docs/parallel.md, "How the
 * handshake bar cases run on bricks"; docs/handshake.md "Under MPI"): the
 * MD atoms of the bar and the MD copies of regions II and III on the MD
 * engine's bricks, the MPM (hierarchical grid included) whole on every
 * rank, region I reaching it in id order (couple/handshake_bricks.h), and
 * every sum the cases take over the atoms -- energies, the stress profile's
 * MD slabs (hence the probes and the front and window analyses), the
 * packet's halves, the temperatures and the bath's heat -- over the ranks.
 *
 * Each case runs 100 steps serially and under `mpirun --oversubscribe` on
 * 1 (bricks asked for), 2 and 4 ranks: the thermo series, the metrics, the
 * last stress profile, every MD particle of the last snapshot (by id) and
 * every material point agree with the serial run to REL of each quantity's
 * scale.  The MD force sums run in another order on bricks and region I
 * enters the MPM's mapping in id order, the MD slabs' sums run over the
 * ranks: the last bits differ, the arithmetic is otherwise the serial one.
 * Checkpoints of the step wave and the packet written on 2 ranks restart
 * serially and on 4 ranks and end where the uninterrupted serial run ends.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10

#define CU                                                                                        \
    "crystal: {element: Cu, a_min: 3.5, a_max: 3.7}\n"                                            \
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"

/* A step wave into a short bar whose loaded end is regions II and III of
 * the right interface, so that the MD feels the load within 100 steps; one
 * level of coarse cells on the left (the hierarchical grid). */
static const char *const wave_yaml =
    "title: step wave on bricks\n"
    "type: handshake_wave\n" CU
    "handshake: {levels: 1, fine: 4}\n"
    "bar: {mpm: [8, 4], md: 12, width: 4}\n"
    "load: {traction: 0.5}\n"
    "md: {timestep: 0.002, steps: 100}\n"
    "probes: {every: 10}\n"
    "profile: {every: 50}\n"
    "output: {thermo_every: 10, snapshot_every: 100%s}\n"
    "parallel: {decomposition: bricks}\n";

/* The quasi-static bar: the load ramped, damping on both sides. */
static const char *const static_yaml =
    "title: static bar on bricks\n"
    "type: handshake_static\n" CU
    "handshake: {levels: 1, fine: 4}\n"
    "bar: {mpm: [8, 4], md: 12, width: 4}\n"
    "load: {traction: 0.5, ramp: 0.1}\n"
    "damping: 0.5\n"
    "md: {timestep: 0.002, steps: 100}\n"
    "profile: {every: 50}\n"
    "output: {thermo_every: 10, snapshot_every: 100%s}\n"
    "parallel: {decomposition: bricks}\n";

/* Packets from the MD into a uniform half-constant grid, started as near
 * the band as the case allows (6 sigma beyond region I) so that the left
 * one reaches it within the 100 steps of 3 fs, measured at step 100; a bar
 * 3 cells wide is cut along x only. */
static const char *const packet_yaml =
    "title: packets on bricks\n"
    "type: handshake_packet\n" CU
    "bar: {mpm: [16, 0], md: 46, width: 3}\n"
    "packet: {sigma: 1, center: 8, fixed: 2}\n"
    "measure_time: 0.3\n"
    "md: {timestep: 0.003, steps: 100}\n"
    "profile: {every: 50}\n"
    "output: {thermo_every: 10, snapshot_every: 100%s}\n"
    "parallel: {decomposition: bricks}\n";

/* An MD region at 300 K: 20 steps under the Langevin thermostat, then 80
 * with the bath on region II alone. */
static const char *const thermal_yaml =
    "title: thermal bar on bricks\n"
    "seed: 5\n"
    "type: handshake_thermal\n" CU
    "elastic: {c11: 164.20, c12: 119.25, c44: 68.27}\n"
    "handshake: {levels: 1, fine: 4}\n"
    "bar: {mpm: [8, 8], md: 12, width: 4}\n"
    "thermal: {temperature: 300, lattice_constant: 3.63176, equilibrate: 0.04, block: 0.02}\n"
    "md: {timestep: 0.002, steps: 80}\n"
    "profile: {every: 50}\n"
    "output: {thermo_every: 10, snapshot_every: 100%s}\n"
    "parallel: {decomposition: bricks}\n";

static const char *write_case(int slot, const char *name, const char *fmt, const char *extra)
{
    static char yaml[8][4096];
    snprintf(yaml[slot], sizeof yaml[slot], fmt, extra);
    return th_write_temp(slot, name, yaml[slot]);
}

/* Metrics that agree to REL of the larger of their magnitude and `scale`
 * (energies relative to the perfect crystal are differences of sums of
 * about -3.5 eV an atom: their round-off scales with the atoms). */
static void compare_scaled(const char *a, const char *b, const char *const *names, double scale,
                           const char *tag)
{
    json_t *ra = thb_result(a), *rb = thb_result(b);
    for (int k = 0; names[k]; k++) {
        double x = thb_metric(ra, names[k]), y = thb_metric(rb, names[k]);
        cr_assert(isfinite(x) && isfinite(y), "%s %s: %g vs %g", tag, names[k], x, y);
        cr_assert_leq(fabs(x - y), REL * fmax(fabs(x), scale), "%s %s: %.17g vs %.17g", tag,
                      names[k], x, y);
    }
    json_decref(ra);
    json_decref(rb);
}

/* /series/<col> of two runs agree to REL of the larger of the column's
 * largest magnitude and floor[k] (a stress probe that only starts to rise
 * within the 100 steps is compared on the load's scale: its per-atom
 * virials, of order GPa, cancel in the slab sums). */
static void compare_series_floor(const char *a, const char *b, const char *const *cols,
                                 const double *floor, double cohesive, const char *tag)
{
    /* sums of per-atom potential energies above the crystal's: on the scale
     * of the atoms' cohesive energy, as the metrics */
    static const char *const pe_sums[] = {"md_pe_eV", "etotal_eV", "md_left_eV", "md_right_eV",
                                          NULL};
    double least[32];
    int n = 0;
    for (; cols[n]; n++) {
        cr_assert_lt(n, 31, "%s: more series columns than the test holds", tag);
        least[n] = floor ? floor[n] : 0;
        for (int k = 0; pe_sums[k]; k++)
            if (strcmp(cols[n], pe_sums[k]) == 0)
                least[n] = fmax(least[n], cohesive);
    }
    thb_compare_series_floor(a, b, cols, least, REL, tag);
}

/* A dataset of two runs' fields.h5, element by element in the stored
 * order, to REL of its largest magnitude (the profiles' slabs are in the
 * same order on every rank count). */
static void compare_dataset(const char *a, const char *b, const char *name, const char *tag)
{
    long na, nb;
    double *x = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &na);
    double *y = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &nb);
    cr_assert_eq(na, nb, "%s %s: %ld vs %ld values", tag, name, na, nb);
    cr_assert_gt(na, 0, "%s %s", tag, name);
    double scale = 0;
    for (long i = 0; i < na; i++)
        scale = fmax(scale, fabs(x[i]));
    for (long i = 0; i < na; i++)
        cr_assert_leq(fabs(x[i] - y[i]), REL * scale, "%s %s [%ld]: %.17g vs %.17g", tag, name, i,
                      x[i], y[i]);
    free(x);
    free(y);
}

static const char *const counts[] = {"atoms",  "atoms_region_I",       "points",
                                     "points_region_II", "points_region_III",
                                     "copies_region_II_III", "nodes", "steps_done", NULL};
static const char *const energies[] = {"md_ke", "md_pe", "mpm_ke", "mpm_strain_energy", "etotal",
                                       NULL};

/* What every bar case writes: the thermo series (to REL of each column's
 * scale, at least floor[k]), the counts exactly, the energies, the last
 * stress profile (the cases that write one), the MD particles by id and
 * the points. */
static void compare_bar(const char *a, const char *b, const char *const *cols,
                        const double *floor, int profile, const char *tag)
{
    json_t *r = thb_result(a);
    double scale = 3.5 * thb_metric(r, "atoms");   /* eV: the atoms' cohesive energy */
    json_decref(r);
    compare_series_floor(a, b, cols, floor, scale, tag);
    thb_compare_metrics(a, b, counts, 0, tag);
    compare_scaled(a, b, energies, scale, tag);
    if (profile) {
        compare_dataset(a, b, "/profiles/00000100/stress", tag);
        compare_dataset(a, b, "/profiles/00000100/displacement_x", tag);
    }
    static const char *const sets[] = {"position", "velocity", "stress", NULL};
    static const int ncomp[] = {3, 3, 6};
    thb_compare_snapshot(a, b, "/particles/00000100", sets, ncomp, REL, tag);
    /* the points by id: on bricks each rank writes the rows it holds */
    thb_compare_snapshot(a, b, "/points/00000100", sets, ncomp, REL, tag);
}

/* The far MD probe and the MPM probes beyond the left interface hold
 * round-off (1e-13 GPa) until the front arrives, after these 100 steps:
 * compared through the profile instead. */
static const char *const wave_cols[] = {"md_ke_eV",  "md_pe_eV",  "mpm_ke_eV", "mpm_strain_eV",
                                        "etotal_eV", "sxx_probe_md1_GPa", NULL};

static void compare_wave(const char *a, const char *b, const char *tag)
{
    static const double floor[] = {0, 0, 0, 0, 0, 0.5};   /* GPa: the traction */
    compare_bar(a, b, wave_cols, floor, 1, tag);
}

static const char *const static_cols[] = {"md_ke_eV", "md_pe_eV", "mpm_ke_eV", "mpm_strain_eV",
                                          "etotal_eV", NULL};

static void compare_static(const char *a, const char *b, const char *tag)
{
    compare_bar(a, b, static_cols, NULL, 1, tag);
    /* deviations relative to the traction and mean stresses (GPa) on the
     * scale of the 0.5 GPa load */
    static const char *const m[] = {"stress_deviation_md", "stress_deviation_mpm", "sxx_md_mean",
                                    "sxx_mpm_mean", NULL};
    compare_scaled(a, b, m, 1.0, tag);
    static const char *const k[] = {"kinetic_residual", NULL};
    compare_scaled(a, b, k, 0, tag);
}

static const char *const packet_cols[] = {"md_ke_eV",   "md_pe_eV",    "mpm_ke_eV",
                                          "etotal_eV",  "md_left_eV",  "md_right_eV",
                                          "mpm_eV",     NULL};

static void compare_packet(const char *a, const char *b, const char *tag)
{
    compare_bar(a, b, packet_cols, NULL, 1, tag);
    static const char *const m[] = {"packet_energy", "reference_energy", "reflected_energy", NULL};
    compare_scaled(a, b, m, 0, tag);
    /* what reached the MPM, on the packet's scale */
    json_t *r = thb_result(a);
    double scale = thb_metric(r, "packet_energy");
    json_decref(r);
    static const char *const t[] = {"transmitted_energy", NULL};
    compare_scaled(a, b, t, scale, tag);
}

static const char *const thermal_cols[] = {"md_ke_eV", "md_pe_eV", "mpm_ke_eV", "etotal_eV",
                                           "T_md_K",   "T_core_K", "T_region_II_K",
                                           "bath_heat_eV", NULL};

static void compare_thermal(const char *a, const char *b, const char *tag)
{
    compare_bar(a, b, thermal_cols, NULL, 0, tag);   /* writes no profile */
    static const char *const m[] = {"temperature_md_mean",     "temperature_core_mean",
                                    "temperature_region_II_mean", "temperature_block_first",
                                    "temperature_block_last",  NULL};
    compare_scaled(a, b, m, 0, tag);
    /* the bath's net heat is a sum of terms of both signs */
    static const char *const heat[] = {"bath_heat", NULL};
    compare_scaled(a, b, heat, 1.0, tag);
}

/* The case at path serially into TEMP/stem-serial, then on 1, 2 and 4
 * ranks (and 8 with upto8), each checked against it with its parallel
 * record (every MD particle, atoms and copies, on exactly one rank).  (The
 * packet's point stresses, a thousandth of the step wave's, differ from
 * the serial run's by more than 1e-10 of their largest on 8 ranks -- 2.4e-13
 * at a stress of 1.6e-3 when tried -- the node sums added in another
 * order: the packet stays at 4.) */
static void ranks_match_serial(const char *path, const char *stem, thb_check_fn check,
                               const char *moved_metric, double moved_min, int upto8)
{
    char d0[600], dk[600], tag[96];
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), stem);
    thb_must_run(path, 0, d0, NULL);
    json_t *r = thb_result(d0);
    /* the comparison is of a bar whose MD moved */
    double moved = thb_metric(r, moved_metric);
    cr_assert_gt(fabs(moved), moved_min, "%s: %s = %g", stem, moved_metric, moved);
    long nmd = (long)(thb_metric(r, "atoms") + thb_metric(r, "copies_region_II_III"));
    json_decref(r);
    static const int nps[] = {1, 2, 4, 8};
    for (int k = 0; k < (upto8 ? 4 : 3); k++) {
        snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), stem, nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        snprintf(tag, sizeof tag, "%s on %d ranks", stem, nps[k]);
        check(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], nmd);
    }
}

Test(bricks_handshake_bar, step_wave_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    ranks_match_serial(write_case(0, "wave.yaml", wave_yaml, ""), "wave", compare_wave, "md_ke",
                       1e-6, 1);
}

/* The step wave's bar with the cuts moved to the particles' quantiles
 * (parallel.balance: shift) after the material points were dealt out by
 * the bricks as first cut: the copies and atoms migrate, the points stay
 * (handshake_bricks.h). */
Test(bricks_handshake_bar, step_wave_with_shifted_cuts_matches_serial_on_1_2_4_ranks,
     .timeout = 900)
{
    char fmt[4096];
    const char *at = strstr(wave_yaml, "decomposition: bricks}");
    cr_assert_not_null(at);
    snprintf(fmt, sizeof fmt, "%.*sdecomposition: bricks, balance: shift}\n",
             (int)(at - wave_yaml), wave_yaml);
    ranks_match_serial(write_case(6, "wave_shift.yaml", fmt, ""), "wave-shift", compare_wave,
                       "md_ke", 1e-6, 0);
}

Test(bricks_handshake_bar, static_bar_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    ranks_match_serial(write_case(1, "static.yaml", static_yaml, ""), "static", compare_static,
                       "md_ke", 1e-7, 1);
}

Test(bricks_handshake_bar, packet_matches_serial_on_1_2_4_ranks, .timeout = 900)
{
    ranks_match_serial(write_case(2, "packet.yaml", packet_yaml, ""), "packet", compare_packet,
                       "transmitted_energy", 1e-12, 0);
}

Test(bricks_handshake_bar, thermal_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    ranks_match_serial(write_case(3, "thermal.yaml", thermal_yaml, ""), "thermal",
                       compare_thermal, "bath_heat", 1e-3, 1);
}

/* Checkpoints at step 50 written on 2 ranks restart serially and on 4
 * ranks; a serial one restarts on 2: each ends where the uninterrupted
 * serial run ends (the atoms and copies from the collective MD part, the
 * points from rank 0's copy, the probes and profile rows from the case's
 * group). */
static void checkpoints_move(const char *path, const char *stem, thb_check_fn check)
{
    char s1[600], m2[600];
    snprintf(s1, sizeof s1, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(m2, sizeof m2, "%s/%s-2", th_temp_dir(), stem);
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    check(s1, m2, "uninterrupted on 2 ranks");
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, check);
}

Test(bricks_handshake_bar, step_wave_checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoints_move(write_case(4, "wave_ck.yaml", wave_yaml, ", checkpoint_every: 50"), "wave-ck",
                     compare_wave);
}

Test(bricks_handshake_bar, packet_checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoints_move(write_case(5, "packet_ck.yaml", packet_yaml, ", checkpoint_every: 50"),
                     "packet-ck", compare_packet);
}

/* The thermal bar with the cuts moved during the run
 * (parallel.balance_every, threshold 1: at every check with any imbalance
 * left; checks ride on list builds, which the atoms' thermal motion brings
 * with a thin skin, while a 0 K bar may build its lists once): the atoms
 * and copies migrate at the checks, the material points stay where they
 * were dealt (handshake_bricks.h), and the run matches the serial one on
 * 1, 2 and 4 ranks; on 2 ranks the checks ran and moved the cuts. */
Test(bricks_handshake_bar, thermal_with_moving_cuts_matches_serial_on_1_2_4_ranks,
     .timeout = 900)
{
    /* a skin of 0.1 Å: the atoms' thermal motion rebuilds the lists every
     * few steps */
    char fmt[4096];
    const char *md = strstr(thermal_yaml, "md: {timestep: 0.002, steps: 80}");
    const char *at = strstr(thermal_yaml, "decomposition: bricks}");
    cr_assert(md && at);
    snprintf(fmt, sizeof fmt,
             "%.*smd: {timestep: 0.002, steps: 80, skin: 0.1}%.*sdecomposition: bricks, "
             "balance: shift, balance_every: 10, balance_threshold: 1.0}\n",
             (int)(md - thermal_yaml), thermal_yaml,
             (int)(at - md - strlen("md: {timestep: 0.002, steps: 80}")),
             md + strlen("md: {timestep: 0.002, steps: 80}"));
    ranks_match_serial(write_case(7, "thermal_every.yaml", fmt, ""), "thermal-every",
                       compare_thermal, "bath_heat", 1e-3, 0);
    char d2[600];
    snprintf(d2, sizeof d2, "%s/thermal-every-2", th_temp_dir());
    long checks = 0, shifts = 0;
    double worst = 0, end = thb_balance_record(d2, &checks, &shifts, &worst);
    cr_log_info("thermal bar on 2 ranks, balance_every 10: %ld checks, %ld shifts, max/mean "
                "%g at worst, %g at the end",
                checks, shifts, worst, end);
    cr_assert_geq(checks, 3, "%ld checks in 80 steps, every 10", checks);
    cr_assert_geq(shifts, 1, "%ld shifts at threshold 1", shifts);
}
