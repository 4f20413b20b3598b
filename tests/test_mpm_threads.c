/*
 * Threads: the particle-to-grid loops run over colouring blocks whose nodes
 * never overlap within a colour, and every other loop is independent per
 * point or node, so an impact computed with 1, 2 and 3 threads gives
 * bit-for-bit the same positions, velocities and stresses (2 and 3 threads
 * against 1; the machine may have fewer cores, which only costs time) -- on a uniform
 * grid with linear and GIMP shape functions and on a hierarchical grid.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "helpers/th_mpm.h"

static void impact(struct mpm *m, int kind, int nthreads)
{
    long nc[3] = {40, 12, 10};
    if (kind == 2) {
        struct mpm_hlevel lv = {3, {.shape = REGION_SLAB, .axis = 0, .lo = {24, 0, 0},
                                    .hi = {1e9, 0, 0}}};
        th_mpm_hier(m, nc, 1.0, &lv, 1, MPM_HANGING_MODIFIED, th_mpm_faces_free, nthreads);
    } else {
        th_mpm_uniform(m, nc, 1.0, kind ? MPM_SHAPE_GIMP : MPM_SHAPE_LINEAR, th_mpm_faces_free,
                       nthreads);
    }
    int mat = th_mpm_material(m, mpm_material_linear_elastic("s", 5.0, 1.0, 0.3));
    double lo1[3] = {12, 2, 2}, hi1[3] = {19.5, 8, 6}, v1[3] = {4, 0.5, 0};
    double lo2[3] = {20, 1, 2}, hi2[3] = {30, 9, 7}, v2[3] = {-4, 0, 0.3};
    th_mpm_box(m, "A", mat, lo1, hi1, 2, v1, 0);
    th_mpm_box(m, "B", mat, lo2, hi2, 2, v2, 0);
    m->sort_every = 7;
    th_mpm_run(m, 30, 0.5);
}

static void compare(int kind)
{
    struct mpm a, b, c;
    impact(&a, kind, 1);
    impact(&b, kind, 2);
    impact(&c, kind, 3);
    long n = a.pts.n;
    cr_assert(b.pts.n == n && c.pts.n == n);
    const struct mpm *o[2] = {&b, &c};
    for (int k = 0; k < 2; k++) {
        cr_assert(memcmp(a.pts.x, o[k]->pts.x, 3 * n * sizeof(double)) == 0,
                  "kind %d: positions differ with %d threads", kind, k + 2);
        cr_assert(memcmp(a.pts.v, o[k]->pts.v, 3 * n * sizeof(double)) == 0,
                  "kind %d: velocities differ with %d threads", kind, k + 2);
        cr_assert(memcmp(a.pts.stress, o[k]->pts.stress, 6 * n * sizeof(double)) == 0,
                  "kind %d: stresses differ with %d threads", kind, k + 2);
        cr_assert(a.time == o[k]->time);
    }
    /* and the impact did happen: the bodies are stressed */
    double smax = 0;
    for (long p = 0; p < 6 * n; p++)
        smax = fmax(smax, a.pts.stress[p] < 0 ? -a.pts.stress[p] : a.pts.stress[p]);
    cr_assert(smax > 1e-3, "no stress: kind %d", kind);
    mpm_free(&a);
    mpm_free(&b);
    mpm_free(&c);
}

Test(mpm_threads, linear_results_independent_of_thread_count)
{
    compare(0);
}

Test(mpm_threads, gimp_results_independent_of_thread_count)
{
    compare(1);
}

Test(mpm_threads, hierarchical_results_independent_of_thread_count)
{
    compare(2);
}
