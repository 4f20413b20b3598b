/*
 * mpm_kernel_probe: the cost of one MPM step of the reference problem
 * (two elastic aluminium cubes in head-on impact, 250,000 points, 61 x 35
 * x 35 cells, linear shape functions, MUSL, bench/cases/mpm_two_cubes.yaml
 * built through the library in metal units) apart from everything else a
 * run does, for the kernel work of issue 18.  It runs WARM steps (130 by
 * default: the cubes touch at step 119, so the timed steps carry stress),
 * then STEPS steps timing each in CPU time, and prints the fastest and the
 * median step per particle: on a shared machine the fastest of many steps
 * is the figure least moved by the other processes.  The whole step and
 * its two halves are timed (mpm_step_map: s9 and any mapping the fused
 * pass did not do; mpm_step_update: s4-s14 and the next step's s1-s3).
 *
 *   mpm_kernel_probe [STEPS [WARM [THREADS [COARSEN [TIMED]]]]]
 *   -> "points P step_min_ns S step_median_ns D step_mean_ns A map_min_ns M
 *       update_min_ns U wall_min_ns W wall_median_ns V balance2_blocks B
 *       balance2_slabs L ke K"
 *
 * step_*, map_*, update_*: CPU time of the process (all threads) per
 * point; step_mean_ns: the timed steps' CPU time over their number, the
 * figure a run's loop time corresponds to (it includes the periodic
 * reorder's steps, which the median passes over: with WARM 0 and STEPS
 * 500 the bench case's whole loop minus the engine around the steps).
 * TIMED 1 gives the model the solver's stage timers (struct timers), as a
 * run has them, so their own cost shows against TIMED 0.
 * wall_*: the same steps in wall-clock time (with THREADS 2 on a
 * loaded machine the fastest wall step is the one that found both cores).
 * balance2_*: how close two threads taking the blocks of each colour one
 * by one come to half the work (1 = perfectly), counted in points per
 * block at the end -- for this grid's blocks and for the slabs of 3 cells
 * across x that the colouring used before (docs/bench.md).
 *
 * COARSEN > 1 makes the cells (and the points' spacing) that many times
 * larger: the same cubes with COARSEN^3 times fewer points, whose arrays
 * stay in the caches -- the kernels' cost without the memory traffic.
 * ke: kinetic energy after the last step (eV), so two builds can be seen
 * to compute the same thing.  Built by bench/bench_mpm.sh against the
 * release build's libraries.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "core/timers.h"
#include "mpm/mpm.h"
#include "mpm/mpm_build.h"

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double wall_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* The share of ideal T-thread speed the coloured passes can reach with the
 * points per block `w(b)`: threads take a colour's blocks in list order,
 * each the next one when it is free (schedule(dynamic, 1)), work counted in
 * points; returns total work / (T x the sum over colours of the last
 * thread's finish).  1 = perfect balance. */
static double balance(int T, int ncol, const long *ncb, const int32_t *const *list,
                      const long *start)
{
    double work = 0, span = 0;
    for (int c = 0; c < ncol; c++) {
        double fin[64] = {0};
        for (long i = 0; i < ncb[c]; i++) {
            long b = list[c][i];
            int t0 = 0;
            for (int t = 1; t < T; t++)
                if (fin[t] < fin[t0])
                    t0 = t;
            fin[t0] += (double)(start[b + 1] - start[b]);
            work += (double)(start[b + 1] - start[b]);
        }
        double mx = 0;
        for (int t = 0; t < T; t++)
            mx = fin[t] > mx ? fin[t] : mx;
        span += mx;
    }
    return span > 0 ? work / (T * span) : 1;
}

/* The same for this grid's blocks and for the slabs of 3 cells across x
 * (two colours) that the colouring used before the blocks, from where the
 * points are now. */
static void balances(const struct mpm *m, int T, double *blocks, double *slabs)
{
    const struct mpm_grid *g = &m->grid;
    const int32_t *list[MPM_COLOURS];
    for (int c = 0; c < MPM_COLOURS; c++)
        list[c] = g->colour_block[c];
    *blocks = balance(T, MPM_COLOURS, g->ncolour, list, m->bins[0].start);
    long ns = (g->ncell[0] + 2) / 3;
    long *start = calloc((size_t)ns + 1, sizeof *start);
    int32_t *sl = malloc((size_t)ns * sizeof *sl);
    if (!start || !sl) {
        *slabs = 0;
        free(start);
        free(sl);
        return;
    }
    for (long p = 0; p < m->pts.n; p++) {
        long key = (long)((m->pts.x[3 * p] - g->origin[0]) * g->inv_hd[0]);
        start[key / 3 + 1]++;
    }
    for (long k = 0; k < ns; k++)
        start[k + 1] += start[k];
    long nsc[2] = {0, 0};
    for (long k = 0; k < ns; k += 2)
        sl[nsc[0]++] = (int32_t)k;
    for (long k = 1; k < ns; k += 2)
        sl[nsc[0] + nsc[1]++] = (int32_t)k;
    const int32_t *slist[2] = {sl, sl + nsc[0]};
    *slabs = balance(T, 2, nsc, slist, start);
    free(start);
    free(sl);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int fail(const struct err *e)
{
    fprintf(stderr, "mpm_kernel_probe: %s\n", e->msg);
    return 1;
}

/* the reference problem: 0.01 m cells = 1e8 Å; aluminium 2700 kg/m^3 =
 * 1.6260 amu/Å^3, E = 70 GPa = 0.43691 eV/Å^3, 50 m/s = 0.5 Å/ps */
static int build(struct mpm *m, int nthreads, int coarsen, struct err *e)
{
    const double h = 1e8 * coarsen, origin[3] = {0, 0, 0};
    const long cells[3] = {(61 + coarsen - 1) / coarsen, (35 + coarsen - 1) / coarsen,
                           (35 + coarsen - 1) / coarsen};
    struct mpm_grid g;
    int rc = mpm_grid_init_uniform(&g, origin, h, cells, MPM_SHAPE_LINEAR, e);
    const enum mpm_face_bc free6[6] = {0};
    if (!rc)
        rc = mpm_grid_set_faces(&g, free6, e);
    if (!rc)
        rc = mpm_init(m, &g, 0, nthreads, e);
    if (rc)
        return rc;
    struct mpm_material *al = mpm_material_linear_elastic("al", 2.7 * 0.6022140762, 70 / 160.21766,
                                                          0.3);
    if (!al)
        return err_nomem(e, "material");
    int mat = mpm_add_material(m, al, e);
    if (mat < 0)
        return ERR_RUNTIME;
    const double xlo[2] = {0.05, 0.31}, vx[2] = {0.5, -0.5};
    for (int k = 0; k < 2; k++) {
        struct mpm_body b = {.material = mat};
        snprintf(b.name, sizeof b.name, "%c", 'A' + k);
        b.velocity[0] = vx[k];
        int body = mpm_add_body(m, &b, e);
        if (body < 0)
            return ERR_INPUT;
        struct region r = {.shape = REGION_BOX};
        for (int d = 0; d < 3; d++) {
            r.lo[d] = 0.05 * 1e10;
            r.hi[d] = 0.30 * 1e10;
        }
        r.lo[0] = xlo[k] * 1e10;
        r.hi[0] = (xlo[k] + 0.25) * 1e10;
        long added, kept;
        rc = mpm_fill_region(m, &r, body, 2, NULL, (int64_t)m->pts.n + 1, &added, &kept, e);
        if (rc)
            return rc;
    }
    m->sort_every = 50;
    return mpm_prepare(m, e);
}

int main(int argc, char **argv)
{
    int steps = argc > 1 ? atoi(argv[1]) : 100;
    int warm = argc > 2 ? atoi(argv[2]) : 130;
    int nthreads = argc > 3 ? atoi(argv[3]) : 1;
    int coarsen = argc > 4 ? atoi(argv[4]) : 1;
    int timed = argc > 5 ? atoi(argv[5]) : 0;
    if (steps < 1 || warm < 0 || nthreads < 1 || coarsen < 1) {
        fprintf(stderr, "usage: mpm_kernel_probe [STEPS [WARM [THREADS [COARSEN [TIMED]]]]]\n");
        return 2;
    }
    struct mpm m;
    struct err e = {0};
    if (build(&m, nthreads, coarsen, &e))
        return fail(&e);
    struct timers tm = {0};
    if (timed)
        m.timers = &tm;
    double *t = malloc(4 * (size_t)steps * sizeof *t);
    if (!t)
        return 1;
    double *tmap = t + steps, *tupd = t + 2 * steps, *twall = t + 3 * steps;
    for (int s = 0; s < warm + steps; s++) {
        double dt = 0.5 * mpm_stable_dt(&m);
        double w0 = wall_seconds();
        double t0 = cpu_seconds();
        if (mpm_step_map(&m, &e))
            return fail(&e);
        double t1 = cpu_seconds();
        if (mpm_step_update(&m, dt, &e))
            return fail(&e);
        double t2 = cpu_seconds();
        if (s >= warm)
            twall[s - warm] = wall_seconds() - w0;
        if (s >= warm) {
            t[s - warm] = t2 - t0;
            tmap[s - warm] = t1 - t0;
            tupd[s - warm] = t2 - t1;
        }
    }
    double scale = 1e9 / (double)m.pts.n;
    double med, sum = 0;
    for (int s = 0; s < steps; s++)
        sum += t[s];
    qsort(tmap, (size_t)steps, sizeof *t, cmp_double);
    qsort(tupd, (size_t)steps, sizeof *t, cmp_double);
    qsort(t, (size_t)steps, sizeof *t, cmp_double);
    qsort(twall, (size_t)steps, sizeof *t, cmp_double);
    med = t[steps / 2];
    double bal_blocks, bal_slabs;
    balances(&m, 2, &bal_blocks, &bal_slabs);
    printf("points %ld step_min_ns %.1f step_median_ns %.1f step_mean_ns %.1f map_min_ns %.1f "
           "update_min_ns %.1f wall_min_ns %.1f wall_median_ns %.1f balance2_blocks %.3f "
           "balance2_slabs %.3f ke %.12e\n",
           m.pts.n, t[0] * scale, med * scale, sum / steps * scale, tmap[0] * scale, tupd[0] * scale,
           twall[0] * scale, twall[steps / 2] * scale, bal_blocks, bal_slabs, m.ke);
    free(t);
    mpm_free(&m);
    return 0;
}
