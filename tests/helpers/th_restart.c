/* th_restart: kill-and-restart comparisons for the checkpoint tests. */
#include "helpers/th_restart.h"

#include <criterion/criterion.h>
#include <hdf5.h>
#include <jansson.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"

int th_restart_solve(const char *out_name, const char *case_path, const char *kill_at,
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

void th_ckpt_poke(const char *file, const char *dataset, long memtype, const void *value)
{
    th_ckpt_poke_at(file, dataset, memtype, 0, value);
}

void th_ckpt_poke_at(const char *file, const char *dataset, long memtype, long row,
                     const void *value)
{
    hid_t h = H5Fopen(file, H5F_ACC_RDWR, H5P_DEFAULT);
    cr_assert_geq(h, 0, "%s", file);
    hid_t ds = H5Dopen2(h, dataset, H5P_DEFAULT);
    cr_assert_geq(ds, 0, "%s: %s", file, dataset);
    hid_t fs = H5Dget_space(ds);
    hsize_t start[1] = {(hsize_t)row}, count[1] = {1};
    H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
    hid_t ms = H5Screate_simple(1, count, NULL);
    cr_assert_geq(H5Dwrite(ds, (hid_t)memtype, ms, fs, H5P_DEFAULT, value), 0);
    H5Sclose(ms);
    H5Sclose(fs);
    H5Dclose(ds);
    H5Fclose(h);
}

long th_ckpt_positions_ids(const char *file, const char *group, double **x, int64_t **ids)
{
    char px[256], pid[256];
    snprintf(px, sizeof px, "%s/x", group);
    snprintf(pid, sizeof pid, "%s/id", group);
    hid_t h = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert_geq(h, 0, "%s", file);
    hid_t dx = H5Dopen2(h, px, H5P_DEFAULT);
    hid_t di = H5Dopen2(h, pid, H5P_DEFAULT);
    cr_assert(dx >= 0 && di >= 0, "%s: %s", file, group);
    hid_t fs = H5Dget_space(di);
    hsize_t dim[1];
    H5Sget_simple_extent_dims(fs, dim, NULL);
    H5Sclose(fs);
    long n = (long)dim[0];
    *x = malloc((size_t)(n ? n : 1) * 3 * sizeof **x);
    *ids = malloc((size_t)(n ? n : 1) * sizeof **ids);
    cr_assert(*x && *ids);
    cr_assert_geq(H5Dread(dx, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, *x), 0);
    cr_assert_geq(H5Dread(di, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, *ids), 0);
    H5Dclose(dx);
    H5Dclose(di);
    H5Fclose(h);
    return n;
}

char *th_restart_slurp(const char *path, long *len)
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
    char *ta = th_restart_slurp(pa, NULL), *tb = th_restart_slurp(pb, NULL);
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

void th_restart_assert_same_snapshot(const char *a, const char *b, const char *collection,
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

void th_kill_and_restart(const char *yaml, const char *const *kill_steps, int thermo_csv,
                         const char *collection, const char *const *datasets)
{
    const char *path = th_write_temp(1, "case.yaml", yaml);
    char msg[8192];
    int rc = th_restart_solve("full", path, NULL, NULL, msg, sizeof msg);
    cr_assert_eq(rc, 0, "%s", msg);
    for (int k = 0; kill_steps[k]; k++) {
        char out[32];
        snprintf(out, sizeof out, "killed-%s", kill_steps[k]);
        rc = th_restart_solve(out, path, kill_steps[k], NULL, msg, sizeof msg);
        cr_assert_eq(rc, 128 + SIGKILL, "the run was to be killed at step %s: %s", kill_steps[k],
                     msg);
        rc = th_restart_solve(out, path, NULL, "", msg, sizeof msg);
        cr_assert_eq(rc, 0, "restart after a kill at step %s: %s", kill_steps[k], msg);
        json_t *r = result_of(out);
        cr_assert(json_integer_value(json_object_get(r, "restarted_from_step")) > 0,
                  "result.json does not say where the run continued from");
        json_decref(r);
        assert_same_metrics("full", out);
        if (thermo_csv)
            assert_same_thermo("full", out);
        if (collection)
            th_restart_assert_same_snapshot("full", out, collection, datasets);
    }
}

