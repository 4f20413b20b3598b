/*
 * The DPD/MPM couplings under mpirun (docs/parallel.md, docs/dpd_mpm.md
 * "Under MPI").  The concurrent DPD/MPM impact (dpd_mpm_impact, Chen 2014
 * Sec. 4.2, Fig. 8) is not decomposed into bricks yet (the grid-carried
 * tensile rod and impact are: tests/test_bricks_dpd_grid_tensile.c,
 * tests/test_bricks_dpd_grid_impact.c): a case that asks
 * for bricks (decomposition: bricks, or a grid) stops before the run
 * naming the case file, line and key; under `auto` (and `replicated`)
 * every rank runs the whole case and rank 0 writes, with a note.  So the
 * runs on 2 and 4 ranks are the serial run, bit for bit (the same
 * arithmetic in the same order on every rank): every metric and series of
 * result.json, the thermo rows, the last snapshot of the DPD particles and
 * of the material points.  A checkpoint written on N ranks (by rank 0,
 * the serial layout) restarts on M and ends bitwise where the
 * uninterrupted serial run ends.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"
#include "helpers/th_restart.h"

#define PARAMS                                                                                    \
    "element: Cu\nepsilon: 0.093945\nc: 37.8271\nn: 9\nm: 6\na: 7.23\ncutoff: 10.845\n"          \
    "mass: 508.368\natoms_per_particle: 8\nlattice_constant: 7.2786\n"

/* The 12 x 3 x 3-cell bar (432 particles, 87 Å) of test_restart_dpd_mpm.c
 * at 100 K, DPDE: the half next to the impact face DPD, the far half
 * material points with partners; the all-DPD comparison run and both
 * reference runs make four coupled simulations.  `steps` time steps of
 * 5 fs, the rigid flyer at the default 5 Å/ps. */
static void concurrent_case(char *buf, size_t len, long steps, const char *output,
                            const char *parallel)
{
    snprintf(buf, len,
             "type: dpd_mpm_impact\nseed: 3\nsystem:\n"
             "  lattice: {style: fcc, a: 7.2786, cells: [12, 3, 3]}\n"
             "  element: Cu\n  boundary: [free, free, free]\n"
             "dpd:\n  parameters: cg.yaml\n  timestep: 0.005\n  steps: %ld\n"
             "  initial_temperature: 100\n"
             "impact:\n  regions: [25.0, 55.0]\n  sample_every: 3\n"
             "  arrival_threshold: 0.002\n  profile_times: [0.25]\n"
             "grid:\n  cell: 4.0\n"
             "concurrent:\n  dpd: [-10, 45.2]\n  mpm: [45.2, 100]\n  monitor: 15\n"
             "%s%s",
             steps, output, parallel);
}

#define OUTPUT "output: {thermo_every: 10, snapshot_every: 50, final_state: final.data}\n"
#define OUTPUT_CK                                                                                 \
    "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 50, "                       \
    "final_state: final.data}\n"

static const char *const particle_sets[] = {"position", "velocity", "force", "u_internal", NULL};
static const char *const point_sets[] = {"position", "velocity", "stress", NULL};

/* Every metric of b bitwise that of a (null where a's is null), and every
 * series equal. */
static void assert_same_result(const char *a, const char *b, const char *tag)
{
    json_t *ra = thb_result(a), *rb = thb_result(b);
    json_t *ma = json_object_get(ra, "metrics"), *mb = json_object_get(rb, "metrics");
    cr_assert_gt(json_object_size(ma), 40, "%s: %zu metrics", tag, json_object_size(ma));
    const char *k;
    json_t *v;
    int compared = 0;
    json_object_foreach(ma, k, v)
    {
        json_t *u = json_object_get(v, "value"), *w = json_object_get(json_object_get(mb, k), "value");
        cr_assert(u && w, "%s: metric %s missing", tag, k);
        double x = json_number_value(u), y = json_number_value(w);
        cr_assert(json_is_null(u) ? json_is_null(w) : memcmp(&x, &y, sizeof x) == 0,
                  "%s: metric %s %.17g vs %.17g", tag, k, x, y);
        compared++;
    }
    cr_assert_gt(compared, 40, "%s: %d metrics compared", tag, compared);
    json_t *sa = json_object_get(ra, "series"), *sb = json_object_get(rb, "series");
    cr_assert_gt(json_object_size(sa), 10, "%s: %zu series", tag, json_object_size(sa));
    json_object_foreach(sa, k, v)
    {
        json_t *w = json_object_get(sb, k);
        cr_assert(w && json_equal(v, w), "%s: series %s differs", tag, k);
    }
    json_decref(ra);
    json_decref(rb);
}

/* thermo.csv and the final state (%.17g) equal below their headers. */
static void assert_same_text(const char *a, const char *b, const char *name, const char *tag)
{
    static char ta[1 << 20], tb[1 << 20];
    thb_read_text(a, name, ta, sizeof ta);
    thb_read_text(b, name, tb, sizeof tb);
    const char *xa = strchr(ta, '\n'), *xb = strchr(tb, '\n');
    cr_assert(xa && xb && strlen(xa) > 100, "%s: %s too short", tag, name);
    cr_assert_str_eq(xa, xb, "%s: %s differs", tag, name);
}

/* The run is measured, not a comparison of NaNs: the wave reached region 1
 * and the monitor, the interface forces did work. */
static void assert_measured(const char *dir)
{
    json_t *r = thb_result(dir);
    cr_assert_gt(thb_metric(r, "displacement_max_1"), 0.002, "%s: no wave at region 1", dir);
    cr_assert_gt(thb_metric(r, "incident_amplitude"), 0.1, "%s: no wave at the monitor", dir);
    cr_assert_gt(thb_metric(r, "partners"), 0, "%s: no partners", dir);
    cr_assert_gt(thb_metric(r, "material_points"), 0, "%s: no material points", dir);
    json_decref(r);
}

/* dir relative to th_temp_dir() (th_restart_assert_same_snapshot's form). */
static const char *rel(const char *dir)
{
    size_t n = strlen(th_temp_dir());
    return strncmp(dir, th_temp_dir(), n) == 0 && dir[n] == '/' ? dir + n + 1 : dir;
}

static void assert_same_run(const char *a, const char *b, const char *tag)
{
    assert_same_result(a, b, tag);
    assert_same_text(a, b, "thermo.csv", tag);
    assert_same_text(a, b, "final.data", tag);
    th_restart_assert_same_snapshot(rel(a), rel(b), "particles", particle_sets);
    th_restart_assert_same_snapshot(rel(a), rel(b), "points", point_sets);
}

/* a run restarted from step 50 against the uninterrupted one a */
static void assert_same_restarted(const char *a, const char *b, const char *tag)
{
    json_t *r = thb_result(b);
    cr_assert_eq(json_integer_value(json_object_get(r, "restarted_from_step")), 50,
                 "%s: not restarted from step 50", tag);
    json_decref(r);
    assert_same_result(a, b, tag);
    assert_same_text(a, b, "final.data", tag);
    assert_same_text(a, b, "thermo.csv", tag);
    th_restart_assert_same_snapshot(rel(a), rel(b), "points", point_sets);
}

/* Under `auto` on 2 and 4 ranks: the note, and the serial run bitwise. */
Test(bricks_dpd_mpm, concurrent_impact_on_2_and_4_ranks_is_the_serial_run, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    concurrent_case(yaml, sizeof yaml, 100, OUTPUT, "parallel: {decomposition: auto}\n");
    const char *path = th_write_temp(0, "conc.yaml", yaml);
    char d0[600], dk[600];
    snprintf(d0, sizeof d0, "%s/conc-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    assert_measured(d0);
    static char out[16384];
    static const int nps[] = {2, 4};
    for (int k = 0; k < 2; k++) {
        snprintf(dk, sizeof dk, "%s/conc-%d", th_temp_dir(), nps[k]);
        int rc = thb_run(path, nps[k], dk, NULL, out, sizeof out);
        cr_assert_eq(rc, 0, "%d ranks: exit %d\n%s", nps[k], rc, out);
        cr_assert(strstr(out, "case type 'dpd_mpm_impact' is not decomposed into bricks yet"),
                  "%d ranks: no note\n%s", nps[k], out);
        char tag[64];
        snprintf(tag, sizeof tag, "concurrent impact on %d ranks", nps[k]);
        assert_same_run(d0, dk, tag);
    }
}

/* A checkpoint written on 2 ranks restarts serially and on 4 ranks, and a
 * serial one on 2 ranks: each ends where the uninterrupted serial run
 * ends, bitwise. */
Test(bricks_dpd_mpm, checkpoint_moves_between_rank_counts, .timeout = 600)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    concurrent_case(yaml, sizeof yaml, 100, OUTPUT_CK, "");
    const char *path = th_write_temp(0, "ck.yaml", yaml);
    char s1[600], m2[600];
    snprintf(s1, sizeof s1, "%s/ck-serial", th_temp_dir());
    snprintf(m2, sizeof m2, "%s/ck-2", th_temp_dir());
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    assert_measured(s1);
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, assert_same_restarted);
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

/* Asked for bricks, every coupled type stops before the run: exit 2 and
 * the case file, line and column of the key that asked
 * (parallel.decomposition or parallel.grid), on 2 ranks and on 1. */
static void assert_refused(const char *name, const char *yaml, const char *value,
                           const char *key, const char *type, int np)
{
    static char out[16384];
    const char *path = th_write_temp(0, name, yaml);
    char dir[600], want[900];
    snprintf(dir, sizeof dir, "%s/refused-%s-%d", th_temp_dir(), name, np);
    int line = 0, col = 0;
    line_col(yaml, value, &line, &col);
    snprintf(want, sizeof want, "%s:%d:%d: %s: case type %s is not decomposed into bricks yet",
             path, line, col, key, type);
    cr_assert_eq(thb_run(path, np, dir, NULL, out, sizeof out), 2, "%s on %d ranks:\n%s", name,
                 np, out);
    cr_assert(strstr(out, want), "%s on %d ranks: want '%s' in\n%s", name, np, want, out);
    cr_assert(strstr(out, "use decomposition: replicated (or auto)"), "%s", out);
}

Test(bricks_dpd_mpm, bricks_are_refused_naming_the_key, .timeout = 300)
{
    th_write_temp(2, "cg.yaml", PARAMS);
    char yaml[4096];
    concurrent_case(yaml, sizeof yaml, 5, OUTPUT, "parallel:\n  decomposition: bricks\n");
    assert_refused("conc_bricks.yaml", yaml, "bricks\n", "parallel.decomposition",
                   "dpd_mpm_impact", 2);
    assert_refused("conc_bricks.yaml", yaml, "bricks\n", "parallel.decomposition",
                   "dpd_mpm_impact", 1);
    concurrent_case(yaml, sizeof yaml, 5, OUTPUT, "parallel: {grid: [2, 1, 1]}\n");
    assert_refused("conc_grid.yaml", yaml, "[2, 1, 1]", "parallel.grid", "dpd_mpm_impact", 2);

    /* replicated asks for no bricks: the whole case on every rank, no note */
    static char out[16384];
    concurrent_case(yaml, sizeof yaml, 5, OUTPUT, "parallel: {decomposition: replicated}\n");
    const char *path = th_write_temp(0, "conc_repl.yaml", yaml);
    char dir[600];
    snprintf(dir, sizeof dir, "%s/conc-repl-2", th_temp_dir());
    cr_assert_eq(thb_run(path, 2, dir, NULL, out, sizeof out), 0, "%s", out);
    cr_assert_null(strstr(out, "not decomposed"), "%s", out);
}
