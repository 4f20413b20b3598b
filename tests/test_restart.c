/*
 * Checkpoint and restart (engine/sim.h, output/checkpoint.h).
 *
 * The promise: a run killed with SIGKILL at any step and restarted from its
 * newest checkpoint ends in the same state as the uninterrupted run, bitwise
 * on the same thread count -- every metric of result.json, every thermo row,
 * and the positions, velocities and forces of the last snapshot compared
 * with ==, not with a tolerance.  The kill comes from the solver itself
 * (CASCADE_SOLVER_KILL_AT_STEP) so that it lands on an exact step: one
 * between output steps and one on an output step.
 *
 * And the refusals: a checkpoint of another case (job key), of another
 * format version, a truncated and a corrupted file, each named in the
 * message; checkpoints asked of a case type that cannot write them.
 */
#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/th.h"

static int solve(const char *out_name, const char *case_path, const char *kill_at,
                 const char *restart, char *msg, size_t len)
{
    char outdir[512];
    snprintf(outdir, sizeof outdir, "%s/%s", th_temp_dir(), out_name);
    const char *argv[12] = {th_solver(), "run", case_path, "--out", outdir, "--threads", "1",
                            "--quiet"};
    int n = 8;
    if (restart) {
        argv[n++] = "--restart";
        if (*restart)
            argv[n++] = restart;
    }
    argv[n] = NULL;
    if (kill_at)
        setenv("CASCADE_SOLVER_KILL_AT_STEP", kill_at, 1);
    int rc = th_run(argv, msg, len);
    unsetenv("CASCADE_SOLVER_KILL_AT_STEP");
    return rc;
}

static json_t *result_of(const char *out_name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/result.json", th_temp_dir(), out_name);
    json_error_t je;
    json_t *r = json_load_file(path, 0, &je);
    cr_assert_not_null(r, "%s: %s", path, je.text);
    return r;
}

/* Every metric equal, bit for bit (NaN equal to NaN). */
static void assert_same_metrics(const char *a, const char *b)
{
    json_t *ra = result_of(a), *rb = result_of(b);
    json_t *ma = json_object_get(ra, "metrics"), *mb = json_object_get(rb, "metrics");
    cr_assert_eq(json_object_size(ma), json_object_size(mb));
    cr_assert_gt(json_object_size(ma), 5);
    const char *k;
    json_t *v;
    json_object_foreach(ma, k, v)
    {
        json_t *w = json_object_get(mb, k);
        cr_assert_not_null(w, "metric %s missing after the restart", k);
        double x = json_number_value(json_object_get(v, "value"));
        double y = json_number_value(json_object_get(w, "value"));
        int same = json_is_null(json_object_get(v, "value"))
                       ? json_is_null(json_object_get(w, "value"))
                       : memcmp(&x, &y, sizeof x) == 0;
        cr_assert(same, "metric %s: %.17g uninterrupted, %.17g restarted", k, x, y);
    }
    cr_assert_str_eq(json_string_value(json_object_get(rb, "status")), "ok");
    json_decref(ra);
    json_decref(rb);
}

static char *slurp(const char *path, long *len)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    cr_assert_eq(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = '\0';
    fclose(f);
    if (len)
        *len = n;
    return buf;
}

/* thermo.csv without its first (provenance) line. */
static void assert_same_thermo(const char *a, const char *b)
{
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s/thermo.csv", th_temp_dir(), a);
    snprintf(pb, sizeof pb, "%s/%s/thermo.csv", th_temp_dir(), b);
    char *ta = slurp(pa, NULL), *tb = slurp(pb, NULL);
    const char *ra = strchr(ta, '\n'), *rb = strchr(tb, '\n');
    cr_assert(ra && rb);
    cr_assert_str_eq(ra, rb, "thermo rows differ after the restart");
    cr_assert_gt(strlen(ra), 100);
    free(ta);
    free(tb);
}

/* A dataset of the last snapshot of `collection` in out_name/fields.h5. */
static double *last_snapshot(const char *out_name, const char *collection, const char *dataset,
                             long *n)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/fields.h5", th_temp_dir(), out_name);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert_geq(f, 0, "cannot open %s", path);
    hid_t g = H5Gopen2(f, collection, H5P_DEFAULT);
    cr_assert_geq(g, 0, "%s has no /%s", path, collection);
    H5G_info_t info;
    H5Gget_info(g, &info);
    cr_assert_gt(info.nlinks, 0);
    char name[64];
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, info.nlinks - 1, name, sizeof name,
                       H5P_DEFAULT);
    hid_t s = H5Gopen2(g, name, H5P_DEFAULT);
    hid_t ds = H5Dopen2(s, dataset, H5P_DEFAULT);
    cr_assert_geq(ds, 0, "%s: no %s/%s/%s", path, collection, name, dataset);
    hid_t sp = H5Dget_space(ds);
    hssize_t np = H5Sget_simple_extent_npoints(sp);
    double *d = malloc((size_t)np * sizeof *d);
    cr_assert_geq(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d), 0);
    H5Sclose(sp);
    H5Dclose(ds);
    H5Gclose(s);
    H5Gclose(g);
    H5Fclose(f);
    *n = (long)np;
    return d;
}

static void assert_same_snapshot(const char *a, const char *b, const char *collection,
                                 const char *const *datasets)
{
    for (int k = 0; datasets[k]; k++) {
        long na, nb;
        double *da = last_snapshot(a, collection, datasets[k], &na);
        double *db = last_snapshot(b, collection, datasets[k], &nb);
        cr_assert_eq(na, nb);
        cr_assert_eq(memcmp(da, db, (size_t)na * sizeof *da), 0,
                     "last snapshot's %s differs after the restart", datasets[k]);
        free(da);
        free(db);
    }
}

/* Kill the run at each of the steps, restart it, compare with the run that
 * was never interrupted. */
static void kill_and_restart(const char *yaml, const char *const *kill_steps,
                             const char *collection, const char *const *datasets)
{
    const char *path = th_write_temp(1, "case.yaml", yaml);
    char msg[8192];
    int rc = solve("full", path, NULL, NULL, msg, sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
    for (int k = 0; kill_steps[k]; k++) {
        char out[32];
        snprintf(out, sizeof out, "killed-%s", kill_steps[k]);
        rc = solve(out, path, kill_steps[k], NULL, msg, sizeof msg);
        cr_assert_eq(rc, 128 + SIGKILL, "the run was to be killed at step %s: %s", kill_steps[k],
                     msg);
        rc = solve(out, path, NULL, "", msg, sizeof msg);
        cr_assert_eq(rc, 0, "restart after a kill at step %s: %s", kill_steps[k], msg);
        json_t *r = result_of(out);
        cr_assert(json_integer_value(json_object_get(r, "restarted_from_step")) > 0,
                  "result.json does not say where the run continued from");
        json_decref(r);
        assert_same_metrics("full", out);
        assert_same_thermo("full", out);
        assert_same_snapshot("full", out, collection, datasets);
    }
}

static const char *const md_fields[] = {"position", "velocity", "force", NULL};

/* EAM copper with a Langevin thermostat: the random forces are keyed on
 * (seed, step, atom id), so the stream continues exactly. */
Test(restart, md_eam_langevin_continues_bitwise, .timeout = 300)
{
    const char *yaml = "seed: 7\n"
                       "system: {lattice: {style: fcc, a: 3.615, cells: [4, 4, 4]}, element: Cu}\n"
                       "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
                       "md:\n"
                       "  timestep: 0.002\n"
                       "  steps: 300\n"
                       "  temperature: 600\n"
                       "  thermostat: {style: langevin, temperature: 500, tau: 0.1}\n"
                       "output: {thermo_every: 25, snapshot_every: 100, checkpoint_every: 40}\n";
    /* 130: between output and checkpoint steps; 200: a snapshot, thermo
     * and checkpoint step */
    const char *const kills[] = {"130", "200", NULL};
    kill_and_restart(yaml, kills, "particles", md_fields);
}

static const char *md_case = "seed: 3\n"
                             "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                             "element: Cu}\n"
                             "potential: {style: sutton_chen}\n"
                             "md: {timestep: 0.002, steps: 60, temperature: 300}\n"
                             "output: {checkpoint_every: 20, hdf5: false}\n";

static const char *checkpoint_path(const char *out, long step)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s/checkpoint-%010ld.h5", th_temp_dir(), out, step);
    return path;
}

Test(restart, keeps_the_newest_two_checkpoints)
{
    const char *path = th_write_temp(1, "case.yaml", md_case);
    char msg[4096];
    cr_assert_eq(solve("ck", path, NULL, NULL, msg, sizeof msg), 0, "%s", msg);
    struct stat sb;
    cr_assert_eq(stat(checkpoint_path("ck", 20), &sb), 0, "checkpoint of step 20 missing");
    cr_assert_eq(stat(checkpoint_path("ck", 40), &sb), 0, "checkpoint of step 40 missing");
    /* the last step needs none: the run is complete */
    cr_assert_neq(stat(checkpoint_path("ck", 60), &sb), 0);
}

Test(restart, refuses_another_case_version_truncated_and_corrupt)
{
    const char *path = th_write_temp(1, "case.yaml", md_case);
    char msg[4096];
    cr_assert_eq(solve("ck", path, "50", NULL, msg, sizeof msg), 128 + SIGKILL, "%s", msg);
    /* another case: the job key differs */
    const char *other = th_write_temp(2, "other.yaml",
                                      "seed: 4\n"
                                      "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                                      "element: Cu}\n"
                                      "potential: {style: sutton_chen}\n"
                                      "md: {timestep: 0.002, steps: 60, temperature: 300}\n"
                                      "output: {checkpoint_every: 20, hdf5: false}\n");
    char ck40[512];
    snprintf(ck40, sizeof ck40, "%s", checkpoint_path("ck", 40));
    int rc = solve("other", other, NULL, ck40, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, ck40) && strstr(msg, "checkpoint of another case"), "%s", msg);

    /* another format version */
    char copy[512];
    snprintf(copy, sizeof copy, "%s/v99.h5", th_temp_dir());
    long n;
    char *bytes = slurp(ck40, &n);
    FILE *f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n, f);
    fclose(f);
    hid_t h = H5Fopen(copy, H5F_ACC_RDWR, H5P_DEFAULT);
    cr_assert_geq(h, 0);
    hid_t a = H5Aopen(h, "version", H5P_DEFAULT);
    double v = 99;
    H5Awrite(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
    H5Fclose(h);
    rc = solve("v", path, NULL, copy, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "v99.h5") && strstr(msg, "format version 99"), "%s", msg);

    /* truncated: half the file */
    snprintf(copy, sizeof copy, "%s/half.h5", th_temp_dir());
    f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n / 2, f);
    fclose(f);
    rc = solve("half", path, NULL, copy, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "half.h5") && strstr(msg, "corrupt"), "%s", msg);

    /* corrupt: bytes flipped inside the particle data (checksummed) */
    snprintf(copy, sizeof copy, "%s/flip.h5", th_temp_dir());
    for (long k = n / 2; k < n / 2 + 64; k++)
        bytes[k] ^= 0x5a;
    f = fopen(copy, "wb");
    fwrite(bytes, 1, (size_t)n, f);
    fclose(f);
    rc = solve("flip", path, NULL, copy, msg, sizeof msg);
    cr_assert_neq(rc, 0, "a corrupted checkpoint was accepted: %s", msg);
    cr_assert(strstr(msg, "flip.h5"), "%s", msg);
    free(bytes);

    /* a directory without checkpoints */
    char empty[512];
    snprintf(empty, sizeof empty, "%s/empty", th_temp_dir());
    mkdir(empty, 0755);
    rc = solve("e", path, NULL, empty, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "no checkpoint-*.h5 file"), "%s", msg);
}

Test(restart, checkpoints_refused_for_a_case_type_off_the_engine)
{
    const char *path = th_write_temp(1, "case.yaml",
                                      "type: crystal\n"
                                      "system: {lattice: {style: fcc, a: 3.61, cells: [3, 3, 3]}, "
                                      "element: Cu}\n"
                                      "potential: {style: sutton_chen}\n"
                                      "output: {checkpoint_every: 20}\n");
    const char *argv[] = {th_solver(), "check", path, NULL};
    char msg[4096];
    int rc = th_run(argv, msg, sizeof msg);
    cr_assert_eq(rc, 2, "%s", msg);
    cr_assert(strstr(msg, "case.yaml:4:") && strstr(msg, "output.checkpoint_every") &&
                  strstr(msg, "does not write checkpoints"),
              "%s", msg);
}
