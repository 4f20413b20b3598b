/*
 * DPD and DPDE on bricks (docs/parallel.md, docs/dpd.md): `mpirun -np N
 * cascade-solver run` of a `type: dpd` case splits the box into N bricks.
 * The random pair forces are keyed on the pair's two global ids, its
 * periodic image and the step, so both ranks of a pair across a brick face
 * draw the same number; the Shardlow sweep runs in cell-colour order
 * (solver/dpd/dpd_sweep_cells.c), which does not depend on the bricks.  So
 * a serial run with `dpd.sweep: cells` and runs on 1, 2, 4 and 8 ranks
 * make the same pair updates; only the conservative force sums run in
 * another order, and over 100 steps the thermo series, the final metrics
 * and the last snapshot (positions, velocities, forces, DPDE internal
 * energies, matched by id) agree to 1e-10 relative.  The default serial
 * sweep (neighbour-list order) is another order of the same splitting: its
 * trajectory differs from the first step on, and only its averages agree
 * with a run on bricks (a stated statistical tolerance, below).
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"
#include "helpers/th_restart.h"

#define REL 1e-10

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.1\nc: 39.0\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\nmass: 508.368\n"    \
    "atoms_per_particle: 8\nlattice_constant: 7.23\n"

static const char *const series_cols[] = {"pe_eV",  "ke_eV",     "uint_eV", "etotal_eV",
                                          "temp_K", "press_GPa", NULL};
static const char *const metrics[] = {"particles",        "pe",          "ke",
                                      "internal_energy",  "etotal",      "temperature",
                                      "temperature_mean", "pressure_mean", "neighbor_rebuilds",
                                      NULL};

static void compare_runs(const char *a, const char *b, long step, int dpde, const char *tag)
{
    thb_compare_series(a, b, series_cols, REL, tag);
    thb_compare_metrics(a, b, metrics, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    double pa = thb_metric(ra, "momentum"), pb = thb_metric(rb, "momentum");
    cr_assert_leq(fabs(pa - pb), REL * pa + 1e-8, "%s: momentum %.17g vs %.17g", tag, pa, pb);
    json_decref(ra);
    json_decref(rb);
    static const char *const sets[] = {"position", "velocity", "force", "u_internal", NULL};
    static const int ncomp[] = {3, 3, 3, 1};
    static const char *const sets_dpd[] = {"position", "velocity", "force", NULL};
    char group[64];
    snprintf(group, sizeof group, "/particles/%08ld", step);
    thb_compare_snapshot(a, b, group, dpde ? sets : sets_dpd, ncomp, REL, tag);
}

/* The serial run with the cell sweep, then 1 (bricks asked for), 2, 4 and
 * 8 ranks (nps ends with 0). */
static void check_rank_counts(const char *tag, const char *yaml, long n, long steps, int dpde,
                              const int *nps)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char name[64], d0[600], dk[600];
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *path = th_write_temp(0, name, yaml);
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), tag);
    thb_must_run(path, 0, d0, NULL);
    for (int k = 0; nps[k]; k++) {
        snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), tag, nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        char what[96];
        snprintf(what, sizeof what, "%s on %d ranks", tag, nps[k]);
        compare_runs(d0, dk, steps, dpde, what);
        if (strstr(yaml, "final_state: final.xyz"))   /* gathered on rank 0 by id */
            thb_compare_final_xyz(d0, dk, "final.xyz", REL, what);
        thb_check_parallel_record(dk, nps[k], n);
    }
}

/* DPDE: the internal energies take the pair sweep's heat, so they go to
 * the owners with the velocities after each colour.  6^3 fcc cells of
 * 7.28 Å (43.7 Å, 864 particles): 3 sweep cells of 14.6 Å per axis,
 * ghost range 7.3 + 10.845 + 1 = 19.1 Å, bricks of 21.8 Å on 2 x 2 x 2. */
Test(bricks_dpd, dpde_matches_serial_cell_sweep, .timeout = 900)
{
    static const int nps[] = {1, 2, 4, 8, 0};
    check_rank_counts("dpde",
                      "type: dpd\nseed: 5\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [6, 6, 6]}\n"
                      "  element: Cu\ndpd: {parameters: cg.yaml, variant: dpde, gamma: 2.0, "
                      "steps: 100, timestep: 0.01, initial_temperature: 600, sweep: cells}\n"
                      "parallel: {decomposition: bricks}\n"
                      "output: {thermo_every: 10, snapshot_every: 100, final_state: final.xyz}\n",
                      864, 100, 1, nps);
}

/* Isothermal DPD under the Berendsen thermostat (a global temperature)
 * in a slab with free surfaces along z: the box shrink-wraps at every
 * rebuild, the bricks and the sweep cells follow it. */
Test(bricks_dpd, dpd_free_surface_berendsen_matches_serial, .timeout = 900)
{
    static const int nps[] = {2, 4, 0};
    check_rank_counts("slab",
                      "type: dpd\nseed: 8\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [6, 6, 8]}\n"
                      "  element: Cu\n  boundary: [periodic, periodic, free]\n"
                      "dpd: {parameters: cg.yaml, variant: dpd, gamma: 1.0, steps: 100, "
                      "timestep: 0.01, initial_temperature: 900, sweep: cells,\n"
                      "      thermostat: {style: berendsen, temperature: 300, tau: 0.5}}\n"
                      "parallel: {decomposition: bricks}\n"
                      "output: {thermo_every: 10, snapshot_every: 100}\n",
                      1152, 100, 0, nps);
}

/* The default serial sweep visits the pairs in neighbour-list order,
 * another order of the same Shardlow splitting (an O(dt) difference per
 * step that the chaotic dynamics then amplifies): its trajectory is not
 * the bricks' one, its averages are.  Stated tolerance: over the second
 * half of 100 steps the mean pressures agree within 3 combined standard
 * errors (block averages of result.json) and the mean temperatures within
 * 1 % (the temperature of 864 particles fluctuates by sqrt(2 / 3N) = 2.8 %
 * per sample). */
Test(bricks_dpd, list_sweep_agrees_statistically, .timeout = 900)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *path =
        th_write_temp(0, "stat.yaml",
                      "type: dpd\nseed: 11\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [6, 6, 6]}\n"
                      "  element: Cu\ndpd: {parameters: cg.yaml, variant: dpd, gamma: 2.0, steps: 100, "
                      "timestep: 0.01, temperature: 298, initial_temperature: 298}\n"
                      "output: {thermo_every: 10}\n");
    char d0[600], d2[600];
    snprintf(d0, sizeof d0, "%s/stat-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/stat-2", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 2, d2, NULL);   /* auto: bricks on 2 ranks */
    thb_check_parallel_record(d2, 2, 864);
    json_t *a = thb_result(d0), *b = thb_result(d2);
    double pa = thb_metric(a, "pressure_mean"), pb = thb_metric(b, "pressure_mean");
    double sa = thb_metric(a, "pressure_sem"), sb = thb_metric(b, "pressure_sem");
    cr_assert_leq(fabs(pa - pb), 3 * sqrt(sa * sa + sb * sb), "pressure %.6g vs %.6g GPa (sem %.3g, "
                  "%.3g)", pa, pb, sa, sb);
    double ta = thb_metric(a, "temperature_mean"), tb = thb_metric(b, "temperature_mean");
    cr_assert_leq(fabs(ta - tb), 0.01 * ta, "temperature %.6g vs %.6g K", ta, tb);
    /* the same particles, and momentum conserved by both sweeps */
    cr_assert_eq(thb_metric(a, "particles"), thb_metric(b, "particles"));
    cr_assert_leq(thb_metric(b, "momentum"), 1e-6);
    json_decref(a);
    json_decref(b);
}

/* a restarted run against ref: series, metrics and the step-100 snapshot */
static void compare_restarted(const char *ref, const char *dir, const char *tag)
{
    compare_runs(ref, dir, 100, 1, tag);
}

/* A DPDE checkpoint written on N ranks restarts on M: the restarted run
 * ends where the uninterrupted serial one does (to REL); on the same rank
 * count the thermo is the same text.  par: the case's parallel line. */
static void checkpoint_moves(const char *stem, const char *par)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[1024], name[64];
    snprintf(yaml, sizeof yaml,
             "type: dpd\nseed: 5\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [6, 6, 6]}\n"
             "  element: Cu\ndpd: {parameters: cg.yaml, variant: dpde, gamma: 2.0, "
             "steps: 100, timestep: 0.01, initial_temperature: 600, sweep: cells}\n"
             "output: {thermo_every: 10, snapshot_every: 100, checkpoint_every: 50}\n%s",
             par);
    snprintf(name, sizeof name, "%s.yaml", stem);
    const char *path = th_write_temp(0, name, yaml);
    char s1[600], m2[600];
    snprintf(s1, sizeof s1, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(m2, sizeof m2, "%s/%s-2", th_temp_dir(), stem);
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    compare_runs(s1, m2, 100, 1, "uninterrupted 2 ranks");
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {s1, 2, "1 to 2", NULL}, {m2, 2, "2 to 2", m2}};
    thb_restarts_match(path, 50, cases, 3, s1, compare_restarted);
}

Test(bricks_dpd, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoint_moves("ck", "");
}

/* The same with shifted cuts moved at every check (balance_every 20,
 * threshold 1: any imbalance) and at each checkpoint. */
Test(bricks_dpd, dynamic_balance_checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoint_moves("dyn", "parallel: {balance: shift, balance_every: 20, "
                            "balance_threshold: 1.0}\n");
}

/* parallel.balance on DPD (the slab above, free along z, on 2 and 4
 * ranks): the first list build cuts at the particles' quantiles, a check
 * every 20 steps moves the cuts again where any imbalance is left; the
 * pair updates do not depend on the bricks (the cell sweep), so the
 * trajectory is still the serial one to REL. */
Test(bricks_dpd, shifted_cuts_match_serial, .timeout = 900)
{
    static const int nps[] = {2, 4, 0};
    check_rank_counts("balanced",
                      "type: dpd\nseed: 8\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [6, 6, 8]}\n"
                      "  element: Cu\n  boundary: [periodic, periodic, free]\n"
                      "dpd: {parameters: cg.yaml, variant: dpd, gamma: 1.0, steps: 100, "
                      "timestep: 0.01, initial_temperature: 900, sweep: cells,\n"
                      "      thermostat: {style: berendsen, temperature: 300, tau: 0.5}}\n"
                      "parallel: {decomposition: bricks, balance: shift, balance_every: 20,\n"
                      "           balance_threshold: 1.0}\n"
                      "output: {thermo_every: 10, snapshot_every: 100}\n",
                      1152, 100, 0, nps);
    char d2[600];
    snprintf(d2, sizeof d2, "%s/balanced-2", th_temp_dir());
    long checks, shifts;
    thb_balance_record(d2, &checks, &shifts, NULL);
    cr_log_info("DPD slab on 2 ranks, balance_every 20: %ld checks, %ld shifts", checks, shifts);
    cr_assert_geq(checks, 4, "%ld checks", checks);
    /* the first build's shift, and at least one check that moved the cuts */
    cr_assert_geq(shifts, 2, "%ld shifts", shifts);
}

/* The cell sweep needs three cells of r_d along a periodic axis: a box of
 * 4^3 cells (29.1 Å < 3 x 10.845 Å) is refused on bricks naming the case
 * file and the parallel section, and serially with sweep: cells. */
Test(bricks_dpd, box_too_small_for_the_cell_sweep_is_refused, .timeout = 300)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    static char out[16384];
    const char *path =
        th_write_temp(0, "small.yaml",
                      "type: dpd\nseed: 5\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [4, 4, 4]}\n"
                      "  element: Cu\ndpd: {parameters: cg.yaml, steps: 10}\n"
                      "parallel:\n  decomposition: bricks\n");
    char dir[600];
    snprintf(dir, sizeof dir, "%s/small", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "small.yaml:8:") && strstr(out, "at least 3 r_d"), "%s", out);
    path = th_write_temp(1, "small_cells.yaml",
                         "type: dpd\nseed: 5\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [4, 4, 4]}\n"
                         "  element: Cu\ndpd: {parameters: cg.yaml, steps: 10, sweep: cells}\n");
    snprintf(dir, sizeof dir, "%s/small-cells", th_temp_dir());
    int rc = thb_run(path, 0, dir, NULL, out, sizeof out);
    cr_assert_neq(rc, 0, "%s", out);
    cr_assert(strstr(out, "at least 3 r_d = 32.535 Å long along x"), "%s", out);
}

/* A restart on bricks reads, on each rank, only the stored particles of
 * its brick (model_particles_read_brick).  What no run stores is refused
 * with exit 2, naming the file and the dataset, printed once without
 * "another MPI rank": an id stored twice, once deep in each rank's brick
 * (found by comparing the ranks' ids, rank 1's words), a NaN position,
 * and positions 1e300 and 1e5 Å outside a 58 Å box (more than a box
 * length: the box wraps its particles at every list build). */
Test(bricks_dpd, restart_refuses_impossible_stored_particles, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *path = th_write_temp(
        0, "badck.yaml",
        "type: dpd\nseed: 5\nsystem:\n  lattice: {style: fcc, a: 7.28, cells: [8, 6, 6]}\n"
        "  element: Cu\ndpd: {parameters: cg.yaml, variant: dpde, gamma: 2.0, steps: 20, "
        "timestep: 0.01, initial_temperature: 600, sweep: cells}\n"
        "parallel: {decomposition: bricks, grid: [2, 1, 1]}\n"
        "output: {thermo_every: 10, checkpoint_every: 10}\n");
    char run[600], ck[700];
    snprintf(run, sizeof run, "%s/badck-2", th_temp_dir());
    thb_must_run(path, 2, run, NULL);
    snprintf(ck, sizeof ck, "%s/checkpoint-%010d.h5", run, 10);
    long row_high = -1;
    int64_t low_id = 0;
    {   /* a row near the lowest x (rank 0's brick) and one near the highest
         * (rank 1's) */
        double *x = NULL;
        int64_t *ids = NULL;
        long n = th_ckpt_positions_ids(ck, "/model/dpd/particles", &x, &ids);
        cr_assert_eq(n, 1152);
        long lo = 0, hi = 0;
        for (long i = 1; i < n; i++) {
            lo = x[3 * i] < x[3 * lo] ? i : lo;
            hi = x[3 * i] > x[3 * hi] ? i : hi;
        }
        low_id = ids[lo];
        row_high = hi;
        free(x);
        free(ids);
    }
    double nan = NAN, huge = 1e300, far = -1e5;
    static const struct {
        const char *name, *dataset, *want;
    } bad[] = {
        {"dup", "/model/dpd/particles/id", "model/dpd/particles/id: 1 id(s) given twice"},
        {"nan", "/model/dpd/particles/x", "model/dpd/particles/x/v/f: a non-finite position"},
        {"huge", "/model/dpd/particles/x", "model/dpd/particles/x: particle"},
        {"far", "/model/dpd/particles/x", "model/dpd/particles/x: particle"},
    };
    const void *val[] = {&low_id, &nan, &huge, &far};
    const long type[] = {(long)H5T_NATIVE_INT64, (long)H5T_NATIVE_DOUBLE,
                         (long)H5T_NATIVE_DOUBLE, (long)H5T_NATIVE_DOUBLE};
    const long row[] = {row_high, 3 * row_high, 3 * row_high, 3 * row_high};
    for (int k = 0; k < 4; k++) {
        char stem[64], out[16384];
        snprintf(stem, sizeof stem, "badck-%s", bad[k].name);
        thb_restart_refuses(path, ck, 10, stem, 2, bad[k].dataset, type[k], row[k], val[k],
                            bad[k].want, out, sizeof out);
        cr_assert(k < 2 || strstr(out, "more than a box length outside the stored box"), "%s: %s",
                  bad[k].name, out);
    }
}
