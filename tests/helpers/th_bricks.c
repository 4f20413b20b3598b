/* th_bricks: serial / mpirun runs and their comparison (th_bricks.h). */
#include "helpers/th_bricks.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "helpers/th.h"
#include "helpers/th_restart.h"

void thb_mpi_env(int np)
{
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMP_NUM_THREADS", "1", 1);
    /* Open MPI's dlopen'ed components leak at exit (test_parallel.c); the
     * serial runs keep leak checking for our code */
    setenv("ASAN_OPTIONS", np > 0 ? "detect_leaks=0" : "detect_leaks=1", 1);
}

int thb_run(const char *path, int np, const char *dir, const char *const *extra, char *out,
            size_t len)
{
    thb_mpi_env(np);
    char nps[16];
    snprintf(nps, sizeof nps, "%d", np);
    const char *argv[24];
    int k = 0;
    if (np > 0) {
        argv[k++] = "/usr/bin/mpirun";
        argv[k++] = "-np";
        argv[k++] = nps;
        argv[k++] = "--oversubscribe";
    }
    argv[k++] = th_solver();
    argv[k++] = "run";
    argv[k++] = path;
    argv[k++] = "--out";
    argv[k++] = dir;
    argv[k++] = "--quiet";
    for (int i = 0; extra && extra[i] && k < 23; i++)
        argv[k++] = extra[i];
    argv[k] = NULL;
    return th_run(argv, out, len);
}

void thb_must_run(const char *path, int np, const char *dir, const char *const *extra)
{
    static char out[16384];
    int rc = thb_run(path, np, dir, extra, out, sizeof out);
    cr_assert_eq(rc, 0, "%d ranks, %s: exit %d\n%s", np, dir, rc, out);
}

void *thb_read_h5(const char *dir, const char *name, hid_t type, size_t elem, long *n)
{
    char path[700];
    snprintf(path, sizeof path, "%s/fields.h5", dir);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    cr_assert_geq(f, 0, "%s", path);
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    cr_assert_geq(ds, 0, "%s: %s", path, name);
    hid_t sp = H5Dget_space(ds);
    hssize_t cnt = H5Sget_simple_extent_npoints(sp);
    void *buf = malloc((size_t)(cnt > 0 ? cnt : 1) * elem);
    cr_assert_not_null(buf);
    cr_assert_geq(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf), 0);
    H5Sclose(sp);
    H5Dclose(ds);
    H5Fclose(f);
    *n = (long)cnt;
    return buf;
}

void thb_compare_series_floor(const char *a, const char *b, const char *const *cols,
                              const double *floor, double rel, const char *tag)
{
    for (int c = 0; cols[c]; c++) {
        char name[96];
        snprintf(name, sizeof name, "/series/%s", cols[c]);
        long na, nb;
        double *x = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &na);
        double *y = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &nb);
        cr_assert_eq(na, nb, "%s %s: %ld vs %ld rows", tag, name, na, nb);
        cr_assert_geq(na, 2, "%s %s: %ld rows", tag, name, na);
        double scale = floor ? floor[c] : 0;
        for (long i = 0; i < na; i++)
            scale = fmax(scale, fabs(x[i]));
        for (long i = 0; i < na; i++)
            cr_assert_leq(fabs(x[i] - y[i]), rel * scale, "%s %s row %ld: %.17g vs %.17g", tag,
                          name, i, x[i], y[i]);
        free(x);
        free(y);
    }
}

void thb_compare_series(const char *a, const char *b, const char *const *cols, double rel,
                        const char *tag)
{
    thb_compare_series_floor(a, b, cols, NULL, rel, tag);
}

json_t *thb_result(const char *dir)
{
    char path[700];
    snprintf(path, sizeof path, "%s/result.json", dir);
    json_error_t je;
    json_t *r = json_load_file(path, 0, &je);
    cr_assert_not_null(r, "%s: %s", path, je.text);
    return r;
}

double thb_metric(json_t *res, const char *name)
{
    json_t *m = json_object_get(json_object_get(res, "metrics"), name);
    cr_assert_not_null(m, "metric %s missing", name);
    json_t *v = json_is_object(m) ? json_object_get(m, "value") : m;
    return json_number_value(v);
}

void thb_compare_metrics(const char *a, const char *b, const char *const *names, double rel,
                         const char *tag)
{
    json_t *ra = thb_result(a), *rb = thb_result(b);
    for (int k = 0; names[k]; k++) {
        double x = thb_metric(ra, names[k]), y = thb_metric(rb, names[k]);
        cr_assert_leq(fabs(x - y), rel * fabs(x) + 1e-12 * fabs(x), "%s %s: %.17g vs %.17g", tag,
                      names[k], x, y);
    }
    json_decref(ra);
    json_decref(rb);
}

static int cmp_by_id(const void *a, const void *b)
{
    int64_t x = ((const struct thb_by_id *)a)->id, y = ((const struct thb_by_id *)b)->id;
    return (x > y) - (x < y);
}

struct thb_by_id *thb_order_by_id(const char *dir, const char *group, long *n)
{
    char name[160];
    snprintf(name, sizeof name, "%s/id", group);
    int64_t *id = thb_read_h5(dir, name, H5T_NATIVE_INT64, sizeof(int64_t), n);
    struct thb_by_id *o = malloc((size_t)(*n > 0 ? *n : 1) * sizeof *o);
    cr_assert_not_null(o);
    for (long i = 0; i < *n; i++)
        o[i] = (struct thb_by_id){id[i], i};
    qsort(o, (size_t)*n, sizeof *o, cmp_by_id);
    free(id);
    return o;
}

long thb_compare_setup(const char *a, const char *b, double vmin, double vrel, const char *tag)
{
    long na, nb;
    struct thb_by_id *oa = thb_order_by_id(a, "/particles/00000000", &na);
    struct thb_by_id *ob = thb_order_by_id(b, "/particles/00000000", &nb);
    cr_assert_eq(na, nb, "%s: %ld vs %ld atoms", tag, na, nb);
    for (long i = 0; i < na; i++)
        cr_assert_eq(oa[i].id, ob[i].id, "%s: id %ld differs", tag, i);
    long lx;
    const char *pos = "/particles/00000000/position", *vel = "/particles/00000000/velocity";
    double *xa = thb_read_h5(a, pos, H5T_NATIVE_DOUBLE, sizeof(double), &lx);
    double *xb = thb_read_h5(b, pos, H5T_NATIVE_DOUBLE, sizeof(double), &lx);
    double *va = thb_read_h5(a, vel, H5T_NATIVE_DOUBLE, sizeof(double), &lx);
    double *vb = thb_read_h5(b, vel, H5T_NATIVE_DOUBLE, sizeof(double), &lx);
    double vmax = 0;
    for (long k = 0; k < lx; k++)
        vmax = fmax(vmax, fabs(va[k]));
    cr_assert_gt(vmax, vmin, "%s: velocities of at most %g Å/ps", tag, vmax);
    for (long i = 0; i < na; i++)
        for (int d = 0; d < 3; d++) {
            long p = 3 * oa[i].i + d, q = 3 * ob[i].i + d;
            cr_assert_eq(xa[p], xb[q], "%s: id %lld x%d: %.17g vs %.17g", tag,
                         (long long)oa[i].id, d, xa[p], xb[q]);
            cr_assert_leq(fabs(va[p] - vb[q]), vrel * vmax, "%s: id %lld v%d: %.17g vs %.17g",
                          tag, (long long)oa[i].id, d, va[p], vb[q]);
        }
    free(xa);
    free(xb);
    free(va);
    free(vb);
    free(oa);
    free(ob);
    return na;
}

void thb_compare_snapshot(const char *a, const char *b, const char *group,
                          const char *const *sets, const int *ncomp, double rel, const char *tag)
{
    long na, nb;
    struct thb_by_id *oa = thb_order_by_id(a, group, &na), *ob = thb_order_by_id(b, group, &nb);
    cr_assert_eq(na, nb, "%s: %ld vs %ld particles", tag, na, nb);
    for (long i = 0; i < na; i++)
        cr_assert_eq(oa[i].id, ob[i].id, "%s: id %ld differs", tag, i);
    for (int s = 0; sets[s]; s++) {
        char name[160];
        snprintf(name, sizeof name, "%s/%s", group, sets[s]);
        long la, lb;
        double *x = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &la);
        double *y = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &lb);
        cr_assert_eq(la, na * ncomp[s], "%s %s", tag, name);
        cr_assert_eq(lb, nb * ncomp[s], "%s %s", tag, name);
        double scale = 0;
        for (long k = 0; k < la; k++)
            scale = fmax(scale, fabs(x[k]));
        for (long i = 0; i < na; i++)
            for (int c = 0; c < ncomp[s]; c++) {
                double u = x[oa[i].i * ncomp[s] + c], v = y[ob[i].i * ncomp[s] + c];
                cr_assert_leq(fabs(u - v), rel * scale, "%s %s id %lld: %.17g vs %.17g", tag,
                              name, (long long)oa[i].id, u, v);
            }
        free(x);
        free(y);
    }
    free(oa);
    free(ob);
}

void thb_check_parallel_record(const char *dir, int np, long n)
{
    json_t *r = thb_result(dir);
    json_t *par = json_object_get(r, "parallel");
    cr_assert_not_null(par, "%s: no parallel record", dir);
    cr_assert_eq(json_integer_value(json_object_get(par, "ranks")), np);
    json_t *per = json_object_get(par, "particles_per_rank");
    cr_assert_eq((long)json_array_size(per), np);
    long sum = 0, max = 0;
    for (int k = 0; k < np; k++) {
        long c = (long)json_integer_value(json_array_get(per, (size_t)k));
        sum += c;
        max = c > max ? c : max;
    }
    cr_assert_eq(sum, n, "%s: %ld particles over the ranks, %ld expected", dir, sum, n);
    double imb = json_real_value(json_object_get(par, "imbalance_max_over_mean"));
    cr_assert_float_eq(imb, (double)max / ((double)sum / np), 1e-10);   /* 12 digits */
    json_t *grid = json_object_get(par, "grid");
    long prod = 1;
    for (size_t d = 0; d < 3; d++)
        prod *= (long)json_integer_value(json_array_get(grid, d));
    cr_assert_eq(prod, np);
    json_decref(r);
}

double thb_check_cell_tables(const char *dir, int np, double most)
{
    json_t *r = thb_result(dir);
    json_t *par = json_object_get(r, "parallel");
    cr_assert_not_null(par, "%s: no parallel record", dir);
    long cells = (long)json_integer_value(json_object_get(par, "mpm_cells"));
    json_t *per = json_object_get(par, "mpm_cell_tables_per_rank");
    cr_assert_eq((long)json_array_size(per), np, "%s: mpm_cell_tables_per_rank", dir);
    double worst = 0;
    long sum = 0;
    for (int k = 0; k < np; k++) {
        long made = (long)json_integer_value(json_array_get(per, (size_t)k));
        double f = cells > 0 ? (double)made / (double)cells : 1.0;
        sum += made;
        cr_assert(made >= 0 && f < most,
                  "%s: rank %d made the node tables of %ld of %ld cells (%.3f, at most %.3f)", dir,
                  k, made, cells, f, most);
        worst = f > worst ? f : worst;
    }
    cr_assert_gt(sum, 0, "%s: no rank made a node table", dir);
    json_decref(r);
    return worst;
}

void thb_assert_bricks(const char *dir, int np, const int *grid)
{
    json_t *r = thb_result(dir);
    json_t *par = json_object_get(r, "parallel");
    const char *dec = json_string_value(json_object_get(par, "decomposition"));
    cr_assert(dec && strcmp(dec, "bricks") == 0, "%s: decomposition %s", dir,
              dec ? dec : "(none)");
    cr_assert_eq(json_integer_value(json_object_get(par, "ranks")), np, "%s: ranks", dir);
    for (size_t d = 0; grid && d < 3; d++)
        cr_assert_eq(json_integer_value(json_array_get(json_object_get(par, "grid"), d)),
                     grid[d], "%s: grid[%zu]", dir, d);
    json_decref(r);
}

/* mkdir dir, copy file from into to. */
int thb_mkdir_copy(const char *from, const char *dir, const char *to)
{
    if (mkdir(dir, 0755) != 0)
        return -1;
    FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
    int rc = a && b ? 0 : -1;
    char buf[65536];
    size_t n;
    while (!rc && (n = fread(buf, 1, sizeof buf, a)) > 0)
        rc = fwrite(buf, 1, n, b) == n ? 0 : -1;
    if (a)
        fclose(a);
    if (b && fclose(b) != 0)
        rc = -1;
    return rc;
}

void thb_restart_refuses(const char *path, const char *ck, long step, const char *stem, int np,
                         const char *dataset, long type, long row, const void *val,
                         const char *want, char *out, size_t len)
{
    char dir[700], file[800], name[64];
    snprintf(dir, sizeof dir, "%s/%s", th_temp_dir(), stem);
    snprintf(name, sizeof name, "checkpoint-%010ld.h5", step);
    snprintf(file, sizeof file, "%s/%s", dir, name);
    cr_assert_eq(thb_mkdir_copy(ck, dir, file), 0, "%s", ck);
    th_ckpt_poke_at(file, dataset, type, row, val);
    const char *extra[] = {"--restart", NULL};
    int rc = thb_run(path, np, dir, extra, out, len);
    cr_assert_eq(rc, 2, "%s: exit %d: %s", stem, rc, out);
    cr_assert(strstr(out, name) && strstr(out, want), "%s: %s", stem, out);
    cr_assert(!strstr(out, "another MPI rank"), "%s: %s", stem, out);
}

void thb_restart_at(const char *path, const char *from_dir, long step, int np, int k, char *dir,
                    size_t len)
{
    char ck[800], from[800];
    snprintf(dir, len, "%s/ck-restart-%d", th_temp_dir(), k);
    snprintf(ck, sizeof ck, "%s/checkpoint-%010ld.h5", dir, step);
    snprintf(from, sizeof from, "%s/checkpoint-%010ld.h5", from_dir, step);
    cr_assert_eq(thb_mkdir_copy(from, dir, ck), 0, "%s", from);
    const char *extra[] = {"--restart", NULL};
    thb_must_run(path, np, dir, extra);
}

static void assert_restarted_from(const char *dir, long step, const char *tag)
{
    json_t *res = thb_result(dir);
    cr_assert_eq(json_integer_value(json_object_get(res, "restarted_from_step")), step,
                 "%s: not restarted from step %ld", tag, step);
    json_decref(res);
}

/* thb_restarts_match, and with check_step each run's restarted_from_step */
static void restarts_match(const char *path, long step, const struct thb_restart *r, int n,
                           const char *ref, thb_check_fn check, int check_step)
{
    for (int k = 0; k < n; k++) {
        char dir[700];
        thb_restart_at(path, r[k].from, step, r[k].np, k, dir, sizeof dir);
        if (check_step)
            assert_restarted_from(dir, step, r[k].tag);
        check(ref, dir, r[k].tag);
        if (!r[k].bitwise_with)
            continue;
        static char t1[65536], t2[65536];
        thb_read_text(r[k].bitwise_with, "thermo.csv", t1, sizeof t1);
        thb_read_text(dir, "thermo.csv", t2, sizeof t2);
        const char *b1 = strchr(t1, '\n'), *b2 = strchr(t2, '\n');
        cr_assert(b1 && b2);
        cr_assert_str_eq(b1, b2, "%s restart is not bitwise", r[k].tag);
    }
}

void thb_restarts_match(const char *path, long step, const struct thb_restart *r, int n,
                        const char *ref, thb_check_fn check)
{
    restarts_match(path, step, r, n, ref, check, 0);
}

void thb_checkpoint_moves(const char *path, const char *stem, thb_check_fn compare,
                          const char *what)
{
    char s1[600], m2[600], tag[128];
    snprintf(s1, sizeof s1, "%s/%s-ck-serial", th_temp_dir(), stem);
    snprintf(m2, sizeof m2, "%s/%s-ck-2", th_temp_dir(), stem);
    thb_must_run(path, 0, s1, NULL);
    thb_must_run_auto_bricks(path, 2, m2);
    snprintf(tag, sizeof tag, "checkpointing %s on 2 ranks", what);
    compare(s1, m2, tag);
    const struct thb_restart cases[] = {
        {m2, 0, "2 to 1", NULL}, {m2, 4, "2 to 4", NULL}, {m2, 2, "2 to 2", m2}};
    restarts_match(path, 50, cases, 3, s1, compare, 1);
}

void thb_matches_serial(const char *path, const char *stem, const int *nps, int nnp, long n,
                        void (*measured)(const char *dir), thb_check_fn compare,
                        const char *what)
{
    char d0[600], dk[600];
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), stem);
    thb_must_run(path, 0, d0, NULL);
    if (measured)
        measured(d0);
    for (int k = 0; k < nnp; k++) {
        snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), stem, nps[k]);
        thb_must_run(path, nps[k], dk, NULL);
        char tag[128];
        snprintf(tag, sizeof tag, "%s on %d ranks", what, nps[k]);
        compare(d0, dk, tag);
        thb_check_parallel_record(dk, nps[k], n);
    }
}

void thb_must_run_auto_bricks(const char *path, int np, const char *dir)
{
    static char out[16384];
    cr_assert_eq(thb_run(path, np, dir, NULL, out, sizeof out), 0, "%s", out);
    cr_assert_null(strstr(out, "not decomposed"), "%s", out);
    thb_assert_bricks(dir, np, NULL);
}

void thb_read_text(const char *dir, const char *name, char *buf, size_t len)
{
    char path[700];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "%s", path);
    size_t n = fread(buf, 1, len - 1, f);
    buf[n] = '\0';
    fclose(f);
}

/* One whitespace-separated field of an XYZ line, with a header's `Key=`
 * and quotes taken off. */
static const char *xyz_field(char *tok)
{
    char *eq = strchr(tok, '=');
    if (eq)
        tok = eq + 1;
    while (*tok == '"')
        tok++;
    size_t n = strlen(tok);
    while (n && tok[n - 1] == '"')
        tok[--n] = '\0';
    return tok;
}

static int xyz_number(const char *s, double *x)
{
    char *end;
    *x = strtod(s, &end);
    return *s && end != s && *end == '\0';
}

#define XYZ_MAXCOL 64

/* Largest magnitude of each numeric column over the atom lines (from the
 * third line on). */
static void xyz_column_max(char **lines, long n, double *cmax)
{
    for (int k = 0; k < XYZ_MAXCOL; k++)
        cmax[k] = 0;
    for (long l = 2; l < n; l++) {
        char *copy = strdup(lines[l]), *save = NULL;
        int k = 0;
        for (char *t = strtok_r(copy, " \t", &save); t && k < XYZ_MAXCOL;
             t = strtok_r(NULL, " \t", &save), k++) {
            double x;
            if (xyz_number(xyz_field(t), &x) && fabs(x) > cmax[k])
                cmax[k] = fabs(x);
        }
        free(copy);
    }
}

static char **xyz_lines(const char *path, long *n)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s: cannot open", path);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    rewind(f);
    char *text = malloc((size_t)len + 1);
    cr_assert_eq(fread(text, 1, (size_t)len, f), (size_t)len, "%s: short read", path);
    fclose(f);
    text[len] = '\0';
    long cap = 16, k = 0;
    char **lines = malloc(cap * sizeof *lines);
    char *save = NULL;
    for (char *l = strtok_r(text, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
        if (k == cap)
            lines = realloc(lines, (cap *= 2) * sizeof *lines);
        lines[k++] = strdup(l);
    }
    free(text);
    *n = k;
    return lines;
}

/* The atom's id: the 11th field (species, pos:3, velo:3, forces:3, id). */
static long long xyz_line_id(const char *line)
{
    const char *p = line;
    for (int k = 0; k < 10; k++) {
        p += strcspn(p, " \t");
        p += strspn(p, " \t");
    }
    return strtoll(p, NULL, 10);
}

static int xyz_by_id(const void *a, const void *b)
{
    long long x = xyz_line_id(*(char *const *)a), y = xyz_line_id(*(char *const *)b);
    return (x > y) - (x < y);
}

void thb_compare_final_xyz(const char *a, const char *b, const char *name, double rel,
                           const char *tag)
{
    char pa[700], pb[700];
    snprintf(pa, sizeof pa, "%s/%s", a, name);
    snprintf(pb, sizeof pb, "%s/%s", b, name);
    long na, nb;
    char **la = xyz_lines(pa, &na), **lb = xyz_lines(pb, &nb);
    cr_assert_eq(na, nb, "%s: %s has %ld lines, %s %ld", tag, pa, na, pb, nb);
    cr_assert_geq(na, 3, "%s: %s holds no atoms", tag, pa);
    /* a serial run writes its atoms in memory (cell) order, bricks in id
     * order: compare by id */
    qsort(la + 2, (size_t)(na - 2), sizeof *la, xyz_by_id);
    qsort(lb + 2, (size_t)(nb - 2), sizeof *lb, xyz_by_id);
    double cmax[XYZ_MAXCOL];
    xyz_column_max(la, na, cmax);
    for (long l = 0; l < na; l++) {
        char *sa = NULL, *sb = NULL;
        char *ta = strtok_r(la[l], " \t", &sa), *tb = strtok_r(lb[l], " \t", &sb);
        for (int k = 0; ta || tb; k++) {
            cr_assert(ta && tb, "%s: %s line %ld: %d vs other field count", tag, name, l + 1, k);
            const char *fa = xyz_field(ta), *fb = xyz_field(tb);
            double x, y;
            if (xyz_number(fa, &x) && xyz_number(fb, &y)) {
                double scale = l >= 2 && k < XYZ_MAXCOL ? cmax[k] : fmax(fabs(x), fabs(y));
                double tol = 1e-9 * fmax(fabs(x), fabs(y)) + rel * scale;
                cr_assert_leq(fabs(x - y), tol, "%s: %s line %ld field %d: %.17g vs %.17g", tag,
                              name, l + 1, k + 1, x, y);
            } else {
                cr_assert_str_eq(fa, fb, "%s: %s line %ld field %d", tag, name, l + 1, k + 1);
            }
            ta = strtok_r(NULL, " \t", &sa);
            tb = strtok_r(NULL, " \t", &sb);
        }
    }
    for (long l = 0; l < na; l++) {
        free(la[l]);
        free(lb[l]);
    }
    free(la);
    free(lb);
}

json_t *thb_series_values(json_t *res, const char *name)
{
    json_t *s = json_object_get(json_object_get(res, "series"), name);
    return json_is_object(s) ? json_object_get(s, "values") : s;
}

void thb_compare_result_series(json_t *ra, json_t *rb, size_t min_series, double rel,
                               const char *tag)
{
    json_t *sa = json_object_get(ra, "series");
    cr_assert_geq(json_object_size(sa), min_series, "%s: %zu series", tag,
                  json_object_size(sa));
    const char *name;
    json_t *s;
    json_object_foreach(sa, name, s)
    {
        json_t *va = thb_series_values(ra, name), *vb = thb_series_values(rb, name);
        cr_assert(json_is_array(va) && json_is_array(vb), "%s: series %s missing", tag, name);
        size_t n = json_array_size(va);
        cr_assert_eq(n, json_array_size(vb), "%s: series %s length", tag, name);
        double scale = 0;
        for (size_t q = 0; q < n; q++)
            scale = fmax(scale, fabs(json_number_value(json_array_get(va, q))));
        for (size_t q = 0; q < n; q++) {
            json_t *xa = json_array_get(va, q), *xb = json_array_get(vb, q);
            cr_assert_eq(json_is_null(xa), json_is_null(xb), "%s: %s[%zu] null in one run",
                         tag, name, q);
            double x = json_number_value(xa), y = json_number_value(xb);
            cr_assert_leq(fabs(x - y), rel * scale + 1e-12 * fabs(x),
                          "%s: %s[%zu] %.17g vs %.17g", tag, name, q, x, y);
        }
    }
}

void thb_compare_grid(const char *a, const char *b, long step, const char *const *sets,
                      double rel, const char *tag)
{
    for (int k = 0; sets[k]; k++) {
        char name[96];
        snprintf(name, sizeof name, "/grid/%08ld/%s", step, sets[k]);
        long na = 0, nb = 0;
        double *va = thb_read_h5(a, name, H5T_NATIVE_DOUBLE, sizeof(double), &na);
        double *vb = thb_read_h5(b, name, H5T_NATIVE_DOUBLE, sizeof(double), &nb);
        cr_assert_eq(na, nb, "%s: %s has %ld vs %ld values", tag, name, na, nb);
        double scale = 0, worst = 0;
        for (long i = 0; i < na; i++)
            scale = fmax(scale, fabs(va[i]));
        for (long i = 0; i < na; i++)
            worst = fmax(worst, fabs(va[i] - vb[i]));
        cr_assert(scale > 0, "%s: %s is all zero", tag, name);
        cr_assert_leq(worst, rel * scale, "%s: %s differs by %g of %g", tag, name, worst, scale);
        free(va);
        free(vb);
    }
}

void thb_short_replicates(const char *path, int np, const char *stem)
{
    static char out[16384], ta[1 << 18], tb[1 << 18];
    char d0[600], dk[600], want[64];
    snprintf(d0, sizeof d0, "%s/%s-serial", th_temp_dir(), stem);
    snprintf(dk, sizeof dk, "%s/%s-%d", th_temp_dir(), stem, np);
    thb_must_run(path, 0, d0, NULL);
    cr_assert_eq(thb_run(path, np, dk, NULL, out, sizeof out), 0, "%s on %d ranks:\n%s", stem,
                 np, out);
    snprintf(want, sizeof want, "has no grid of %d bricks", np);
    cr_assert(strstr(out, want), "%s: no note '%s'\n%s", stem, want, out);
    thb_read_text(d0, "thermo.csv", ta, sizeof ta);
    thb_read_text(dk, "thermo.csv", tb, sizeof tb);
    const char *xa = strchr(ta, '\n'), *xb = strchr(tb, '\n');
    cr_assert(xa && xb && strlen(xa) > 50, "%s: thermo.csv too short", stem);
    cr_assert_str_eq(xa, xb, "%s: thermo.csv on %d ranks differs from the serial one", stem, np);
}

static int is_energy_change(const char *name)
{
    static const char *const changes[] = {"energy_drift", "energy_deviation_max",
                                          "energy_deviation_max_abs",
                                          "energy_error_impact_fraction", NULL};
    for (int k = 0; changes[k]; k++)
        if (strcmp(name, changes[k]) == 0)
            return 1;
    return 0;
}

void thb_compare_impact_metrics(json_t *ra, json_t *rb, double flyer_p, double rel,
                                const char *tag)
{
    json_t *ma = json_object_get(ra, "metrics"), *mb = json_object_get(rb, "metrics");
    cr_assert_gt(json_object_size(ma), 40, "%s: %zu metrics", tag, json_object_size(ma));
    double e0 = fabs(json_number_value(json_array_get(thb_series_values(ra, "etotal"), 1)));
    double ke0 = json_number_value(json_object_get(json_object_get(ma, "impact_energy"), "value"));
    cr_assert_gt(e0, 1e3, "%s: total energy %g eV", tag, e0);
    cr_assert_gt(ke0, 1.0, "%s: impact energy %g eV", tag, ke0);
    const char *k;
    json_t *v;
    int compared = 0;
    json_object_foreach(ma, k, v)
    {
        json_t *u = json_object_get(v, "value");
        json_t *w = json_object_get(json_object_get(mb, k), "value");
        cr_assert(u && w, "%s: metric %s missing", tag, k);
        cr_assert_eq(json_is_null(u), json_is_null(w), "%s: metric %s null in one run", tag, k);
        if (json_is_null(u))
            continue;
        double x = json_number_value(u), y = json_number_value(w), tol;
        compared++;
        if (strcmp(k, "momentum_change") == 0) {
            cr_assert_leq(fmax(x, y), rel * flyer_p, "%s: momentum_change %g, %g", tag, x, y);
            continue;
        }
        if (!is_energy_change(k))
            tol = rel * fabs(x) + 1e-12 * fabs(x);
        else if (strcmp(k, "energy_deviation_max_abs") == 0)
            tol = rel * e0;
        else if (strcmp(k, "energy_error_impact_fraction") == 0)
            tol = rel * e0 / ke0;
        else   /* over |E| */
            tol = rel;
        cr_assert_leq(fabs(x - y), tol, "%s: metric %s %.17g vs %.17g", tag, k, x, y);
    }
    cr_assert_gt(compared, 40, "%s: %d metrics compared", tag, compared);
}

void thb_assert_ranks_changed(const char *dir, const char *dir_step0, int np)
{
    json_t *r = thb_result(dir), *r0 = thb_result(dir_step0);
    json_t *per = json_object_get(json_object_get(r, "parallel"), "particles_per_rank");
    json_t *per0 = json_object_get(json_object_get(r0, "parallel"), "particles_per_rank");
    cr_assert_eq(json_array_size(per), (size_t)np);
    cr_assert_eq(json_array_size(per0), (size_t)np);
    int moved = 0;
    for (int i = 0; i < np; i++)
        moved |= json_integer_value(json_array_get(per, (size_t)i)) !=
                 json_integer_value(json_array_get(per0, (size_t)i));
    json_decref(r);
    json_decref(r0);
    cr_assert(moved, "no particle changed its rank (%s against %s)", dir, dir_step0);
}

void thb_compare_metrics_abs(const char *a, const char *b, const char *const *names,
                             double tol, const char *tag)
{
    json_t *ra = thb_result(a), *rb = thb_result(b);
    for (int k = 0; names[k]; k++) {
        double va = thb_metric(ra, names[k]), vb = thb_metric(rb, names[k]);
        cr_assert_leq(fabs(va - vb), tol, "%s: %s %.17g vs %.17g (tolerance %g)", tag, names[k],
                      va, vb, tol);
    }
    json_decref(ra);
    json_decref(rb);
}

double thb_balance_record(const char *dir, long *checks, long *shifts, double *worst)
{
    json_t *r = thb_result(dir);
    json_t *par = json_object_get(r, "parallel");
    cr_assert_not_null(par, "%s: no parallel record", dir);
    cr_assert_not_null(json_object_get(par, "balance_checks"), "%s: no balance record", dir);
    double imbalance = json_real_value(json_object_get(par, "imbalance_max_over_mean"));
    if (checks)
        *checks = (long)json_integer_value(json_object_get(par, "balance_checks"));
    if (shifts)
        *shifts = (long)json_integer_value(json_object_get(par, "balance_shifts"));
    if (worst)
        *worst = json_real_value(json_object_get(par, "imbalance_worst_at_checks"));
    json_decref(r);
    return imbalance;
}
