/*
 * Brick decomposition (core/halo.h): `mpirun -np N cascade-solver run` of
 * an MD case splits the box into N bricks.  Over 100 steps the thermo
 * series (the full doubles of /series in fields.h5) and the final metrics
 * agree with the serial run to 1e-10 relative (the sums run in another
 * order, so not bitwise), for LJ, EAM Cu, SW Si and meam/spline Si on 1,
 * 2, 4 and 8 ranks; the last snapshot holds the same atoms with the same
 * positions, velocities and forces (sorted by id); atoms crossing every
 * face of every brick migrate; checkpoints move between rank counts; bad
 * grids are refused naming the case file and line.
 */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10

static const char *const series_cols[] = {"pe_eV",     "ke_eV",     "etotal_eV", "temp_K",
                                          "press_GPa", "pxx_GPa",   "pyy_GPa",   "pzz_GPa",
                                          "pxy_GPa",   "pxz_GPa",   "pyz_GPa",   NULL};

/* The thermo series agree to REL of each column's largest magnitude (an
 * off-diagonal pressure passes through zero: relative to itself it would
 * compare round-off with round-off), over at least 11 rows. */
static void compare_series(const char *a, const char *b, const char *tag)
{
    long n;
    free(thb_read_h5(a, "/series/pe_eV", H5T_NATIVE_DOUBLE, sizeof(double), &n));
    cr_assert_geq(n, 11, "%s: %ld thermo rows", tag, n);
    thb_compare_series(a, b, series_cols, REL, tag);
}

/* Final metrics: to REL relative, except the ones that are differences of
 * nearly equal numbers (drift, its rate and the fluctuation about it) or
 * round-off themselves (momentum), compared to REL of the energy per atom
 * and to a round-off bound. */
static void compare_metrics(const char *a, const char *b, const char *tag)
{
    static const char *const rel[] = {"atoms", "pe", "pe_per_atom", "ke", "etotal",
                                      "temperature", "temperature_mean", "pressure",
                                      "pressure_mean", "pxx", "pyy", "pzz", "max_force", "volume",
                                      "density", "neighbor_rebuilds", NULL};
    thb_compare_metrics(a, b, rel, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    double epa = fabs(thb_metric(ra, "pe_per_atom"));
    static const char *const per_atom[] = {"energy_drift_rate", "energy_fluctuation", NULL};
    for (int k = 0; per_atom[k]; k++) {
        double x = thb_metric(ra, per_atom[k]), y = thb_metric(rb, per_atom[k]);
        cr_assert_leq(fabs(x - y), REL * epa, "%s %s: %.17g vs %.17g", tag, per_atom[k], x, y);
    }
    cr_assert_leq(fabs(thb_metric(ra, "energy_drift") - thb_metric(rb, "energy_drift")), REL,
                  "%s drift", tag);
    double pa = thb_metric(ra, "momentum"), pb = thb_metric(rb, "momentum");
    cr_assert_leq(fabs(pa - pb), REL * pa + 1e-8, "%s: momentum %.17g vs %.17g", tag, pa, pb);
    json_decref(ra);
    json_decref(rb);
}

/* The last snapshot: the same datasets, and the same atoms (by id) with
 * positions, velocities, forces, energies and stresses to REL of each
 * dataset's largest value. */
static void compare_snapshot(const char *a, const char *b, long step, const char *tag)
{
    char group[64];
    snprintf(group, sizeof group, "/particles/%08ld", step);
    static const char *const sets[] = {"position", "velocity", "force", "pe", "stress", NULL};
    static const int ncomp[] = {3, 3, 3, 1, 6};
    thb_compare_snapshot(a, b, group, sets, ncomp, REL, tag);
}

/* Serial, then 1 (bricks asked for), 2, 4 and 8 ranks. */
static void check_rank_counts(const char *tag, const char *yaml, long natoms, long steps)
{
    char name[64], dir[5][600];
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *path = th_write_temp(0, name, yaml);
    const int nps[5] = {0, 1, 2, 4, 8};
    for (int k = 0; k < 5; k++) {
        snprintf(dir[k], sizeof dir[k], "%s/%s-%d", th_temp_dir(), tag, nps[k]);
        thb_must_run(path, nps[k], dir[k], NULL);
    }
    for (int k = 1; k < 5; k++) {
        char what[96];
        snprintf(what, sizeof what, "%s on %d ranks", tag, nps[k]);
        compare_series(dir[0], dir[k], what);
        compare_metrics(dir[0], dir[k], what);
        compare_snapshot(dir[0], dir[k], steps, what);
        if (strstr(yaml, "final_state: final.xyz"))   /* gathered on rank 0 by id */
            thb_compare_final_xyz(dir[0], dir[k], "final.xyz", REL, what);
        thb_check_parallel_record(dir[k], nps[k], natoms);
    }
}

/* decomposition: bricks so that 1 rank runs on one brick too (auto keeps
 * the serial path there) */
Test(bricks, lj_matches_serial, .timeout = 600)
{
    check_rank_counts("lj", "seed: 5\nsystem:\n  lattice: {style: fcc, a: 5.26, cells: [6, 6, 6]}\n"
                            "  element: Ar\npotential: {style: lj, elements: [Ar], epsilon: "
                            "[0.0104], sigma: [3.4], cutoff: 8.5}\n"
                            "md: {steps: 100, temperature: 60, timestep: 0.002}\n"
                            "parallel: {decomposition: bricks}\n"
                            "output: {thermo_every: 10}\n",
                      864, 100);
}

Test(bricks, eam_cu_matches_serial, .timeout = 600)
{
    check_rank_counts("eam", "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [8, 8, 8]}\n"
                             "  element: Cu\npotential: {style: eam/alloy, file: "
                             "Cu_mishin1.eam.alloy}\nmd: {steps: 100, temperature: 600}\n"
                             "parallel: {decomposition: bricks}\n"
                             "output: {thermo_every: 10, final_state: final.xyz}\n",
                      2048, 100);
}

/* Three-body terms over full lists: each rank sums the triplets centred
 * on its own atoms, forces on ghosts go back to their owners */
Test(bricks, sw_si_matches_serial, .timeout = 600)
{
    check_rank_counts("sw", "seed: 4\nsystem:\n  lattice: {style: diamond, a: 5.431, cells: [4, 4, 4]}\n"
                            "  element: Si\npotential: {style: sw, file: Si.sw, elements: [Si]}\n"
                            "md: {steps: 100, temperature: 600}\n"
                            "parallel: {decomposition: bricks}\n"
                            "output: {thermo_every: 10}\n",
                      512, 100);
}

/* meam/spline also needs U'(rho) of the ghosts: forwarded from owners */
Test(bricks, meam_spline_si_matches_serial, .timeout = 600)
{
    check_rank_counts("meam", "seed: 4\nsystem:\n  lattice: {style: diamond, a: 5.431, cells: [4, 4, 4]}\n"
                              "  element: Si\npotential: {style: meam/spline, file: "
                              "Si_1.meam.spline, elements: [Si]}\n"
                              "md: {steps: 100, temperature: 600}\n"
                              "parallel: {decomposition: bricks}\n"
                              "output: {thermo_every: 10}\n",
                      512, 100);
}

/* A slab with free surfaces along z (the box shrink-wraps over all ranks
 * at every rebuild, the z bricks follow it) under a Langevin thermostat
 * (random forces keyed on the atom's id and the step: every rank count
 * draws the same numbers) */
Test(bricks, free_surface_langevin_matches_serial, .timeout = 600)
{
    check_rank_counts("slab", "seed: 9\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [8, 8, 8]}\n"
                              "  element: Cu\n  boundary: [periodic, periodic, free]\n"
                              "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                              "md: {steps: 100, temperature: 900, thermostat: {style: langevin, "
                              "temperature: 900, tau: 0.05}}\n"
                              "parallel: {decomposition: bricks}\n"
                              "output: {thermo_every: 10}\n",
                      2048, 100);
}

/* An argon crystal of 6^3 cells (31.56 Å) moving as a whole at +-(v, v, v)
 * with v = 200 Å/ps on top of small random velocities: in 100 steps of
 * 2 fs every atom travels 40 Å along each axis, more than the box, so on a
 * 2 x 2 x 2 grid (bricks of 15.78 Å) it leaves its brick through the faces
 * of every axis several times and wraps around the periodic box. */
static void drifting_crystal(const char *tag, double sign)
{
    const double a = 5.26, v = 200.0;
    const int n = 6;
    const double L = n * a;
    static char text[1 << 17];
    int at = snprintf(text, sizeof text,
                      "%d\nLattice=\"%.10g 0 0 0 %.10g 0 0 0 %.10g\" "
                      "Properties=species:S:1:pos:R:3:vel:R:3\n",
                      4 * n * n * n, L, L, L);
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    unsigned s = 12345;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++)
                for (int b = 0; b < 4; b++) {
                    double r[3];
                    for (int d = 0; d < 3; d++) {
                        s = s * 1103515245u + 12345u;
                        r[d] = ((double)(s >> 8) / (double)(1u << 24) - 0.5) * 2.0;   /* Å/ps */
                    }
                    at += snprintf(text + at, sizeof text - (size_t)at,
                                   "Ar %.10g %.10g %.10g %.10g %.10g %.10g\n",
                                   (i + basis[b][0]) * a, (j + basis[b][1]) * a,
                                   (k + basis[b][2]) * a, sign * v + r[0], sign * v + r[1],
                                   sign * v + r[2]);
                }
    char xyz[64], yaml[1024];
    snprintf(xyz, sizeof xyz, "%s.xyz", tag);
    const char *xpath = th_write_temp(1, xyz, text);
    snprintf(yaml, sizeof yaml,
             "seed: 7\nsystem:\n  read_xyz: %s\n"
             "potential: {style: lj, elements: [Ar], epsilon: [0.0104], sigma: [3.4], "
             "cutoff: 8.5}\nmd: {steps: 100, temperature: 0, timestep: 0.002}\n"
             "parallel: {grid: [2, 2, 2]}\noutput: {thermo_every: 10}\n",
             xpath);
    char name[64], d0[600], d8[600];
    snprintf(name, sizeof name, "%s.yaml", tag);
    const char *path = th_write_temp(2, name, yaml);
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), tag);
    snprintf(d8, sizeof d8, "%s/%s-8", th_temp_dir(), tag);
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 8, d8, NULL);
    /* the crystal moved 40 Å per axis: more than two bricks */
    cr_assert_gt(v * 100 * 0.002, 2 * L / 2);
    compare_series(d0, d8, tag);
    compare_metrics(d0, d8, tag);
    compare_snapshot(d0, d8, 100, tag);
    thb_check_parallel_record(d8, 8, 864);
}

Test(bricks, atoms_migrate_through_every_face_up, .timeout = 600)
{
    drifting_crystal("drift_up", 1.0);
}

Test(bricks, atoms_migrate_through_every_face_down, .timeout = 600)
{
    drifting_crystal("drift_down", -1.0);
}

/* the series, metrics and last snapshot of a restarted run against ref */
static void compare_restarted(const char *ref, const char *dir, const char *tag)
{
    compare_series(ref, dir, tag);
    compare_metrics(ref, dir, tag);
    compare_snapshot(ref, dir, 100, tag);
}

/* A checkpoint written on N ranks restarts on M (2 -> 1, 1 -> 2, 2 -> 2,
 * 2 -> 4, 4 -> 2, 4 -> 1 under mpirun): the restarted run ends where
 * the uninterrupted one does (to REL; on the same rank count the thermo
 * is the same text). */
Test(bricks, checkpoint_moves_between_rank_counts, .timeout = 600)
{
    const char *yaml = "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [6, 6, 6]}\n"
                       "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {steps: 100, temperature: 600}\n"
                       "output: {thermo_every: 10, checkpoint_every: 50}\n";
    const char *path = th_write_temp(0, "ck.yaml", yaml);
    char s1[600], m2[600], m4[600];
    snprintf(s1, sizeof s1, "%s/ck-serial", th_temp_dir());
    snprintf(m2, sizeof m2, "%s/ck-2", th_temp_dir());
    snprintf(m4, sizeof m4, "%s/ck-4", th_temp_dir());
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    thb_must_run(path, 4, m4, NULL);
    compare_series(s1, m2, "uninterrupted 2 ranks");
    compare_series(s1, m4, "uninterrupted 4 ranks");
    /* the checkpoints of 2 and 4 ranks are written collectively, each rank
     * its own atoms (docs/parallel.md, "Output"); read back on M ranks, each
     * reads a share of the rows collectively and migrates them home */
    const struct thb_restart cases[] = {{m2, 0, "2 to 1", NULL}, {s1, 2, "1 to 2", NULL},
                                        {m2, 2, "2 to 2", m2},       {m2, 4, "2 to 4", NULL},
                                        {m4, 2, "4 to 2", NULL},     {m4, 1, "4 to 1 (mpirun -np 1)", NULL}};
    thb_restarts_match(path, 50, cases, 6, s1, compare_restarted);
}

/* Bad grids: the product is not the rank count, or a brick is thinner
 * than cutoff + skin; both name the case file, the line and the key. */
Test(bricks, bad_grid_names_file_and_line, .timeout = 300)
{
    const char *base = "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [6, 6, 6]}\n"
                       "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {steps: 10, temperature: 100}\n";
    char yaml[1024];
    static char out[16384];
    snprintf(yaml, sizeof yaml, "%sparallel:\n  grid: [2, 2, 1]\n", base);
    const char *path = th_write_temp(0, "grid4.yaml", yaml);
    char dir[600];
    snprintf(dir, sizeof dir, "%s/bad-grid", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "grid4.yaml:8:") && strstr(out, "parallel.grid") &&
                  strstr(out, "product must equal the rank count"),
              "%s", out);
    /* 21.69 Å / 4 = 5.4 Å bricks, the range is 5.51 + 1 Å */
    snprintf(yaml, sizeof yaml, "%sparallel:\n  grid: [4, 1, 1]\n", base);
    path = th_write_temp(1, "thin.yaml", yaml);
    cr_assert_eq(thb_run(path, 4, dir, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "thin.yaml:8:") && strstr(out, "parallel.grid") &&
                  strstr(out, "thinner than the interaction range"),
              "%s", out);
    /* decomposition: bricks with no grid that fits: 3^3 cells (10.8 Å) on 2 ranks */
    snprintf(yaml, sizeof yaml,
             "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [3, 3, 3]}\n"
             "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 10, temperature: 100}\nparallel:\n  decomposition: bricks\n");
    path = th_write_temp(2, "nogrid.yaml", yaml);
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "nogrid.yaml:8:") && strstr(out, "parallel.decomposition"), "%s", out);
    /* a grid with replicated data, and a misspelt key, at check time */
    snprintf(yaml, sizeof yaml, "%sparallel:\n  decomposition: replicated\n  grid: [1, 1, 2]\n",
             base);
    path = th_write_temp(3, "repl.yaml", yaml);
    thb_mpi_env(0);   /* serial from here: leak checks on */
    const char *a1[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a1, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "repl.yaml:9:") && strstr(out, "parallel.grid"), "%s", out);
    snprintf(yaml, sizeof yaml, "%sparallel:\n  gird: [1, 1, 2]\n", base);
    path = th_write_temp(4, "typo.yaml", yaml);
    const char *a2[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a2, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "did you mean 'grid'"), "%s", out);
    /* a balance with replicated data, and an unknown balance */
    snprintf(yaml, sizeof yaml,
             "%sparallel:\n  decomposition: replicated\n  balance: shift\n", base);
    path = th_write_temp(5, "replbal.yaml", yaml);
    const char *a3[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a3, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "replbal.yaml:9:") && strstr(out, "parallel.balance"), "%s", out);
    snprintf(yaml, sizeof yaml, "%sparallel:\n  balance: rcb\n", base);
    path = th_write_temp(6, "badbal.yaml", yaml);
    const char *a4[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a4, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "badbal.yaml:8:") && strstr(out, "parallel.balance") &&
                  strstr(out, "shift"),
              "%s", out);
    /* a case type that keeps equal bricks refuses the key instead of
     * ignoring it (dpd: the faces never move) */
    path = th_write_temp(7, "dpdbal.yaml",
                         "type: dpd_tensile\ndpd:\n  parameters: cu_cg.params\n"
                         "parallel:\n  decomposition: bricks\n  balance: shift\n");
    const char *a5[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a5, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "dpdbal.yaml:6:") && strstr(out, "parallel.balance") &&
                  strstr(out, "'dpd_tensile' does not move its brick faces"),
              "%s", out);
    /* balance_every without balance: shift, a threshold without
     * balance_every, a threshold below 1 or not a number, a key given
     * twice (every type that moves its faces moves them again; the others
     * refuse balance: shift, above) */
    snprintf(yaml, sizeof yaml, "%sparallel:\n  balance_every: 50\n", base);
    path = th_write_temp(0, "every.yaml", yaml);
    const char *a6[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a6, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "every.yaml:8:") && strstr(out, "parallel.balance_every") &&
                  strstr(out, "add balance: shift"),
              "%s", out);
    snprintf(yaml, sizeof yaml, "%sparallel:\n  balance: shift\n  balance_threshold: 1.2\n",
             base);
    path = th_write_temp(1, "thresh.yaml", yaml);
    const char *a7[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a7, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "thresh.yaml:9:") && strstr(out, "parallel.balance_threshold") &&
                  strstr(out, "give balance_every too"),
              "%s", out);
    snprintf(yaml, sizeof yaml,
             "%sparallel:\n  balance: shift\n  balance_every: 10\n  balance_threshold: 0.9\n",
             base);
    path = th_write_temp(2, "low.yaml", yaml);
    const char *a8[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a8, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "low.yaml:10:") && strstr(out, "parallel.balance_threshold"), "%s",
              out);
    snprintf(yaml, sizeof yaml,
             "%sparallel:\n  balance: shift\n  balance_every: 10\n  balance_threshold: .nan\n",
             base);
    path = th_write_temp(4, "nan.yaml", yaml);
    const char *a10[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a10, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "nan.yaml:10:") && strstr(out, "parallel.balance_threshold"), "%s",
              out);
    snprintf(yaml, sizeof yaml,
             "%sparallel:\n  balance: shift\n  balance_every: 10\n  balance_every: 20\n", base);
    path = th_write_temp(5, "twice.yaml", yaml);
    const char *a11[] = {th_solver(), "check", path, NULL};
    cr_assert_eq(th_run(a11, out, sizeof out), 2, "%s", out);
    cr_assert(strstr(out, "twice.yaml:10:") && strstr(out, "duplicate key 'balance_every'"), "%s",
              out);
}

/* The final max/mean of a run with static cuts: no balance record */
static double static_imbalance(const char *dir)
{
    json_t *r = thb_result(dir);
    json_t *par = json_object_get(r, "parallel");
    cr_assert_not_null(par, "%s: no parallel record", dir);
    cr_assert_null(json_object_get(par, "balance_checks"), "%s: a static balance checked", dir);
    double imb = json_real_value(json_object_get(par, "imbalance_max_over_mean"));
    json_decref(r);
    return imb;
}

/* Dynamic balance (parallel.balance_every): a Cu flyer plate 21.7 Å thick
 * crosses a periodic 60 Å box along x at 10 km/s (1 Å every 10 steps),
 * on 2 bricks along x.  The set-up cuts it in half; cuts that stay leave
 * every atom in one brick after 100 steps (max/mean 2), cuts checked
 * every 10 steps follow it (within a plane of 32 atoms of 384).  The
 * trajectory is the serial one to 1e-10 on 2 and 4 ranks, and a
 * checkpoint taken between two checks restarts on 2 ranks bitwise (both
 * runs cut at the stored atoms) and on 1 and 4 to 1e-10. */
Test(bricks, dynamic_balance_follows_a_moving_plate, .timeout = 900)
{
    const double a = 3.615;
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    static char text[1 << 16];
    char body[1 << 16];
    int n = 0, at = 0;
    uint64_t r = 12345;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 4; j++)
            for (int k = 0; k < 4; k++)
                for (int b = 0; b < 4; b++, n++) {
                    double x[3] = {(i + basis[b][0]) * a + 19.0, (j + basis[b][1]) * a,
                                   (k + basis[b][2]) * a};
                    /* 0.05 Å of deterministic noise: forces in the bulk too */
                    for (int d = 0; d < 3; d++) {
                        r = r * 6364136223846793005ull + 1442695040888963407ull;
                        x[d] += 0.1 * ((double)(r >> 11) / 9007199254740992.0 - 0.5);
                    }
                    at += snprintf(body + at, sizeof body - (size_t)at,
                                   "Cu %.10g %.10g %.10g 100 0 0\n", x[0], x[1], x[2]);
                }
    snprintf(text, sizeof text,
             "%d\nLattice=\"60 0 0 0 %.10g 0 0 0 %.10g\" "
             "Properties=species:S:1:pos:R:3:vel:R:3 pbc=\"T T T\"\n%s",
             n, 4 * a, 4 * a, body);
    const char *xpath = th_write_temp(1, "plate.xyz", text);
    /* no grid: on 2 ranks and on 4 the bricks cut the 60 Å axis (the
     * smallest brick surface), so one case file restarts on any count */
    const char *common = "seed: 6\nsystem:\n  read_xyz: %s\n"
                         "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                         "md: {steps: 100}\n"
                         "output: {thermo_every: 10, checkpoint_every: 55}\n"
                         "parallel: {balance: shift%s}\n";
    char yaml[1024];
    snprintf(yaml, sizeof yaml, common, xpath, ", balance_every: 10, balance_threshold: 1.05");
    const char *p2 = th_write_temp(2, "plate.yaml", yaml);
    snprintf(yaml, sizeof yaml, common, xpath, "");
    const char *pst = th_write_temp(3, "plate_static.yaml", yaml);
    char d0[600], d2[600], d4[600], dst[600];
    snprintf(d0, sizeof d0, "%s/plate-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/plate-2", th_temp_dir());
    snprintf(d4, sizeof d4, "%s/plate-4", th_temp_dir());
    snprintf(dst, sizeof dst, "%s/plate-static", th_temp_dir());
    thb_must_run(p2, 0, d0, NULL);
    thb_must_run(p2, 2, d2, NULL);
    thb_must_run(p2, 4, d4, NULL);
    thb_must_run(pst, 2, dst, NULL);
    compare_series(d0, d2, "dynamic balance, 2 ranks");
    compare_metrics(d0, d2, "dynamic balance, 2 ranks");
    compare_snapshot(d0, d2, 100, "dynamic balance, 2 ranks");
    compare_series(d0, d4, "dynamic balance, 4 ranks");
    compare_metrics(d0, d4, "dynamic balance, 4 ranks");
    compare_snapshot(d0, d4, 100, "dynamic balance, 4 ranks");
    thb_check_parallel_record(d2, 2, n);
    thb_check_parallel_record(d4, 4, n);
    long checks, shifts;
    double worst;
    double ist = static_imbalance(dst);
    double idy = thb_balance_record(d2, &checks, &shifts, &worst);
    cr_log_info("moving plate, 2 bricks along x: final max/mean %.3f static, %.3f dynamic "
                "(%ld checks, %ld shifts, worst at a check %.3f)",
                ist, idy, checks, shifts, worst);
    /* the plate moved 10 Å past the set-up's cut, inside the upper brick */
    cr_assert_gt(ist, 1.9, "static cuts: max/mean %g", ist);
    /* a check at the first list build of every 10 steps (the plate
     * crosses half the skin in a few steps, so builds are frequent) and
     * the cuts moved; 1 Å between checks is less than the 1.8 Å between
     * (200) planes of 32 atoms: a check finds one plane on the wrong side
     * (max/mean 1 + 64 / 384), two at most */
    cr_assert_geq(checks, 8, "%ld checks in 100 steps", checks);
    cr_assert_geq(shifts, 3, "%ld shifts", shifts);
    cr_assert_leq(worst, 1.0 + 2 * 64.0 / n + 1e-9, "worst at a check %g", worst);
    cr_assert_leq(idy, 1.0 + 2 * 64.0 / n + 1e-9, "final max/mean %g", idy);
    const struct thb_restart cases[] = {{d2, 2, "2 to 2", d2}, {d2, 0, "2 to 1", NULL},
                                        {d2, 4, "2 to 4", NULL}, {d4, 2, "4 to 2", NULL}};
    thb_restarts_match(p2, 55, cases, 4, d0, compare_restarted);
    /* 2 to 2 (ck-restart-0): both runs went on with the cuts of the stored
     * atoms, so the last snapshot is the uninterrupted run's bit for bit */
    char r22[700];
    snprintf(r22, sizeof r22, "%s/ck-restart-0", th_temp_dir());
    static const char *const sets[] = {"position", "velocity", "force", NULL};
    static const int ncomp[] = {3, 3, 3};
    thb_compare_snapshot(d2, r22, "/particles/00000100", sets, ncomp, 0.0, "2 to 2, bitwise");
}

/* A case type that is not decomposed runs whole on every rank, and says so */
Test(bricks, other_case_types_say_they_are_not_decomposed, .timeout = 300)
{
    const char *path = th_write_temp(0, "crystal.yaml",
                                     "type: crystal\ncrystal: {lattice: fcc, element: Cu, a_min: "
                                     "3.4, a_max: 3.8, cells: 3}\npotential: {style: sutton_chen}\n"
                                     "output: {hdf5: false}\n");
    char d0[600], d2[600];
    static char out[16384];
    snprintf(d0, sizeof d0, "%s/crystal-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/crystal-2", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    cr_assert_eq(thb_run(path, 2, d2, NULL, out, sizeof out), 0, "%s", out);
    cr_assert(strstr(out, "note: case type 'crystal' is not decomposed into bricks yet"), "%s",
              out);
    json_t *a = thb_result(d0), *b = thb_result(d2);
    double x = thb_metric(a, "lattice_constant"), y = thb_metric(b, "lattice_constant");
    cr_assert_eq(x, y, "lattice constant %.17g vs %.17g", x, y);
    cr_assert_null(json_object_get(b, "parallel"));
    json_decref(a);
    json_decref(b);
}

/* Distributed set-up: each rank builds only its brick's lattice sites, yet
 * the atoms are those of the serial build: a sphere region keeps some sites
 * (ids count the kept sites of the whole lattice), `displace` moves each
 * by the serial amounts (one sequence run through by every rank, each
 * keeping its ids' draws: positions equal bitwise) and the Maxwell
 * velocities are the serial draws (the momentum and temperature sums run
 * over the ranks: equal to round-off, 1e-13 of the largest). */
Test(bricks, setup_builds_the_serial_atoms_brick_by_brick, .timeout = 600)
{
    const char *yaml = "seed: 11\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [8, 8, 8]}\n"
                       "  element: Cu\n  displace: 0.05\n"
                       "  region: {shape: sphere, center: [14.46, 14.46, 14.46], radius: 13}\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {steps: 0, temperature: 500}\n"
                       "parallel: {decomposition: bricks}\n";
    const char *path = th_write_temp(0, "setup.yaml", yaml);
    char d0[600], d4[600];
    snprintf(d0, sizeof d0, "%s/setup-serial", th_temp_dir());
    snprintf(d4, sizeof d4, "%s/setup-4", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 4, d4, NULL);
    long na = thb_compare_setup(d0, d4, 1.0, 1e-13, "set-up on 4 ranks");
    cr_assert(na > 100 && na < 2048, "the region keeps %ld of 2048 sites", na);
    long nid;
    struct thb_by_id *oa = thb_order_by_id(d0, "/particles/00000000", &nid);
    cr_assert_eq(oa[na - 1].id, na, "ids run 1..%ld", na);
    free(oa);
    thb_check_parallel_record(d4, 4, na);
}

/* A checkpoint holding one id twice, the two copies in different bricks:
 * each rank reads only its brick's atoms and sees no repeat, so the ranks
 * compare their ids; the restart is refused naming the file. */
Test(bricks, restart_refuses_an_id_on_two_ranks, .timeout = 600)
{
    const char *yaml = "seed: 3\nsystem:\n  lattice: {style: fcc, a: 3.615, cells: [6, 6, 6]}\n"
                       "  element: Cu\npotential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md: {steps: 20, temperature: 600}\n"
                       "parallel: {grid: [1, 1, 2]}\n"
                       "output: {thermo_every: 10, checkpoint_every: 10}\n";
    const char *path = th_write_temp(0, "dup.yaml", yaml);
    char run[600], dir[700], from[700], ck[800];
    snprintf(run, sizeof run, "%s/dup-run", th_temp_dir());
    thb_must_run(path, 2, run, NULL);
    snprintf(dir, sizeof dir, "%s/dup-restart", th_temp_dir());
    snprintf(from, sizeof from, "%s/checkpoint-0000000010.h5", run);
    snprintf(ck, sizeof ck, "%s/checkpoint-0000000010.h5", dir);
    cr_assert_eq(thb_mkdir_copy(from, dir, ck), 0);
    /* the atom lowest in z takes the id of the one highest in z */
    hid_t f = H5Fopen(ck, H5F_ACC_RDWR, H5P_DEFAULT);
    cr_assert_geq(f, 0);
    hid_t dx = H5Dopen2(f, "/model/md/atoms/x", H5P_DEFAULT);
    hid_t di = H5Dopen2(f, "/model/md/atoms/id", H5P_DEFAULT);
    cr_assert(dx >= 0 && di >= 0, "checkpoint layout");
    hid_t sp = H5Dget_space(di);
    long n = (long)H5Sget_simple_extent_npoints(sp);
    H5Sclose(sp);
    double *x = malloc((size_t)n * 3 * sizeof *x);
    int64_t *id = malloc((size_t)n * sizeof *id);
    cr_assert(x && id);
    cr_assert_geq(H5Dread(dx, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x), 0);
    cr_assert_geq(H5Dread(di, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, id), 0);
    long lo = 0, hi = 0;
    for (long i = 1; i < n; i++) {
        if (x[3 * i + 2] < x[3 * lo + 2]) lo = i;
        if (x[3 * i + 2] > x[3 * hi + 2]) hi = i;
    }
    id[lo] = id[hi];
    cr_assert_geq(H5Dwrite(di, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, id), 0);
    H5Dclose(dx);
    H5Dclose(di);
    H5Fclose(f);
    free(x);
    free(id);
    static char out[16384];
    const char *extra[] = {"--restart", NULL};
    int rc = thb_run(path, 2, dir, extra, out, sizeof out);
    cr_assert_neq(rc, 0, "restart with a repeated id ran:\n%s", out);
    cr_assert(strstr(out, "1 id(s) given twice") && strstr(out, "checkpoint-0000000010.h5"), "%s",
              out);
}

/* The impact geometry: a Cu slab (8 x 8 x 5 cells, periodic across, free
 * along z) with a cluster of 43 atoms 12 Å above it, on 4 bricks along z.
 * Equal bricks leave one brick empty and the cluster's nearly so (max /
 * mean about 2); `balance: shift` moves the cuts to the atoms' quantiles
 * along z (each brick still cutoff + skin wide): the imbalance falls
 * below 0.75 of it, and the trajectory is the serial one to 1e-10. */
Test(bricks, shift_balance_evens_a_cluster_above_a_slab, .timeout = 600)
{
    const double a = 3.615;
    static char text[1 << 17];
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    int n = 0, at = 0;
    char body[1 << 17];
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++)
            for (int k = 0; k < 5; k++)
                for (int b = 0; b < 4; b++, n++)
                    at += snprintf(body + at, sizeof body - (size_t)at, "Cu %.10g %.10g %.10g\n",
                                   (i + basis[b][0]) * a, (j + basis[b][1]) * a,
                                   (k + basis[b][2]) * a + 0.1);
    const double c[3] = {4 * a, 4 * a, 5 * a + 12.0 + 2 * a};
    for (int i = -3; i <= 3; i++)
        for (int j = -3; j <= 3; j++)
            for (int k = -3; k <= 3; k++)
                for (int b = 0; b < 4; b++) {
                    double x[3] = {(i + basis[b][0]) * a, (j + basis[b][1]) * a,
                                   (k + basis[b][2]) * a};
                    if (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] > 5.5 * 5.5)
                        continue;
                    at += snprintf(body + at, sizeof body - (size_t)at, "Cu %.10g %.10g %.10g\n",
                                   c[0] + x[0], c[1] + x[1], c[2] + x[2]);
                    n++;
                }
    snprintf(text, sizeof text,
             "%d\nLattice=\"%.10g 0 0 0 %.10g 0 0 0 %.10g\" Properties=species:S:1:pos:R:3 "
             "pbc=\"T T F\"\n%s",
             n, 8 * a, 8 * a, 60.0, body);
    const char *xpath = th_write_temp(1, "impact.xyz", text);
    char yaml[1024], yaml_eq[1024];
    const char *common = "seed: 6\nsystem:\n  read_xyz: %s\n  boundary: [periodic, periodic, free]\n"
                         "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                         "md: {steps: 100, temperature: 300}\n"
                         "output: {thermo_every: 10}\n"
                         "parallel: {grid: [1, 1, 4]%s}\n";
    snprintf(yaml, sizeof yaml, common, xpath, ", balance: shift");
    snprintf(yaml_eq, sizeof yaml_eq, common, xpath, "");
    const char *path = th_write_temp(2, "impact.yaml", yaml);
    const char *path_eq = th_write_temp(3, "impact_eq.yaml", yaml_eq);
    char d0[600], dbal[600], deq[600];
    snprintf(d0, sizeof d0, "%s/impact-serial", th_temp_dir());
    snprintf(dbal, sizeof dbal, "%s/impact-shift", th_temp_dir());
    snprintf(deq, sizeof deq, "%s/impact-equal", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 4, dbal, NULL);
    thb_must_run(path_eq, 4, deq, NULL);
    compare_series(d0, dbal, "shift balance");
    compare_metrics(d0, dbal, "shift balance");
    compare_snapshot(d0, dbal, 100, "shift balance");
    thb_check_parallel_record(dbal, 4, n);
    thb_check_parallel_record(deq, 4, n);
    json_t *rb = thb_result(dbal), *re = thb_result(deq);
    double ib = json_real_value(json_object_get(json_object_get(rb, "parallel"),
                                                "imbalance_max_over_mean"));
    double ie = json_real_value(json_object_get(json_object_get(re, "parallel"),
                                                "imbalance_max_over_mean"));
    cr_log_info("impact geometry, 4 bricks along z: imbalance max/mean %.3f equal, %.3f shift",
                ie, ib);
    cr_assert_gt(ie, 1.6, "equal bricks: imbalance %g", ie);
    cr_assert_lt(ib, 0.75 * ie, "shift: imbalance %g against %g of equal bricks", ib, ie);
    json_decref(rb);
    json_decref(re);
}
