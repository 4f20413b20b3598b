/*
 * The concurrent DPD/MPM impact (dpd_mpm_impact, Chen 2014 Sec. 4.2, Fig.
 * 8) on MPI bricks (docs/dpd_mpm.md "Under MPI", docs/parallel.md).  The
 * DPD particles of each run (target, flyer and the partners, the DPD
 * copies of the material points near the interface) are split over the
 * bricks of the DPD halo as in dpd_grid_impact
 * (tests/test_bricks_dpd_grid_impact.c), while the grid and the material
 * points are whole on every rank: every rank advances every point from
 * the summed nodes, the points' share of the nodes added once after the
 * sum, the partners found by id after every migration, their frozen
 * F'(rho) travelling with them, the reaction on the points (Eq. 3.1)
 * summed over the ranks.
 *
 * With no Shardlow sweep only the order of the sums changes: over 100
 * steps the thermo series, every metric and series of result.json, the
 * last snapshot of the DPD particles and of the material points (by id)
 * and the final state (gathered on rank 0, by id) agree with the serial
 * run to 1e-10 relative on 1, 2, 4 and 8 ranks (8 bricks along the bar,
 * oversubscribed); the energy-change metrics,
 * differences of nearly equal total energies, on the total energy's
 * scale (1e-10 of it), the total momentum's change (round-off) on the
 * flyer's momentum's; the CNA counts exactly.  A checkpoint written on 2
 * ranks restarts serially and on 4 (to the same tolerances) and on 2
 * (bitwise); a serial one restarts on 2.  `auto` takes bricks when the DPD
 * part is long enough, else replicated data (the serial run bitwise).
 * In those runs no partner crosses a brick face (the faces stay among
 * the DPD particles; result.json's parallel.partner_migrations says 0).
 * partners_cross_brick_faces_on_2_and_4_ranks places the faces among
 * the partners (partner_crossing_case): the flyer's advance moves the
 * faces across a plane of partners within the cutoff of the DPD
 * particles, the solver counts the partners that migrated (must be some:
 * measured 18 on 2 ranks, 36 on 4), and the runs agree with the serial
 * one to the same tolerances -- the lookup of the partners' points by id
 * after a migration and their frozen F'(rho) travelling with them, under
 * the interface forces.  (Checked that it can fail: zeroing an arriving
 * partner's frozen F'(rho) moves final positions by 5 Å, and the test
 * fails at the thermo series.)
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
#define PARTICLE_MASS 508.368   /* amu */
#define FLYER_VELOCITY 5.0      /* Å/ps, the default */

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

#define OUTPUT "output: {thermo_every: 10, snapshot_every: 50, final_state: final.xyz}\n"
#define OUTPUT_TEXT "output: {thermo_every: 10, snapshot_every: 50, final_state: final.data}\n"
#define OUTPUT_CK                                                                                 \
    "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 50, "                       \
    "final_state: final.xyz}\n"

/* A cells x 3 x 3-cell bar at 100 K, DPDE on a 4 Å grid: DPD particles
 * from the impact face to `iface` Å, material points (with partners)
 * beyond; the all-DPD comparison run and both reference runs make four
 * coupled simulations.  `steps` time steps of 5 fs, the rigid flyer at
 * the default 5 Å/ps. */
static void concurrent_case_with(char *buf, size_t len, int cells, double iface,
                                 const char *regions, double monitor, long steps,
                                 const char *output, const char *parallel,
                                 const char *impact_extra, const char *concurrent_extra)
{
    snprintf(buf, len,
             "type: dpd_mpm_impact\nseed: 3\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [%d, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, free, free]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: %ld\n"
             "  initial_temperature: 100\n"
             "impact:\n  regions: %s\n  sample_every: 3\n"
             "  arrival_threshold: 0.002\n  profile_times: [0.25]\n%s"
             "grid:\n  cell: 4.0\n"
             "concurrent:\n  dpd: [-10, %g]\n  mpm: [%g, 200]\n  monitor: %g\n%s"
             "%s%s",
             cells, steps, regions, impact_extra, iface, iface, monitor, concurrent_extra, output,
             parallel);
}

static void concurrent_case(char *buf, size_t len, int cells, double iface, const char *regions,
                            double monitor, long steps, const char *output, const char *parallel)
{
    concurrent_case_with(buf, len, cells, iface, regions, monitor, steps, output, parallel, "",
                         "");
}

/* The bricks case: a 25-cell bar (182 Å), 125 Å of DPD particles -- the
 * DPD halo (with the partners, 33.5 Å deep into the points, and the
 * flyer) is then 143.6 Å long, enough for 8 bricks of the 17.3 Å
 * interaction range along the bar (its 16 Å cross-section takes one
 * brick; a 24-cell bar with 120 Å of DPD particles gives 136.3 Å, too
 * short for 8); regions 8 and 26 Å from the face (both reached in the
 * 0.5 ps).  810 DPD particles in the flyer run (630 of the target, the 72
 * of the flyer, 108 partners), 270 material points. */
static void bricks_case(char *buf, size_t len, const char *output, const char *parallel)
{
    concurrent_case(buf, len, 25, 125, "[8.0, 26.0]", 15, 100, output, parallel);
}
#define BRICKS_N 810
#define FLYER_N 72

/* The wave across the interface: a 12-cell bar with 20 Å of DPD
 * particles, region 2 at 26 Å among the material points (too short a DPD
 * part for more than 2 bricks). */
static void crossing_case(char *buf, size_t len, const char *output, const char *parallel)
{
    concurrent_case(buf, len, 12, 20, "[8.0, 26.0]", 10, 100, output, parallel);
}

/* Partners that cross brick faces (docs/dpd_mpm.md "Under MPI").  The
 * bricks are fixed fractions of the flyer run's box, shrink-wrapped at
 * every list rebuild to the DPD particles, partners and flyer: its low end
 * is the flyer's back face, so the faces move up the bar as the flyer
 * advances (by half its advance for the middle face, a quarter for the
 * upper one of 4 bricks), while the partners, copies of material points,
 * barely move in the run.  A 12 x 3 x 3-cell bar: 8 planes of DPD
 * particles (144, to 25.48 Å), the material points (288) from 29.11 Å,
 * partners out to 48 Å from the DPD particles (`partner_range`: 13 planes,
 * 234 partners, to 72.79 Å; the default two cutoffs give 6 planes, and no
 * uniform face of bricks at least 17.27 Å wide can then fall among them),
 * the 72-particle flyer 0.4 Å off the face (its back at -14.96 Å): the
 * face of 2 bricks (the middle one of 4) starts at 28.91 Å, 0.2 Å below
 * the first plane of partners (3.64 Å from the DPD particles: well within
 * the cutoff, so they carry the interface forces of Eq. (3.1)), the upper
 * face of 4 bricks at 50.85 Å, 0.1 Å below the partners at 50.95 Å.  No
 * all-DPD comparison runs (`compare: false`: they have no partners).
 * 100 steps; 450 DPD particles in the flyer run. */
static void partner_crossing_case(char *buf, size_t len, const char *parallel)
{
    concurrent_case_with(buf, len, 12, 27, "[8.0, 20.0]", 15, 100, OUTPUT, parallel,
                         "  gap: 0.4\n", "  partner_range: 48\n  compare: false\n");
}
#define CROSSING_N 450
#define CROSSING_PARTNERS 234

static const char *const series_cols[] = {"pe_eV",  "ke_eV",     "uint_eV", "etotal_eV",
                                          "temp_K", "press_GPa", NULL};

static void compare_results(const char *a, const char *b, const char *tag)
{
    thb_compare_series(a, b, series_cols, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    thb_compare_impact_metrics(ra, rb, FLYER_N * PARTICLE_MASS * FLYER_VELOCITY, REL, tag);
    thb_compare_result_series(ra, rb, 11, REL, tag);
    static const char *const counts[] = {"cna_fcc", "cna_hcp", "cna_other", "cna_fcc_start",
                                         "partners", "material_points", NULL};
    for (int k = 0; counts[k]; k++)
        cr_assert_eq(thb_metric(ra, counts[k]), thb_metric(rb, counts[k]), "%s: %s", tag,
                     counts[k]);
    json_decref(ra);
    json_decref(rb);
    static const char *const psets[] = {"position", "velocity", "stress", NULL};
    static const int pcomp[] = {3, 3, 6};
    thb_compare_snapshot(a, b, "/points/00000100", psets, pcomp, REL, tag);
}

static void compare_runs(const char *a, const char *b, const char *tag)
{
    compare_results(a, b, tag);
    static const char *const sets[] = {"position", "velocity", "force", "u_internal", NULL};
    static const int ncomp[] = {3, 3, 3, 1};
    thb_compare_snapshot(a, b, "/particles/00000100", sets, ncomp, REL, tag);
    thb_compare_final_xyz(a, b, "final.xyz", REL, tag);   /* gathered on rank 0 by id */
}

/* The run is measured, not a comparison of NaNs: the wave reached both
 * regions and the monitor, the points and partners exist. */
static void assert_measured(const char *dir)
{
    json_t *r = thb_result(dir);
    cr_assert_gt(thb_metric(r, "displacement_max_1"), 0.05, "%s: no wave at region 1", dir);
    cr_assert_gt(thb_metric(r, "displacement_max_2"), 0.002, "%s: no wave at region 2", dir);
    cr_assert_gt(thb_metric(r, "incident_amplitude"), 0.1, "%s: no wave at the monitor", dir);
    cr_assert_gt(thb_metric(r, "partners"), 50, "%s: no partners", dir);
    cr_assert_gt(thb_metric(r, "material_points"), 100, "%s: no material points", dir);
    json_decref(r);
}

/* result.json's parallel.partner_migrations of a brick run: the flyer
 * run's partners that a migration moved to another rank during the steps. */
static long partner_migrations(const char *dir)
{
    json_t *r = thb_result(dir);
    json_t *v = json_object_get(json_object_get(r, "parallel"), "partner_migrations");
    cr_assert(json_is_integer(v), "%s: no parallel.partner_migrations", dir);
    long n = (long)json_integer_value(v);
    json_decref(r);
    return n;
}

Test(bricks_dpd_mpm, concurrent_impact_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    bricks_case(yaml, sizeof yaml, OUTPUT, "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "conc.yaml", yaml);
    static const int nps[] = {1, 2, 4, 8};
    thb_matches_serial(path, "conc", nps, 4, BRICKS_N, assert_measured, compare_runs,
                       "concurrent impact");
    /* here no partner crosses a face (the faces stay among the DPD
     * particles; partners_cross_brick_faces_on_2_and_4_ranks below has
     * crossings): the count says 0, it is not a constant */
    for (int k = 0; k < 4; k++) {
        char dk[600];
        snprintf(dk, sizeof dk, "%s/conc-%d", th_temp_dir(), nps[k]);
        cr_assert_eq(partner_migrations(dk), 0, "%s", dk);
        thb_assert_bricks(dk, nps[k], (int[3]){nps[k], 1, 1});   /* all along the bar */
    }
}

/* Partners cross brick faces during the run (partner_crossing_case): on 2
 * and 4 ranks the solver counts the migrations of the flyer run's
 * partners (must be some: the lookup of their points by id after a
 * migration and their frozen F'(rho) travelling with them are then used
 * with interface forces acting), and the thermo series, every metric and
 * series, the last snapshots of the DPD particles and the material points
 * and the final state agree with the serial run to REL (energy changes on
 * the total energy's scale), as in the tests above. */
Test(bricks_dpd_mpm, partners_cross_brick_faces_on_2_and_4_ranks, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    partner_crossing_case(yaml, sizeof yaml, "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "pcross.yaml", yaml);
    char d0[600], dk[600];
    snprintf(d0, sizeof d0, "%s/pcross-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    json_t *r = thb_result(d0);
    cr_assert_gt(thb_metric(r, "displacement_max_1"), 0.05, "no wave at region 1");
    cr_assert_eq(thb_metric(r, "partners"), CROSSING_PARTNERS);
    cr_assert_eq(thb_metric(r, "material_points"), 288);
    cr_assert_null(json_object_get(r, "parallel"), "a serial run has no parallel record");
    json_decref(r);
    static const int nps[] = {2, 4};
    for (int k = 0; k < 2; k++) {
        snprintf(dk, sizeof dk, "%s/pcross-%d", th_temp_dir(), nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        long moved = partner_migrations(dk);
        /* measured: 18 on 2 ranks (the first plane of partners at the
         * rebuild of step 19), 36 on 4 (that plane and the one at 50.95 Å) */
        cr_assert_gt(moved, 0, "%s: no partner crossed a brick face on %d ranks", dk, nps[k]);
        char tag[128];
        snprintf(tag, sizeof tag, "partners crossing on %d ranks", nps[k]);
        compare_runs(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], CROSSING_N);
    }
}

/* The wave crosses the interface into the material points within the
 * run (region 2 lies among them): the transmitted signal, the points'
 * snapshot and the final state on 2 bricks are the serial run's to REL. */
Test(bricks_dpd_mpm, wave_across_the_interface_on_2_ranks, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    crossing_case(yaml, sizeof yaml, OUTPUT, "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "cross.yaml", yaml);
    char d0[600], d2[600];
    snprintf(d0, sizeof d0, "%s/cross-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/cross-2", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 2, d2, NULL);
    json_t *r = thb_result(d0);
    /* measured among the points: 7e-3 Å displacement, 95 % of the
     * all-DPD run's velocity there */
    cr_assert_gt(thb_metric(r, "displacement_max_2"), 0.003, "no wave in the points");
    double tr = thb_metric(r, "transmission_ratio");
    cr_assert(tr > 0.5 && tr < 1.5, "transmission ratio %g", tr);
    json_decref(r);
    compare_runs(d0, d2, "wave across the interface on 2 ranks");
    thb_check_parallel_record(d2, 2, 288);   /* 108 DPD target, 72 flyer, 108 partners */
}

/* A checkpoint of step 50 written on 2 ranks (auto: bricks) restarts
 * serially, on 4 and on 2 ranks, and a serial one on 2: each ends where
 * the uninterrupted serial run ends (REL), the 2-rank restart's thermo
 * bitwise the 2-rank run's. */
Test(bricks_dpd_mpm, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    bricks_case(yaml, sizeof yaml, OUTPUT_CK, "");
    const char *path = th_write_temp(0, "conc_ck.yaml", yaml);
    thb_checkpoint_moves(path, "conc", compare_runs, "concurrent impact");
    char s1[600];
    snprintf(s1, sizeof s1, "%s/conc-ck-serial", th_temp_dir());
    char d[700];   /* ck-restart-0..2 are thb_checkpoint_moves' */
    thb_restart_at(path, s1, 50, 2, 3, d, sizeof d);
    json_t *r = thb_result(d);
    cr_assert_eq(json_integer_value(json_object_get(r, "restarted_from_step")), 50,
                 "1 to 2: not restarted from step 50");
    json_decref(r);
    compare_runs(s1, d, "1 to 2");
}

/* every metric and series of b bitwise a's */
static void assert_same_result(const char *a, const char *b, const char *tag)
{
    json_t *ra = thb_result(a), *rb = thb_result(b);
    json_t *ma = json_object_get(ra, "metrics"), *mb = json_object_get(rb, "metrics");
    cr_assert_gt(json_object_size(ma), 40, "%s: %zu metrics", tag, json_object_size(ma));
    const char *k;
    json_t *v;
    json_object_foreach(ma, k, v)
    {
        json_t *u = json_object_get(v, "value"), *w = json_object_get(json_object_get(mb, k), "value");
        cr_assert(u && w, "%s: metric %s missing", tag, k);
        double x = json_number_value(u), y = json_number_value(w);
        cr_assert(json_is_null(u) ? json_is_null(w) : memcmp(&x, &y, sizeof x) == 0,
                  "%s: metric %s %.17g vs %.17g", tag, k, x, y);
    }
    json_t *sa = json_object_get(ra, "series"), *sb = json_object_get(rb, "series");
    json_object_foreach(sa, k, v)
    {
        json_t *w = json_object_get(sb, k);
        cr_assert(w && json_equal(v, w), "%s: series %s differs", tag, k);
    }
    json_decref(ra);
    json_decref(rb);
}

/* dir/name equal below its header line */
static void assert_same_text(const char *a, const char *b, const char *name, const char *tag)
{
    static char ta[1 << 20], tb[1 << 20];
    thb_read_text(a, name, ta, sizeof ta);
    thb_read_text(b, name, tb, sizeof tb);
    const char *xa = strchr(ta, '\n'), *xb = strchr(tb, '\n');
    cr_assert(xa && xb && strlen(xa) > 100, "%s: %s too short", tag, name);
    cr_assert_str_eq(xa, xb, "%s: %s differs", tag, name);
}

/* 1-based line and column of the first occurrence of `what` in text. */
static void line_col(const char *text, const char *what, int *line, int *col)
{
    const char *at = strstr(text, what);
    cr_assert_not_null(at, "%s not in the case", what);
    *line = 1;
    const char *bol = text;
    for (const char *q = text; q < at; q++)
        if (*q == '\n') {
            (*line)++;
            bol = q + 1;
        }
    *col = (int)(at - bol) + 1;
}

/* A DPD part too short for the bricks: `auto` on 4 ranks says so and runs
 * replicated -- the serial run bitwise --, `replicated` on 2 likewise
 * without a note, and `bricks` on 4 stops before the run naming the case
 * file, line and key (exit 2). */
Test(bricks_dpd_mpm, short_bar_replicates_under_auto_and_refuses_bricks, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    static char out[16384];
    char yaml[4096], d0[600], dk[600];
    crossing_case(yaml, sizeof yaml, OUTPUT_TEXT, "");
    const char *path = th_write_temp(0, "short.yaml", yaml);
    snprintf(d0, sizeof d0, "%s/short-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    snprintf(dk, sizeof dk, "%s/short-4", th_temp_dir());
    cr_assert_eq(thb_run(path, 4, dk, NULL, out, sizeof out), 0, "%s", out);
    cr_assert(strstr(out, "has no grid of 4 bricks at least 17.2675 Å"), "no note\n%s", out);
    assert_same_result(d0, dk, "short bar under auto on 4 ranks");
    assert_same_text(d0, dk, "thermo.csv", "short bar under auto on 4 ranks");
    assert_same_text(d0, dk, "final.data", "short bar under auto on 4 ranks");

    crossing_case(yaml, sizeof yaml, OUTPUT_TEXT, "parallel: {decomposition: replicated}\n");
    path = th_write_temp(0, "short_repl.yaml", yaml);
    snprintf(dk, sizeof dk, "%s/short-repl-2", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dk, NULL, out, sizeof out), 0, "%s", out);
    cr_assert_null(strstr(out, "note:"), "%s", out);
    assert_same_result(d0, dk, "short bar replicated on 2 ranks");
    assert_same_text(d0, dk, "final.data", "short bar replicated on 2 ranks");

    crossing_case(yaml, sizeof yaml, OUTPUT_TEXT, "parallel:\n  decomposition: bricks\n");
    path = th_write_temp(0, "short_bricks.yaml", yaml);
    snprintf(dk, sizeof dk, "%s/short-bricks-4", th_temp_dir());
    int line = 0, col = 0;
    line_col(yaml, "bricks\n", &line, &col);
    char want[900];
    snprintf(want, sizeof want, "%s:%d:%d: parallel.decomposition: no grid of 4 bricks", path,
             line, col);
    cr_assert_eq(thb_run(path, 4, dk, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, want), "want '%s' in\n%s", want, out);
}
