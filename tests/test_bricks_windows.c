/*
 * Text outputs of a run on bricks (output/final_state.c, md_output.c):
 * the XYZ frames, final.xyz and a LAMMPS data file hold every rank's
 * atoms in id order, written by rank 0 a window of HALO_GATHER_WINDOW
 * (32,768) atoms at a time (core/halo.h, halo_gather_windows), so no rank
 * holds them all; an XYZ frame's per-atom stresses divide by the volume
 * per atom of the whole system, not of a window.  With 42,592 atoms the
 * walk takes two windows; on 2 and 3 ranks the files have the serial
 * run's header lines, every atom once, in ascending id order (a serial
 * run writes its own order), with the serial positions, velocities,
 * forces, energies and stresses to REL of each column's largest
 * magnitude (the sums of a brick run in another order).
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"
#include "helpers/th_bricks.h"

#define REL 1e-10
#define NATOMS 42592L   /* 22^3 fcc cells */

/* One section of a data file: ids and up to 6 numbers a line. */
struct rows {
    long n;
    long long *id;
    double (*v)[6];
};

/* The lines of `path` from the line after `heading` (and its blank line)
 * up to the next blank line: id then ncol numbers (a type first when
 * typed). */
static struct rows read_section(const char *path, const char *heading, int typed, int ncol)
{
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "cannot read %s", path);
    struct rows r = {0, malloc(sizeof(long long) * (NATOMS + 1)),
                     malloc(sizeof(double[6]) * (NATOMS + 1))};
    cr_assert(r.id && r.v);
    char line[512];
    int in = 0;
    while (fgets(line, sizeof line, f)) {
        if (!in) {
            in = strncmp(line, heading, strlen(heading)) == 0;
            if (in && fgets(line, sizeof line, f) == NULL)
                break;   /* the blank line after the heading */
            continue;
        }
        if (line[0] == '\n')
            break;
        cr_assert_lt(r.n, NATOMS + 1, "%s: more than %ld lines in %s", path, NATOMS, heading);
        char *s = line, *end;
        r.id[r.n] = strtoll(s, &end, 10);
        s = end;
        if (typed)
            (void)strtol(s, &s, 10);
        for (int c = 0; c < ncol; c++) {
            r.v[r.n][c] = strtod(s, &end);
            cr_assert_neq(end, s, "%s: %s line %ld: too few numbers", path, heading, r.n + 1);
            s = end;
        }
        r.n++;
    }
    fclose(f);
    return r;
}

static int cmp_row(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

/* A serial run's rows in id order (it writes its atoms in its own order). */
static void sort_rows(struct rows *r)
{
    struct {
        long long id;
        double v[6];
    } *t = malloc(sizeof *t * (size_t)(r->n ? r->n : 1));
    cr_assert(t);
    for (long i = 0; i < r->n; i++) {
        t[i].id = r->id[i];
        memcpy(t[i].v, r->v[i], sizeof t[i].v);
    }
    qsort(t, (size_t)r->n, sizeof *t, cmp_row);
    for (long i = 0; i < r->n; i++) {
        r->id[i] = t[i].id;
        memcpy(r->v[i], t[i].v, sizeof t[i].v);
    }
    free(t);
}

static void free_rows(struct rows *r)
{
    free(r->id);
    free(r->v);
}

/* Every atom once, in ascending id order, and the values of b those of a
 * to REL of each column's largest magnitude. */
static void compare_rows(const struct rows *a, const struct rows *b, int ncol, const char *tag)
{
    cr_assert_eq(a->n, NATOMS, "%s: %ld rows", tag, a->n);
    cr_assert_eq(b->n, NATOMS, "%s: %ld rows", tag, b->n);
    for (int c = 0; c < ncol; c++) {
        double scale = 0, worst = 0;
        for (long i = 0; i < a->n; i++)
            scale = fmax(scale, fabs(a->v[i][c]));
        for (long i = 0; i < a->n; i++) {
            cr_assert_eq(a->id[i], b->id[i], "%s: row %ld: id %lld vs %lld", tag, i, a->id[i],
                         b->id[i]);
            cr_assert(i == 0 || b->id[i] > b->id[i - 1], "%s: ids not ascending at row %ld", tag,
                      i);
            worst = fmax(worst, fabs(a->v[i][c] - b->v[i][c]));
        }
        cr_assert_leq(worst, REL * scale + 1e-13, "%s: column %d differs by %g of %g", tag, c,
                      worst, scale);
    }
}

/* The lines before the Atoms section: title, counts, bounds, masses. */
static void compare_data_headers(const char *a, const char *b, const char *tag)
{
    FILE *fa = fopen(a, "r"), *fb = fopen(b, "r");
    cr_assert(fa && fb, "%s: cannot read %s or %s", tag, a, b);
    char la[512], lb[512];
    int lines = 0;
    while (fgets(la, sizeof la, fa) && fgets(lb, sizeof lb, fb)) {
        cr_assert_str_eq(la, lb, "%s: header line %d", tag, lines + 1);
        lines++;
        if (strncmp(la, "Atoms", 5) == 0)
            break;
    }
    cr_assert_gt(lines, 8, "%s: %d header lines", tag, lines);
    fclose(fa);
    fclose(fb);
}

/* The atoms of frame `frame` (0 the first) of an XYZ file: ids and
 * positions and velocities, or (extras: a frame with energies and
 * stresses) x, vx, fx, the energy, sxx and sxy. */
static struct rows read_frame(const char *path, int frame, int extras)
{
    FILE *f = fopen(path, "r");
    cr_assert_not_null(f, "cannot read %s", path);
    struct rows r = {0, malloc(sizeof(long long) * (NATOMS + 1)),
                     malloc(sizeof(double[6]) * (NATOMS + 1))};
    cr_assert(r.id && r.v);
    static char line[2048];
    for (int k = 0; k <= frame; k++) {
        cr_assert(fgets(line, sizeof line, f), "%s: no frame %d", path, k);
        cr_assert_eq(atol(line), NATOMS, "%s: count line %s", path, line);
        cr_assert(fgets(line, sizeof line, f));   /* the comment line */
        cr_assert(!extras || strstr(line, "energies:R:1:stress:R:6"), "%s: %s", path, line);
        for (long i = 0; i < NATOMS; i++) {
            cr_assert(fgets(line, sizeof line, f), "%s: frame %d has too few lines", path, k);
            if (k < frame)
                continue;
            double c[22];
            char *s = strchr(line, ' '), *end;   /* after the species */
            int nc = extras ? 22 : 11;
            for (int j = 1; j < nc; j++) {
                c[j] = strtod(s, &end);
                cr_assert_neq(end, s, "%s: line of atom %ld: too few columns", path, i);
                s = end;
            }
            r.id[r.n] = (long long)c[10];
            double pick[6] = {c[1], c[2], c[3], c[4], c[5], c[6]};
            double more[6] = {c[1], c[4], c[7], extras ? c[15] : 0, extras ? c[16] : 0,
                              extras ? c[19] : 0};
            memcpy(r.v[r.n], extras ? more : pick, sizeof(double[6]));
            r.n++;
        }
    }
    fclose(f);
    return r;
}

Test(bricks_windows, final_state_and_xyz_pass_in_windows, .timeout = 600)
{
    const char *yaml = "seed: 5\nsystem:\n  lattice: {style: fcc, a: 5.26, cells: [22, 22, 22]}\n"
                       "  element: Ar\npotential: {style: lj, elements: [Ar], epsilon: "
                       "[0.0104], sigma: [3.4], cutoff: 8.5}\n"
                       "md: {steps: 2, temperature: 60, timestep: 0.002}\n"
                       "parallel: {decomposition: bricks}\n"
                       "output: {thermo_every: 1, xyz_every: 2, hdf5: false, "
                       "final_state: state.data}\n";
    const char *path = th_write_temp(0, "windows.yaml", yaml);
    char serial[600];
    snprintf(serial, sizeof serial, "%s/windows-serial", th_temp_dir());
    thb_must_run(path, 0, serial, NULL);
    char sd[700], sx[700];
    snprintf(sd, sizeof sd, "%s/state.data", serial);
    snprintf(sx, sizeof sx, "%s/final.xyz", serial);
    struct rows atoms0 = read_section(sd, "Atoms", 1, 3);
    struct rows vel0 = read_section(sd, "Velocities", 0, 3);
    struct rows xyz0 = read_frame(sx, 0, 0);
    char sf[700];
    snprintf(sf, sizeof sf, "%s/snapshots.xyz", serial);
    struct rows frame0 = read_frame(sf, 1, 1);   /* step 2: energies and stresses */
    sort_rows(&atoms0);
    sort_rows(&vel0);
    sort_rows(&xyz0);
    sort_rows(&frame0);
    static const int nps[] = {2, 3};
    for (int k = 0; k < 2; k++) {
        char dir[600], tag[64], d[700], x[700];
        snprintf(dir, sizeof dir, "%s/windows-%d", th_temp_dir(), nps[k]);
        thb_must_run(path, nps[k], dir, NULL);
        snprintf(d, sizeof d, "%s/state.data", dir);
        snprintf(x, sizeof x, "%s/final.xyz", dir);
        snprintf(tag, sizeof tag, "%d ranks, state.data", nps[k]);
        compare_data_headers(sd, d, tag);
        struct rows atoms = read_section(d, "Atoms", 1, 3);
        struct rows vel = read_section(d, "Velocities", 0, 3);
        compare_rows(&atoms0, &atoms, 3, tag);
        compare_rows(&vel0, &vel, 3, tag);
        snprintf(tag, sizeof tag, "%d ranks, final.xyz", nps[k]);
        struct rows xyz = read_frame(x, 0, 0);
        compare_rows(&xyz0, &xyz, 6, tag);
        thb_compare_final_xyz(serial, dir, "final.xyz", REL, tag);
        snprintf(tag, sizeof tag, "%d ranks, snapshots.xyz step 2", nps[k]);
        snprintf(x, sizeof x, "%s/snapshots.xyz", dir);
        struct rows fr = read_frame(x, 1, 1);
        compare_rows(&frame0, &fr, 6, tag);
        free_rows(&atoms);
        free_rows(&vel);
        free_rows(&xyz);
        free_rows(&fr);
    }
    free_rows(&atoms0);
    free_rows(&vel0);
    free_rows(&xyz0);
    free_rows(&frame0);
}
