/*
 * The DPD/MPM-grid impact on bricks (docs/dpd_mpm.md "Under MPI",
 * docs/parallel.md): under mpirun `dpd_grid_impact` splits the DPD
 * particles of the flyer run over the bricks of the DPD halo and those of
 * the reference run (the target without the flyer) over a second halo of
 * the same bricks, while every rank holds the whole (small) MPM grid of
 * each run and sums its nodes over the ranks, as the grid tensile rod
 * does (tests/test_bricks_dpd_grid_tensile.c).  The flyer is a free rigid
 * body of the DPD model: its force is a sum over the ranks, so it moves
 * alike on every rank.  The region means, profiles, front probes, CNA
 * counts and the internal temperature are sums over the ranks.
 *
 * The grid model has no Shardlow sweep, so only the order of the sums
 * changes: over 100 steps the thermo series, every metric of result.json
 * (wave-speed fits, arrival times, front metrics, the flyer's final
 * velocity, heats) and every series (region displacements, the profile,
 * the front probes), and the last snapshot (positions, velocities,
 * forces, DPDE internal energies, matched by id) and the final state
 * (output.final_state, gathered on rank 0) agree with the serial run
 * to 1e-10 relative on 1, 2, 4 and 8 ranks (8 bricks along the bar,
 * oversubscribed); the energy-change metrics, being
 * differences of nearly equal total energies, on the total energy's scale;
 * the CNA counts exactly.  A checkpoint written on 2 ranks restarts
 * serially and on 4 (to the same tolerances) and on 2 (bitwise).
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10
#define BAR_N 720
#define FLYER_N 72
#define PARTICLE_MASS 508.368   /* amu */
#define FLYER_VELOCITY 5.0      /* Å/ps, the default */

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

/* The 20 x 3 x 3-cell bar (720 particles, 146 Å, free surfaces) at 100 K,
 * DPDE on a 4 Å grid, hit by a free 4-plane flyer (72 particles) at
 * 5 Å/ps, with the reference run; regions 6 and 14 Å from the face (the
 * wave reaches both within the 0.5 ps), a profile at 0.25 ps, CNA at the
 * snapshots: 100 steps of 5 fs.  20 cells so that the DPD halo's box
 * (139.9 Å along the bar with the flyer) takes 8 bricks of the 17.27 Å
 * interaction range; 12 cells (81.7 Å) took only 4, and the 16 Å
 * cross-section takes one brick. */
static void bar_case(char *buf, size_t len, const char *output, const char *parallel)
{
    snprintf(buf, len,
             "type: dpd_grid_impact\nseed: 3\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [20, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, free, free]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: 100\n"
             "  initial_temperature: 100\n"
             "impact: {regions: [6.0, 14.0], sample_every: 2, arrival_threshold: 0.002, "
             "profile_times: [0.25]}\n"
             "grid: {cell: 4.0}\n%s%s",
             output, parallel);
}

#define OUTPUT "output: {thermo_every: 10, snapshot_every: 50, final_state: final.xyz}\n"
#define OUTPUT_CK                                                                                 \
    "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 50, "                       \
    "final_state: final.xyz}\n"

static const char *const series_cols[] = {"pe_eV",  "ke_eV",     "uint_eV", "etotal_eV",
                                          "temp_K", "press_GPa", NULL};

static void compare_runs(const char *a, const char *b, const char *tag)
{
    thb_compare_series(a, b, series_cols, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    thb_compare_impact_metrics(ra, rb, FLYER_N * PARTICLE_MASS * FLYER_VELOCITY, REL, tag);
    thb_compare_result_series(ra, rb, 11, REL, tag);
    /* the CNA counts are counts: the same classes */
    static const char *const counts[] = {"cna_fcc", "cna_hcp", "cna_other", "cna_fcc_start",
                                         NULL};
    for (int k = 0; counts[k]; k++)
        cr_assert_eq(thb_metric(ra, counts[k]), thb_metric(rb, counts[k]), "%s: %s", tag,
                     counts[k]);
    json_decref(ra);
    json_decref(rb);
    static const char *const sets[] = {"position", "velocity", "force", "u_internal", NULL};
    static const int ncomp[] = {3, 3, 3, 1};
    thb_compare_snapshot(a, b, "/particles/00000100", sets, ncomp, REL, tag);
    thb_compare_final_xyz(a, b, "final.xyz", REL, tag);   /* gathered on rank 0 by id */
}

/* The flyer hit the bar: the wave reached both regions, the flyer slowed,
 * and the grid and the D + R forces exchanged heat. */
static void assert_impact(const char *dir)
{
    json_t *r = thb_result(dir);
    cr_assert_gt(thb_metric(r, "displacement_max_1"), 0.05, "%s: no wave at region 1", dir);
    cr_assert_gt(thb_metric(r, "displacement_max_2"), 0.01, "%s: no wave at region 2", dir);
    double vf = thb_metric(r, "flyer_velocity_final");
    cr_assert(vf < 4.9 && vf > 0, "%s: flyer at %g Å/ps", dir, vf);
    cr_assert_eq(thb_metric(r, "target_particles"), BAR_N);
    cr_assert_eq(thb_metric(r, "flyer_particles"), FLYER_N);
    cr_assert_gt(thb_metric(r, "cna_fcc"), 50, "%s: no fcc", dir);
    cr_assert_gt(fabs(thb_metric(r, "heat_grid")), 1e-3, "%s: no grid heat", dir);
    cr_assert_gt(fabs(thb_metric(r, "heat_dr")), 1e-4, "%s: no D + R heat", dir);
    json_decref(r);
}

Test(bricks_dpd_grid_impact, matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048];
    bar_case(yaml, sizeof yaml, OUTPUT, "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "gbar.yaml", yaml);
    static const int nps[] = {1, 2, 4, 8};
    thb_matches_serial(path, "gbar", nps, 4, BAR_N + FLYER_N, assert_impact, compare_runs,
                       "grid impact");
    for (int k = 0; k < 4; k++) {   /* bricks along the bar, on 8 ranks too */
        char dk[600];
        snprintf(dk, sizeof dk, "%s/gbar-%d", th_temp_dir(), nps[k]);
        thb_assert_bricks(dk, nps[k], (int[3]){nps[k], 1, 1});
    }
}

/* Without a `parallel` section (auto) 2 ranks take bricks, with no note
 * that the case is not decomposed; a checkpoint of step 50 written there
 * restarts serially, on 4 and on 2 ranks: each ends where the
 * uninterrupted serial run ends, and the 2-rank restart is the 2-rank
 * run's thermo, bitwise. */
Test(bricks_dpd_grid_impact, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048];
    bar_case(yaml, sizeof yaml, OUTPUT_CK, "");
    thb_checkpoint_moves(th_write_temp(0, "gbar_ck.yaml", yaml), "gbar", compare_runs,
                         "grid impact");
}

/* An 8-cell bar (58 Å) on 4 ranks: its bricks would be thinner than the
 * DPD model's first ghost build takes (the cell sweep's reach, 17.27 Å,
 * before the grid marks the particles), so `auto` must fall back to
 * replicated data with a note -- before 2026-11-28 it planned on the
 * list's range, took bricks and stopped ("the box shrank"). */
Test(bricks_dpd_grid_impact, short_bar_replicates_under_auto, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    bar_case(yaml, sizeof yaml, "output: {thermo_every: 10}\n", "");
    char *cells = strstr(yaml, "cells: [20, 3, 3]");
    cr_assert_not_null(cells);
    memcpy(cells, "cells: [ 8, 3, 3]", 17);
    thb_short_replicates(th_write_temp(0, "gshort.yaml", yaml), 4, "gshort");
}
