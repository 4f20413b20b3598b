/*
 * Checkpoint and restart of the DPD/MPM case types (engine/model_dpd_mpm.c):
 * a run killed with SIGKILL at an exact step -- one between output steps,
 * one on a thermo, snapshot and checkpoint step -- and restarted from its
 * newest checkpoint ends bitwise where the uninterrupted run ends: every
 * metric and series of result.json, the thermo rows, the last snapshot of
 * the DPD particles (and of the material points), the final state.
 *
 * The concurrent impact runs four instances of the model (flyer run and
 * reference run, concurrent and all-DPD), each with its own checkpoint
 * group; the grid impact two; the grid tensile rod one, with its rigid
 * grips.  Small bars (432 particles) and DPDE, whose internal energies and
 * heat accumulators must come back exactly.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/models.h"
#include "helpers/th.h"
#include "helpers/th_restart.h"

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

static const char *const particle_fields[] = {"position", "velocity", "force", "u_internal", NULL};
static const char *const point_fields[] = {"position", "velocity", "stress", NULL};

static json_t *result_of(const char *out)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/result.json", th_temp_dir(), out);
    json_t *r = json_load_file(path, 0, NULL);
    cr_assert_not_null(r, "no %s", path);
    return r;
}

/* Every series of result.json equal (the sample histories, profiles and
 * stress-strain curve are accumulated over the run). */
static void assert_same_series(const char *a, const char *b)
{
    json_t *ra = result_of(a), *rb = result_of(b);
    json_t *sa = json_object_get(ra, "series"), *sb = json_object_get(rb, "series");
    cr_assert_gt(json_object_size(sa), 2);
    cr_assert_eq(json_object_size(sa), json_object_size(sb));
    const char *k;
    json_t *v;
    json_object_foreach(sa, k, v)
    {
        json_t *w = json_object_get(sb, k);
        cr_assert_not_null(w, "series %s missing after the restart", k);
        cr_assert(json_equal(v, w), "series %s differs after the restart", k);
    }
    json_decref(ra);
    json_decref(rb);
}

/* The final state files (LAMMPS data, %.17g) equal below their header. */
static void assert_same_final_state(const char *a, const char *b)
{
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s/final.data", th_temp_dir(), a);
    snprintf(pb, sizeof pb, "%s/%s/final.data", th_temp_dir(), b);
    char *ta = th_restart_slurp(pa, NULL), *tb = th_restart_slurp(pb, NULL);
    const char *ra = strchr(ta, '\n'), *rb = strchr(tb, '\n');
    cr_assert(ra && rb);
    cr_assert_str_eq(ra, rb, "final state differs after the restart");
    free(ta);
    free(tb);
}

/* 300 steps (the wave reaches both regions: every metric is a number);
 * checkpoints every 50; kills at 130 (no output there) and 200 (thermo,
 * snapshot, profile and checkpoint). */
static const char *const kills[] = {"130", "200", NULL};

#define OUTPUT                                                                                    \
    "output: {thermo_every: 25, snapshot_every: 100, checkpoint_every: 50, "                      \
    "final_state: final.data}\n"

/* The 12 x 3 x 3 cell bar of test_dpd_mpm_cli.c at 100 K, DPDE, 300 steps. */
static void impact_case(char *buf, size_t len, const char *type, const char *bc,
                        const char *extra)
{
    snprintf(buf, len,
             "type: %s\nseed: 3\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [12, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, %s, %s]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: 300\n"
             "  initial_temperature: 100\n"
             "impact:\n  regions: [25.0, 55.0]\n  sample_every: 3\n"
             "  arrival_threshold: 0.002\n  profile_times: [0.25, 1.0, 1.4]\n"
             "grid:\n  cell: 4.0\n%s" OUTPUT,
             type, bc, bc, extra);
}

/* A metric of out/result.json that is a number (not null): the comparisons
 * above compare a measurement, not two NaNs. */
static void assert_measured(const char *out, const char *name)
{
    json_t *r = result_of(out);
    json_t *v = json_object_get(json_object_get(json_object_get(r, "metrics"), name), "value");
    cr_assert(json_is_number(v), "%s: metric %s is not a number", out, name);
    json_decref(r);
}

static void check_restarts(const char *yaml, int points)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    th_kill_and_restart(yaml, kills, 1, "particles", particle_fields);
    for (int k = 0; kills[k]; k++) {
        char out[32];
        snprintf(out, sizeof out, "killed-%s", kills[k]);
        assert_same_series("full", out);
        assert_same_final_state("full", out);
        if (points)
            th_restart_assert_same_snapshot("full", out, "points", point_fields);
    }
}

/* Concurrent DPD/MPM: DPD particles, material points with partners, the
 * all-DPD comparison run and both reference runs -- four model instances. */
Test(restart_dpd_mpm, concurrent_impact_continues_bitwise, .timeout = 600)
{
    char yaml[2048];
    impact_case(yaml, sizeof yaml, "dpd_mpm_impact", "free",
                "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n");
    check_restarts(yaml, 1);
    assert_measured("full", "wave_speed_fit");
    assert_measured("full", "wave_speed_threshold");
    assert_measured("full", "reflection_ratio");
}

/* The DPD/MPM-grid model: the target carried by the grid, free flyer. */
Test(restart_dpd_mpm, grid_impact_continues_bitwise, .timeout = 600)
{
    char yaml[2048];
    impact_case(yaml, sizeof yaml, "dpd_grid_impact", "periodic", "");
    check_restarts(yaml, 0);
    assert_measured("full", "wave_speed_fit");
    assert_measured("full", "wave_speed_threshold");
}

/* The grid tensile rod: prescribed grips, stress samples averaged over
 * sample_every = 7 steps, so the checkpoints fall inside a sample. */
Test(restart_dpd_mpm, grid_tensile_continues_bitwise, .timeout = 600)
{
    char yaml[2048];
    snprintf(yaml, sizeof yaml,
             "type: dpd_grid_tensile\nseed: 5\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [12, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, free, free]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: 300\n"
             "  initial_temperature: 100\n"
             "tensile:\n  velocity: 1.0\n  sample_every: 7\n"
             "grid:\n  cell: 4.0\n" OUTPUT);
    check_restarts(yaml, 0);
    assert_measured("full", "peak_stress");
}

/* Every metric equal, bit for bit (NaN equal to NaN). */
static void assert_same_metrics(const char *a, const char *b)
{
    json_t *ra = result_of(a), *rb = result_of(b);
    json_t *ma = json_object_get(ra, "metrics"), *mb = json_object_get(rb, "metrics");
    cr_assert_gt(json_object_size(ma), 5);
    cr_assert_eq(json_object_size(ma), json_object_size(mb));
    const char *k;
    json_t *v;
    json_object_foreach(ma, k, v)
    {
        json_t *w = json_object_get(json_object_get(mb, k), "value");
        json_t *u = json_object_get(v, "value");
        cr_assert_not_null(w, "metric %s missing", k);
        double x = json_number_value(u), y = json_number_value(w);
        cr_assert(json_is_null(u) ? json_is_null(w) : memcmp(&x, &y, sizeof x) == 0,
                  "metric %s: %.17g vs %.17g", k, x, y);
    }
    json_decref(ra);
    json_decref(rb);
}

/* Writing checkpoints leaves the run as it is: periodic across, where a
 * neighbour-list rebuild at the checkpoint would wrap particles at other
 * steps (and the MPM grid is not periodic). */
Test(restart_dpd_mpm, checkpoints_do_not_change_the_run, .timeout = 300)
{
    char yaml[2048];
    impact_case(yaml, sizeof yaml, "dpd_grid_impact", "periodic", "");
    th_write_temp(2, "cg.yaml", PARAMS);
    const char *with = th_write_temp(1, "case.yaml", yaml);
    char msg[8192];
    cr_assert_eq(th_restart_solve("with", with, NULL, NULL, msg, sizeof msg), 0, "%s", msg);
    char *p = strstr(yaml, "checkpoint_every: 50");
    cr_assert_not_null(p);
    memcpy(p, "checkpoint_every:  0", strlen("checkpoint_every:  0"));
    const char *without = th_write_temp(3, "plain.yaml", yaml);
    cr_assert_eq(th_restart_solve("without", without, NULL, NULL, msg, sizeof msg), 0, "%s",
                 msg);
    assert_same_metrics("without", "with");
    assert_same_series("without", "with");
    assert_same_final_state("without", "with");
}

/* Two instances of one model need two checkpoint groups. */
Test(restart_dpd_mpm, model_instances_need_distinct_names)
{
    struct sim s;
    struct err e = {0};
    sim_init(&s, NULL, 10, 0.001);
    int a = 0, b = 0;
    cr_assert_eq(sim_add_model(&s, &sim_model_dpd_mpm, &a, &e), 0);
    cr_assert_neq(sim_add_model(&s, &sim_model_dpd_mpm, &b, &e), 0);
    cr_assert(strstr(e.msg, "two models named dpd_mpm"), "%s", e.msg);
    cr_assert_eq(sim_add_model_named(&s, &sim_model_dpd_mpm, &b, "dpd_mpm_reference", &e), 0);
    cr_assert_eq(s.nmodels, 2);
    cr_assert_str_eq(s.model[1].name, "dpd_mpm_reference");
}
