/*
 * The cluster impact on bricks (docs/parallel.md, docs/impact.md "The
 * paper's scale"): `mpirun -np N cascade-solver run` of a `type:
 * cluster_impact` case with `boundary: fixed_damped` builds each rank's
 * brick of the target and of the cluster (the ids of a serial build),
 * marks the fixed and damped layers on each rank's own atoms, and runs the
 * MD on the bricks; the analyses (structure, displaced, sputtered, crater,
 * damage shape) run on each rank's own atoms with ghosts, with global
 * reductions (solver/analysis/md_analysis_bricks.h).
 *
 * A Cu14 cluster at 20 km/s into a 300 K, 3200-site Cu(001) target (the
 * Maxwell velocities and the damped layer's Langevin forces keyed on the
 * global id), 100 steps: the thermo series and the final metrics agree
 * with the serial run to REL relative on 1, 2, 4 and 8 ranks (the force
 * and energy sums run in another order, so not bitwise; over 0.1 ps of
 * collision cascade the round-off does not grow past 1e-12), the counts
 * of the analysis (structure classes, displaced, sputtered, damage atoms)
 * and the per-atom analysis fields of the last snapshot are equal, and
 * the crater and damage-shape columns agree to REL.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10

/* 10 x 10 x 8 cells (3200 sites; fixed 6 Å, damped 4 Å), the cluster 2 Å
 * above the surface at 20 km/s (0.2 Å per 1 fs step): it lands within 20
 * steps and the cascade runs for the other 80.  Brick faces of 2, 4 and 8
 * ranks cut the impact point (x, y) and the target (z). */
static const char *const impact_yaml =
    "title: Cu14 on bricks\n"
    "seed: 7\n"
    "type: cluster_impact\n"
    "target: {lattice: fcc, element: Cu, a: 3.615, cells: [10, 10, 8], temperature: 300,\n"
    "         damped_thickness: 4}\n"
    "cluster: {atoms: 14, speed: 20, gap: 2}\n"
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
    "md: {timestep: 0.001, steps: 100}\n"
    "analysis: {every: 20, structure: {method: fixed}}\n"
    "output: {thermo_every: 10, snapshot_every: 50}\n"
    "parallel: {decomposition: bricks}\n";

static const char *const thermo_cols[] = {"pe_eV",   "ke_eV",   "etotal_eV", "temp_K",
                                          "press_GPa", "pxx_GPa", "pyy_GPa",   "pzz_GPa",
                                          NULL};

/* Analysis columns that count atoms: equal. */
static const char *const count_cols[] = {
    "n_other12", "n_fcc", "n_hcp", "n_bcc", "n_ico", "n_not12", "n_surface",
    "displaced", "sputtered_atoms", "sputtered_clusters", "damage_atoms", NULL};

/* Analysis columns that are lengths, areas, volumes and ratios: to REL of
 * the column's largest magnitude; NaN (fewer than three damaged atoms) in
 * both or neither. */
static const char *const length_cols[] = {
    "analysis_time_ps",   "crater_depth_A",     "crater_volume_A3",    "crater_extent_100_A",
    "crater_extent_110_A", "rim_height_A",      "damage_lmax_A2",      "damage_lmin_A2",
    "damage_eig_ratio",   "damage_axis_deg",    "damage_extent_100_A", "damage_extent_110_A",
    "damage_extent_ratio", NULL};

static const char *const metrics_rel[] = {
    "atoms",          "target_atoms",      "cluster_atoms",         "fixed_atoms",
    "damped_atoms",   "impact_energy",     "time",                  "displaced_peak",
    "displaced_peak_time", "displaced_final", "hcp_final",           "sputtered_atoms",
    "sputtered_clusters", "crater_depth",  "crater_volume",         "crater_extent_100",
    "crater_extent_110", "rim_height",     "temperature",           "crater_volume_peak",
    NULL};

static void compare_columns(const char *a, const char *b, const char *const *cols, int exact,
                            const char *tag)
{
    for (int c = 0; cols[c]; c++) {
        char name[96];
        snprintf(name, sizeof name, "/series/%s", cols[c]);
        long na, nb;
        double *x = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &na);
        double *y = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &nb);
        cr_assert_eq(na, nb, "%s %s: %ld vs %ld rows", tag, name, na, nb);
        double scale = 0;
        for (long i = 0; i < na; i++)
            if (isfinite(x[i]))
                scale = fmax(scale, fabs(x[i]));
        for (long i = 0; i < na; i++) {
            cr_assert_eq(isnan(x[i]), isnan(y[i]), "%s %s row %ld: %g vs %g", tag, name, i, x[i],
                         y[i]);
            if (isnan(x[i]))
                continue;
            if (exact)
                cr_assert_eq(x[i], y[i], "%s %s row %ld: %.17g vs %.17g", tag, name, i, x[i],
                             y[i]);
            else
                cr_assert_leq(fabs(x[i] - y[i]), REL * scale, "%s %s row %ld: %.17g vs %.17g",
                              tag, name, i, x[i], y[i]);
        }
        free(x);
        free(y);
    }
}

/* The analysis fields of a snapshot, atom by atom (matched by id): equal. */
static void compare_fields(const char *a, const char *b, const char *group, const char *tag)
{
    long na, nb;
    struct thb_by_id *oa = thb_order_by_id(a, group, &na), *ob = thb_order_by_id(b, group, &nb);
    cr_assert_eq(na, nb, "%s %s: %ld vs %ld atoms", tag, group, na, nb);
    static const char *const fields[] = {"structure", "displaced", "sputtered", "crater", NULL};
    for (int k = 0; fields[k]; k++) {
        char name[160];
        snprintf(name, sizeof name, "%s/%s", group, fields[k]);
        long n1, n2;
        double *x = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &n1);
        double *y = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &n2);
        cr_assert_eq(n1, na);
        cr_assert_eq(n2, nb);
        for (long i = 0; i < na; i++) {
            cr_assert_eq(oa[i].id, ob[i].id, "%s: atom %ld ids differ", tag, i);
            cr_assert_eq(x[oa[i].i], y[ob[i].i], "%s %s: atom %lld %g vs %g", tag, name,
                         (long long)oa[i].id, x[oa[i].i], y[ob[i].i]);
        }
        free(x);
        free(y);
    }
    free(oa);
    free(ob);
}

/* Everything of two impact runs, the analysis fields of the snapshot
 * `group` included. */
static void compare_impact_at(const char *a, const char *b, const char *group, const char *tag)
{
    thb_compare_series(a, b, thermo_cols, REL, tag);
    compare_columns(a, b, count_cols, 1, tag);
    compare_columns(a, b, length_cols, 0, tag);
    thb_compare_metrics(a, b, metrics_rel, REL, tag);
    /* what the damped layer took out: a difference of two total energies
     * of about -1e4 eV, to REL of them */
    json_t *ra = thb_result(a), *rb = thb_result(b);
    double ea = thb_metric(ra, "energy_absorbed"), eb = thb_metric(rb, "energy_absorbed");
    cr_assert_leq(fabs(ea - eb), REL * 1.2e4, "%s energy_absorbed %.17g vs %.17g", tag, ea, eb);
    json_decref(ra);
    json_decref(rb);
    static const char *const sets[] = {"position", "velocity", NULL};
    static const int ncomp[] = {3, 3};
    thb_compare_snapshot(a, b, group, sets, ncomp, REL, tag);
    compare_fields(a, b, group, tag);
}

static void compare_impact(const char *a, const char *b, const char *tag)
{
    compare_impact_at(a, b, "/particles/00000100", tag);
}

static const char *write_case(const char *name, const char *yaml)
{
    return th_write_temp(0, name, yaml);
}

/* Atoms i and j with flag set, closer than r, on either side of one of
 * the nb - 1 inner faces along axis d of the box [lo, hi] cut in nb equal
 * bricks: 1 when such a pair exists (any pair when r <= 0). */
static int pair_across_face(const double *x, const double *flag, long n, int d, const double *lo,
                            const double *hi, int nb, double r)
{
    double w = (hi[d] - lo[d]) / nb;
    for (long i = 0; i < n; i++)
        for (long j = 0; flag[i] != 0 && j < n; j++) {
            if (flag[j] == 0)
                continue;
            double r2 = 0;
            for (int k = 0; k < 3; k++)
                r2 += (x[3 * i + k] - x[3 * j + k]) * (x[3 * i + k] - x[3 * j + k]);
            int bi = (int)floor((x[3 * i + d] - lo[d]) / w), bj = (int)floor((x[3 * j + d] - lo[d]) / w);
            if (bi != bj && (r <= 0 || r2 < r * r))
                return 1;
        }
    return 0;
}

/* 1 when two atoms with `field` set in snapshot `group` of the brick run
 * in dir (closer than r when r > 0) lie in different bricks: the grid of
 * result.json's parallel record cutting the snapshot's cell. */
static int field_across_faces(const char *dir, const char *group, const char *field, double r)
{
    json_t *res = thb_result(dir);
    json_t *grid = json_object_get(json_object_get(res, "parallel"), "grid");
    cr_assert(json_is_array(grid) && json_array_size(grid) == 3, "%s: no parallel grid", dir);
    char name[160];
    long n, nf, nl, nh;
    snprintf(name, sizeof name, "%s/position", group);
    double *x = thb_read_h5(dir, name, H5T_NATIVE_DOUBLE, sizeof(double), &n);
    snprintf(name, sizeof name, "%s/%s", group, field);
    double *f = thb_read_h5(dir, name, H5T_NATIVE_DOUBLE, sizeof(double), &nf);
    snprintf(name, sizeof name, "%s/cell/lo", group);
    double *lo = thb_read_h5(dir, name, H5T_NATIVE_DOUBLE, sizeof(double), &nl);
    snprintf(name, sizeof name, "%s/cell/hi", group);
    double *hi = thb_read_h5(dir, name, H5T_NATIVE_DOUBLE, sizeof(double), &nh);
    cr_assert(n == 3 * nf && nl == 3 && nh == 3);
    int across = 0;
    for (int d = 0; d < 3 && !across; d++) {
        int nb = (int)json_integer_value(json_array_get(grid, (size_t)d));
        across = nb > 1 && pair_across_face(x, f, nf, d, lo, hi, nb, r);
    }
    free(x); free(f); free(lo); free(hi);
    json_decref(res);
    return across;
}

/* The serial run, then 1 (bricks asked for), 2, 4 and 8 ranks; each run's
 * parallel record counts every atom once; on 4 and 8 ranks the crater's
 * floor atoms lie in more than one brick. */
Test(bricks_impact, cu14_matches_serial_on_1_2_4_8_ranks, .timeout = 900)
{
    const char *path = write_case("impact.yaml", impact_yaml);
    char d0[600], dk[600];
    snprintf(d0, sizeof d0, "%s/impact-serial", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    /* the comparison is of an impact: damage, hot atoms and a crater */
    json_t *r = thb_result(d0);
    cr_assert_gt(thb_metric(r, "displaced_peak"), 50, "displaced peak %g",
                 thb_metric(r, "displaced_peak"));
    cr_assert_gt(thb_metric(r, "crater_depth"), 0, "no crater");
    cr_assert_gt(thb_metric(r, "energy_absorbed"), 1, "the damped layer took %g eV",
                 thb_metric(r, "energy_absorbed"));
    long natoms = (long)thb_metric(r, "atoms");
    cr_assert_eq(natoms, 3200 + 14);
    json_decref(r);
    static const int nps[] = {1, 2, 4, 8};
    for (int k = 0; k < 4; k++) {
        snprintf(dk, sizeof dk, "%s/impact-%d", th_temp_dir(), nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        char tag[64];
        snprintf(tag, sizeof tag, "impact on %d ranks", nps[k]);
        compare_impact(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], natoms);
        /* the crater's floor spans bricks (faces through the impact point) */
        if (nps[k] >= 4)
            cr_assert(field_across_faces(dk, "/particles/00000100", "crater", 0),
                      "%s: the crater lies in one brick", tag);
    }
}

/* decomposition: replicated on 2 ranks: every rank holds every atom and
 * computes a slice of the forces; the trajectory is the serial one. */
Test(bricks_impact, replicated_data_matches_serial, .timeout = 600)
{
    char yaml[4096];
    snprintf(yaml, sizeof yaml, "%s", impact_yaml);
    char *p = strstr(yaml, "decomposition: bricks");
    cr_assert(p);
    memcpy(p, "decomposition: replicated}\n", 28);
    const char *path = write_case("repl.yaml", yaml);
    char d0[600], d2[600];
    snprintf(d0, sizeof d0, "%s/repl-serial", th_temp_dir());
    snprintf(d2, sizeof d2, "%s/repl-2", th_temp_dir());
    thb_must_run(path, 0, d0, NULL);
    thb_must_run(path, 2, d2, NULL);
    compare_impact(d0, d2, "replicated on 2 ranks");
}

/* A checkpoint written on 2 ranks at step 50 restarts serially and on 4
 * ranks (and one of 1 rank on 2): the restarted runs end where the
 * uninterrupted serial run does, series and analysis included.  `par`:
 * the case's parallel section. */
static void checkpoint_moves(const char *par, const char *stem)
{
    char yaml[4096];
    snprintf(yaml, sizeof yaml, "%s", impact_yaml);
    char *o = strstr(yaml, "output: {");
    cr_assert(o);
    snprintf(o, sizeof yaml - (size_t)(o - yaml),
             "output: {thermo_every: 10, snapshot_every: 50, checkpoint_every: 50}\n"
             "parallel: %s\n", par);
    char name[64];
    snprintf(name, sizeof name, "%s.yaml", stem);
    const char *path = write_case(name, yaml);
    char s1[600], m2[600];
    snprintf(s1, sizeof s1, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(m2, sizeof m2, "%s/%s-2", th_temp_dir(), stem);
    thb_must_run(path, 0, s1, NULL);
    thb_must_run(path, 2, m2, NULL);
    compare_impact(s1, m2, "uninterrupted 2 ranks");
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {s1, 2, "1 to 2", NULL}};
    thb_restarts_match(path, 50, cases, 3, s1, compare_impact);
}

Test(bricks_impact, checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoint_moves("{decomposition: bricks}", "ck");
}

/* The same with the cuts moved at every check (threshold 1: any
 * imbalance), every 20 steps and at each checkpoint: the 2-rank run
 * shifted more than once and still ends where the serial run does. */
Test(bricks_impact, dynamic_balance_checkpoint_moves_between_rank_counts, .timeout = 900)
{
    checkpoint_moves("{decomposition: bricks, balance: shift, balance_every: 20, "
                     "balance_threshold: 1.0}", "dyn");
    char m2[600];
    snprintf(m2, sizeof m2, "%s/dyn-2", th_temp_dir());
    long checks, shifts;
    thb_balance_record(m2, &checks, &shifts, NULL);
    cr_log_info("impact on 2 ranks, balance_every 20: %ld checks, %ld shifts", checks, shifts);
    cr_assert_geq(checks, 3, "%ld checks", checks);
    cr_assert_geq(shifts, 3, "%ld shifts", shifts);
}

/* Cu14 at 30 km/s (seed 4, 0.5 fs steps, 0.3 ps) ends with a sputtered
 * dimer, two monomers and a crater; on a grid of 1 x 5 x 1 bricks (the
 * faces 6.87 Å apart along y) the dimer's atoms lie in two bricks.  The
 * analysis runs on each rank's atoms with ghosts, the groups found by
 * label propagation across the faces (analysis/sputter_bricks.h), the crater from the reduced height
 * map: the series, metrics and per-atom fields equal the serial run's. */
static const char *const sputter_yaml =
    "title: Cu14 sputtering on bricks\n"
    "seed: 4\n"
    "type: cluster_impact\n"
    "target: {lattice: fcc, element: Cu, a: 3.615, cells: [10, 10, 8], temperature: 300,\n"
    "         damped_thickness: 4}\n"
    "cluster: {atoms: 14, speed: 30, gap: 2}\n"
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
    "md: {timestep: 0.0005, steps: 600}\n"
    "analysis: {every: 100, structure: {method: fixed}}\n"
    "output: {thermo_every: 100, snapshot_every: 600}\n"
    "parallel: {decomposition: bricks%s}\n";

Test(bricks_impact, sputtered_dimer_across_a_face_matches_serial, .timeout = 900)
{
    char yaml[2048];
    snprintf(yaml, sizeof yaml, sputter_yaml, "");
    const char *serial = write_case("sputter.yaml", yaml);
    snprintf(yaml, sizeof yaml, sputter_yaml, ", grid: [1, 5, 1]");
    const char *bricks = write_case("sputter5.yaml", yaml);
    char d0[600], d5[600];
    snprintf(d0, sizeof d0, "%s/sputter-serial", th_temp_dir());
    snprintf(d5, sizeof d5, "%s/sputter-5", th_temp_dir());
    thb_must_run(serial, 0, d0, NULL);
    thb_must_run(bricks, 5, d5, NULL);
    json_t *r = thb_result(d0);
    cr_assert_eq(thb_metric(r, "sputtered_largest"), 2, "largest sputtered group %g",
                 thb_metric(r, "sputtered_largest"));
    cr_assert_gt(thb_metric(r, "crater_depth"), 0, "no crater");
    json_decref(r);
    /* the case does what it is for: the dimer's atoms are in two bricks
     * (4.77 Å: the connection cutoff, the fcc surface radius at 3.615 Å) */
    const char *g = "/particles/00000600";
    cr_assert(field_across_faces(d5, g, "sputtered", 4.77), "no sputtered pair across a face");
    compare_impact_at(d0, d5, g, "sputtering on 5 ranks");
    static const char *const counts[] = {"sputtered_largest", "sputtered_monomers", NULL};
    thb_compare_metrics(d0, d5, counts, 0, "sputtering on 5 ranks");
}
