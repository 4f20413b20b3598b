/*
 * Checkpoint and restart of the mpm case type (engine/model_mpm.c).
 *
 * A run killed with SIGKILL at an exact step and restarted from its newest
 * checkpoint ends as the uninterrupted run does, bitwise on one thread:
 * every metric of result.json (time step range, largest energy changes,
 * kinetic energy at the report steps, reactions, probes), every thermo row,
 * and the last snapshot's point fields.  Each case is killed once between
 * output steps and once on an output (and checkpoint) step.
 *
 * - J2 plasticity: a flyer plate drives the target past yield, so the
 *   plastic strain (the J2 state) decides the stresses after the restart;
 *   points are reordered every 7 steps.
 * - An elastic, closed system on the adaptive CFL step: the time step after
 *   the restart comes from the stored largest speed, the energy check from
 *   the stored initial energy; the fused pass (mpm.h) leaves the next
 *   step's mapping on the grid, which the checkpoint carries.  Writing
 *   checkpoints does not change the run.
 * - A hierarchical grid with a ramped load and a probe: external forces and
 *   the load factor.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <stdio.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_restart.h"

static const char *const point_fields[] = {"position", "velocity", "stress",
                                           "deformation_gradient", "volume", "strain_energy",
                                           NULL};

static json_t *result_of(const char *out_name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/result.json", th_temp_dir(), out_name);
    json_error_t je;
    json_t *r = json_load_file(path, 0, &je);
    cr_assert_not_null(r, "%s: %s", path, je.text);
    return r;
}

static double metric(json_t *r, const char *name)
{
    json_t *m = json_object_get(json_object_get(r, "metrics"), name);
    cr_assert_not_null(m, "metric %s missing", name);
    return json_number_value(json_object_get(m, "value"));
}

Test(restart_mpm, j2_flyer_plate_continues_bitwise, .timeout = 300)
{
    const char *yaml =
        "type: mpm\n"
        "mpm:\n"
        "  grid: {cell: 4.0, cells: [40, 4, 4],\n"
        "         faces: {y_lo: sliding, y_hi: sliding, z_lo: sliding, z_hi: sliding}}\n"
        "  materials:\n"
        "    - {name: Cu, law: j2, density: 8.94, E: 128.0, nu: 0.34, yield: 0.5, "
        "hardening: 0.5}\n"
        "  bodies:\n"
        "    - {name: flyer, material: Cu, velocity: [10.0, 0, 0],\n"
        "       region: {shape: box, lo: [8, 0, 0], hi: [40, 16, 16]}}\n"
        "    - {name: target, material: Cu, region: {shape: box, lo: [41, 0, 0], "
        "hi: [140, 16, 16]}}\n"
        "  steps: 150\n"
        "  sort_every: 7\n"
        "  report_steps: [0, 30, 100]\n"
        "  probes: [{name: mid, region: {shape: box, lo: [80, 0, 0], hi: [100, 16, 16]}}]\n"
        "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 20}\n";
    static const char *const fields[] = {"position", "velocity", "stress", "plastic_strain",
                                         "deformation_gradient", "volume", NULL};
    /* 65: between outputs (continues from 60); 100: thermo, snapshot and
     * checkpoint step */
    const char *const kills[] = {"65", "100", NULL};
    th_kill_and_restart(yaml, kills, 1, "points", fields);
    /* past yield: the radial return caps the von Mises stress at
     * yield + H eps_p, so a larger one means plastic strain */
    json_t *r = result_of("full");
    cr_assert_gt(metric(r, "von_mises_max"), 0.6, "the target did not yield");
    json_decref(r);
}

Test(restart_mpm, elastic_adaptive_step_continues_bitwise, .timeout = 300)
{
    static const char *body =
        "type: mpm\n"
        "mpm:\n"
        "  units: si\n"
        "  grid: {cell: 0.05, cells: [13, 7, 7]}\n"
        "  materials:\n"
        "    - {name: al, law: linear_elastic, density: 2700, E: 70.0e9, nu: 0.3}\n"
        "  bodies:\n"
        "    - {name: A, material: al, region: {shape: box, lo: [0.05, 0.05, 0.05], hi: [0.30, "
        "0.30, 0.30]}, velocity: [50, 0, 0]}\n"
        "    - {name: B, material: al, region: {shape: box, lo: [0.35, 0.05, 0.05], hi: [0.60, "
        "0.30, 0.30]}, velocity: [-50, 0, 0]}\n"
        "  steps: 200\n"
        "  report_steps: [40, 80, 200]\n";
    char yaml[2048], plain[2048];
    snprintf(yaml, sizeof yaml, "%soutput: {thermo_every: 20, snapshot_every: 50, "
                                "checkpoint_every: 20}\n", body);
    snprintf(plain, sizeof plain, "%soutput: {thermo_every: 20, snapshot_every: 50}\n", body);
    const char *const kills[] = {"65", "100", NULL};
    th_kill_and_restart(yaml, kills, 1, "points", point_fields);
    json_t *r = result_of("full");
    cr_assert_lt(metric(r, "timestep_min"), metric(r, "timestep_max"),
                 "the time step did not adapt");
    /* a run without checkpoints: the same numbers */
    char msg[8192];
    const char *path = th_write_temp(2, "plain.yaml", plain);
    cr_assert_eq(th_restart_solve("plain", path, NULL, NULL, msg, sizeof msg), 0, "%s", msg);
    json_t *p = result_of("plain");
    const char *k;
    json_t *v;
    json_object_foreach(json_object_get(r, "metrics"), k, v)
    {
        double x = json_number_value(json_object_get(v, "value")), y = metric(p, k);
        cr_assert(memcmp(&x, &y, sizeof x) == 0, "metric %s: %.17g with checkpoints, %.17g without",
                  k, x, y);
    }
    json_decref(p);
    json_decref(r);
}

Test(restart_mpm, hierarchical_grid_ramped_load_continues_bitwise, .timeout = 300)
{
    const char *yaml =
        "type: mpm\n"
        "mpm:\n"
        "  grid:\n"
        "    cell: 2.0\n"
        "    cells: [16, 4, 4]\n"
        "    levels: [{coarsen: xyz, region: {shape: slab, axis: x, lo: 16, hi: 100}}]\n"
        "  materials: [{name: cu, law: cubic_elastic, density: 8.96, C11: 170, C12: 122, "
        "C44: 75}]\n"
        "  bodies: [{name: A, material: cu, region: {shape: box, lo: [0, 0, 0], hi: [32, 8, "
        "8]}}]\n"
        "  loads: [{region: {shape: box, lo: [0, 0, 0], hi: [1, 8, 8]}, normal: x, "
        "traction: [1.0, 0, 0]}]\n"
        "  load_ramp: 0.5\n"
        "  probes: [{name: mid, region: {shape: box, lo: [8, 0, 0], hi: [12, 8, 8]}}]\n"
        "  steps: 60\n"
        "output: {thermo_every: 5, snapshot_every: 30, checkpoint_every: 20}\n";
    /* 27: between outputs (continues from 20); 40: thermo and checkpoint step */
    const char *const kills[] = {"27", "40", NULL};
    th_kill_and_restart(yaml, kills, 1, "points", point_fields);
}
