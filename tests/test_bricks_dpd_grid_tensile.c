/*
 * The DPD/MPM-grid tensile rod on bricks (docs/dpd_mpm.md "Under MPI",
 * docs/parallel.md): under mpirun `dpd_grid_tensile` splits the rod's DPD
 * particles over bricks of the DPD halo, while every rank holds the whole
 * (small) MPM grid, maps its own particles to it and sums the nodes over
 * the ranks (mass, momentum, force of s1-s3b and the MUSL remap of s11).
 * The grips are prescribed bodies whose force is a sum over the ranks.
 * The grid model has no Shardlow sweep: every pair force is evaluated at
 * x(t), v(t) with the random number keyed on the pair's ids and the step,
 * so only the order of the sums changes (pair forces on a ghost returned
 * by the reverse communication, node sums over ranks); over 100 steps the
 * thermo series, the metrics and the stress-strain curve, and the last
 * snapshot (positions, velocities, forces, DPDE internal energies,
 * matched by id) agree with the serial run to 1e-10 relative, on 1, 2 and
 * 4 ranks.  A checkpoint written on 2 ranks restarts serially and on 4
 * (to the same tolerance) and on 2 (bitwise: the same arithmetic).
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10
#define NPART 432

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

/* The 12 x 3 x 3-cell rod (432 particles, 87 Å, free surfaces) at 100 K,
 * DPDE on a 4 Å grid, ends pulled at 1 Å/ps each: 100 steps of 5 fs. */
static void rod_case(char *buf, size_t len, const char *output, const char *parallel)
{
    snprintf(buf, len,
             "type: dpd_grid_tensile\nseed: 5\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [12, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, free, free]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: 100\n"
             "  initial_temperature: 100\n"
             "tensile: {velocity: 1.0, sample_every: 5}\n"
             "grid: {cell: 4.0}\n%s%s",
             output, parallel);
}

#define OUTPUT "output: {thermo_every: 10, snapshot_every: 50}\n"
#define OUTPUT_CK "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 50}\n"

static const char *const series_cols[] = {"pe_eV",  "ke_eV",     "uint_eV", "etotal_eV",
                                          "temp_K", "press_GPa", NULL};
static const char *const metrics[] = {"peak_stress",   "strain_at_peak", "strain_final",
                                      "particles",     "grip_particles", "temperature",
                                      "grid_nodes",    "heat_dr",        "heat_grid",
                                      "internal_temperature", NULL};

/* result.json's series `name` of b against a, to REL of its largest value */
static void compare_result_series(json_t *ra, json_t *rb, const char *name, const char *tag)
{
    json_t *a = json_object_get(json_object_get(ra, "series"), name);
    json_t *b = json_object_get(json_object_get(rb, "series"), name);
    json_t *va = json_is_object(a) ? json_object_get(a, "values") : a;
    json_t *vb = json_is_object(b) ? json_object_get(b, "values") : b;
    cr_assert(json_is_array(va) && json_is_array(vb), "%s: series %s missing", tag, name);
    size_t n = json_array_size(va);
    cr_assert_eq(n, json_array_size(vb), "%s: series %s length", tag, name);
    cr_assert_gt(n, 10, "%s: series %s has %zu values", tag, name, n);
    double scale = 0;
    for (size_t k = 0; k < n; k++)
        scale = fmax(scale, fabs(json_number_value(json_array_get(va, k))));
    for (size_t k = 0; k < n; k++) {
        double x = json_number_value(json_array_get(va, k));
        double y = json_number_value(json_array_get(vb, k));
        cr_assert_leq(fabs(x - y), REL * scale + 1e-12 * fabs(x), "%s: %s[%zu] %.17g vs %.17g",
                      tag, name, k, x, y);
    }
}

static void compare_runs(const char *a, const char *b, const char *tag)
{
    thb_compare_series(a, b, series_cols, REL, tag);
    thb_compare_metrics(a, b, metrics, REL, tag);
    json_t *ra = thb_result(a), *rb = thb_result(b);
    compare_result_series(ra, rb, "stress", tag);
    json_decref(ra);
    json_decref(rb);
    static const char *const sets[] = {"position", "velocity", "force", "u_internal", NULL};
    static const int ncomp[] = {3, 3, 3, 1};
    thb_compare_snapshot(a, b, "/particles/00000100", sets, ncomp, REL, tag);
}

/* The run measured something: the rod was stretched against its
 * cohesion, and the grid and the D + R forces exchanged heat. */
static void assert_measured(const char *dir)
{
    json_t *r = thb_result(dir);
    cr_assert_gt(thb_metric(r, "peak_stress"), 0.1, "%s: no tension", dir);
    cr_assert_eq(thb_metric(r, "particles"), NPART);
    cr_assert_gt(fabs(thb_metric(r, "heat_grid")), 1e-3, "%s: no grid heat", dir);
    cr_assert_gt(fabs(thb_metric(r, "heat_dr")), 1e-4, "%s: no D + R heat", dir);
    json_decref(r);
}

Test(bricks_dpd_grid_tensile, matches_serial_on_1_2_4_ranks, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048];
    rod_case(yaml, sizeof yaml, OUTPUT, "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "rod.yaml", yaml);
    static const int nps[] = {1, 2, 4};
    thb_matches_serial(path, "rod", nps, 3, NPART, assert_measured, compare_runs,
                       "grid tensile");
}

/* Without a `parallel` section (auto) 2 ranks take bricks, with no note
 * that the case is not decomposed; a checkpoint of step 50 written there,
 * restarted serially, on 4 and on 2 ranks: each ends where the uninterrupted serial
 * run ends (to REL), and the 2-rank restart is the 2-rank run's thermo,
 * bitwise. */
Test(bricks_dpd_grid_tensile, checkpoint_moves_between_rank_counts, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048];
    rod_case(yaml, sizeof yaml, OUTPUT_CK, "");
    thb_checkpoint_moves(th_write_temp(0, "rod_ck.yaml", yaml), "rod", compare_runs,
                         "grid tensile");
}

/* An 8-cell rod (58 Å) on 4 ranks: too short for bricks at the reach the
 * first ghost build takes (17.27 Å), so `auto` falls back to replicated
 * data with a note (it stopped with "the box shrank" before 2026-11-28). */
Test(bricks_dpd_grid_tensile, short_rod_replicates_under_auto, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    rod_case(yaml, sizeof yaml, "output: {thermo_every: 10}\n", "");
    char *cells = strstr(yaml, "cells: [12, 3, 3]");
    cr_assert_not_null(cells);
    memcpy(cells, "cells: [ 8, 3, 3]", 17);
    thb_short_replicates(th_write_temp(0, "rshort.yaml", yaml), 4, "rshort");
}

/* The rod read from a data file (the final state of one serial step):
 * rank 0 reads it, broadcasts the rod's extent with the box, and every
 * rank plans the same bricks on it before receiving its brick's
 * particles (md_system_split.on_extent); on 1, 2 and 4 ranks the run
 * matches the serial one to REL. */
Test(bricks_dpd_grid_tensile, rod_from_a_data_file_matches_serial, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048], mk[600];
    rod_case(yaml, sizeof yaml, "output: {final_state: rod.data}\n", "");
    char *st = strstr(yaml, "steps: 100");
    cr_assert_not_null(st);
    memcpy(st, "steps: 1  ", 10);
    snprintf(mk, sizeof mk, "%s/rod-data-maker", th_temp_dir());
    thb_must_run(th_write_temp(0, "rod_mk.yaml", yaml), 0, mk, NULL);
    char data[700], system[1024];
    snprintf(data, sizeof data, "%s/rod.data", mk);
    snprintf(system, sizeof system, "  read_data: %s\n  elements: [Cu]\n", data);
    rod_case(yaml, sizeof yaml, OUTPUT, "parallel: {decomposition: bricks}\n");
    char *lat = strstr(yaml, "  lattice:"), *bnd = strstr(yaml, "  boundary:");
    cr_assert(lat && bnd);
    char tail[2048];
    snprintf(tail, sizeof tail, "%s", bnd);
    snprintf(lat, sizeof yaml - (size_t)(lat - yaml), "%s%s", system, tail);
    const char *path = th_write_temp(1, "rod_data.yaml", yaml);
    static const int nps[] = {1, 2, 4};
    thb_matches_serial(path, "rod-data", nps, 3, NPART, assert_measured, compare_runs,
                       "grid tensile from a data file");
}

/* A restart on bricks selects each rank's particles by their stored
 * positions of the last list build (field_list_position): a NaN there, or
 * a value more than a box length outside the stored box, is refused with
 * exit 2 naming the file and the dataset, printed once. */
Test(bricks_dpd_grid_tensile, restart_refuses_impossible_list_positions, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[2048];
    rod_case(yaml, sizeof yaml, "output: {thermo_every: 10, checkpoint_every: 50}\n",
             "parallel: {decomposition: bricks}\n");
    const char *path = th_write_temp(0, "rod_badlist.yaml", yaml);
    char run[600], ck[700];
    snprintf(run, sizeof run, "%s/rod-badlist-2", th_temp_dir());
    thb_must_run(path, 2, run, NULL);
    snprintf(ck, sizeof ck, "%s/checkpoint-%010d.h5", run, 50);
    double nan = NAN, huge = 1e300, far = -1e5;
    static const char *const name[] = {"nan", "huge", "far"};
    static const char *const want[] = {"a non-finite value of the field it selects by",
                                       "more than a box length outside the stored box",
                                       "more than a box length outside the stored box"};
    const double *val[] = {&nan, &huge, &far};
    for (int k = 0; k < 3; k++) {
        char stem[64], out[16384];
        snprintf(stem, sizeof stem, "rod-badlist-%s", name[k]);
        /* the x component of row 100 (flat: 3 a particle) */
        thb_restart_refuses(path, ck, 50, stem, 2, "/model/dpd_mpm/particles/field_list_position",
                            (long)H5T_NATIVE_DOUBLE, 300, val[k], want[k], out, sizeof out);
        cr_assert(strstr(out, "model/dpd_mpm/particles/field_list_position"), "%s: %s", name[k],
                  out);
    }
}
