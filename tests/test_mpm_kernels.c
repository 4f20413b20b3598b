/*
 * The fast paths of the MPM kernels against their plain forms:
 *
 * - The stress update of isotropic linear elastic points, four at a time
 *   in vector lanes (mpm_stress_chunk.h), against the point-by-point update
 *   (mpm_stress.h, taken when the material's inlined moduli are withheld):
 *   an impact of two bodies, with and without the Jaumann rotation, ends
 *   with the same stresses, deformation gradients, volumes, positions and
 *   velocities to 1e-12 of their largest values (the two forms are the same
 *   operations; only fused multiply-adds may round differently).
 * - Stage timers change nothing: the same impact with timers ends with the
 *   same bits, and the fused pass booked a share of its time (measured on
 *   every MPM_SPLIT_EVERY-th step, applied to the others) as p2g.
 * - The reorder of the points (mpm_points_permute) by following the
 *   permutation's cycles (a few points move) and component by component
 *   (many move) against the definition new[k] = old[perm[k]]: every array,
 *   bit for bit.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th_mpm.h"

static void impact_timed(struct mpm *m, int vector_law, int jaumann, struct timers *tm)
{
    long nc[3] = {40, 12, 10};
    th_mpm_uniform(m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_free, 2);
    struct mpm_material *mat = mpm_material_linear_elastic("s", 5.0, 1.0, 0.3);
    cr_assert_not_null(mat);
    mat->jaumann = jaumann;
    if (!vector_law)
        mat->iso = NULL;   /* the law through its table, point by point */
    int k = th_mpm_material(m, mat);
    double lo1[3] = {12, 2, 2}, hi1[3] = {19.5, 8, 6}, v1[3] = {4, 0.5, 0.2};
    double lo2[3] = {20, 1, 2}, hi2[3] = {30, 9, 7}, v2[3] = {-4, 0.3, 0.3};
    th_mpm_box(m, "A", k, lo1, hi1, 2, v1, 0);
    th_mpm_box(m, "B", k, lo2, hi2, 2, v2, 0);
    m->sort_every = 7;
    m->timers = tm;
    th_mpm_run(m, 40, 0.5);
}

static void impact(struct mpm *m, int vector_law, int jaumann)
{
    impact_timed(m, vector_law, jaumann, NULL);
}

static double max_abs(const double *a, long n)
{
    double r = 0;
    for (long i = 0; i < n; i++)
        r = fmax(r, fabs(a[i]));
    return r;
}

static void same_to_round_off(const double *a, const double *b, long n, const char *what)
{
    double scale = max_abs(a, n), worst = 0;
    cr_assert(scale > 0, "%s: all zero", what);
    for (long i = 0; i < n; i++)
        worst = fmax(worst, fabs(a[i] - b[i]));
    cr_assert(worst <= 1e-12 * scale, "%s differ by %g of %g", what, worst, scale);
}

Test(mpm_kernels, vector_stress_update_matches_point_by_point)
{
    for (int jaumann = 0; jaumann < 2; jaumann++) {
        struct mpm a, b;
        impact(&a, 1, jaumann);
        impact(&b, 0, jaumann);
        long n = a.pts.n;
        cr_assert(b.pts.n == n && n > 1000);
        cr_assert(memcmp(a.pts.id, b.pts.id, (size_t)n * sizeof *a.pts.id) == 0);
        /* the bodies collided: stresses of the impact's order rho c v */
        cr_assert(max_abs(a.pts.stress, 6 * n) > 1e-3, "no impact");
        same_to_round_off(a.pts.stress, b.pts.stress, 6 * n, "stresses");
        same_to_round_off(a.pts.F, b.pts.F, 9 * n, "deformation gradients");
        same_to_round_off(a.pts.vol, b.pts.vol, n, "volumes");
        same_to_round_off(a.pts.eint, b.pts.eint, n, "stress work");
        same_to_round_off(a.pts.x, b.pts.x, 3 * n, "positions");
        same_to_round_off(a.pts.v, b.pts.v, 3 * n, "velocities");
        cr_assert(fabs(a.strain - b.strain) <= 1e-12 * a.strain, "strain energy %.17g vs %.17g",
                  a.strain, b.strain);
        mpm_free(&a);
        mpm_free(&b);
    }
}

Test(mpm_kernels, timers_change_nothing_and_book_the_fused_mapping_as_p2g)
{
    struct mpm a, b;
    struct timers tm = {0};
    impact(&a, 1, 1);
    impact_timed(&b, 1, 1, &tm);
    long n = a.pts.n;
    cr_assert(b.pts.n == n && mpm_fusable(&a));
    cr_assert(memcmp(a.pts.x, b.pts.x, 3 * (size_t)n * sizeof(double)) == 0, "positions");
    cr_assert(memcmp(a.pts.stress, b.pts.stress, 6 * (size_t)n * sizeof(double)) == 0,
              "stresses");
    cr_assert(memcmp(a.pts.F, b.pts.F, 9 * (size_t)n * sizeof(double)) == 0, "F");
    /* 40 steps: the share was timed at steps 0, 16 and 32 */
    cr_assert(b.fused_map_share > 0 && b.fused_map_share < 1, "mapping share %g",
              b.fused_map_share);
    cr_assert(a.fused_map_share < 0, "untimed run timed the share");
    cr_assert(tm.total[TIMER_MPM_P2G] > 0 && tm.total[TIMER_MPM_G2P] > 0 &&
                  tm.total[TIMER_MPM_GRID] > 0,
              "p2g %g g2p %g grid %g s", tm.total[TIMER_MPM_P2G], tm.total[TIMER_MPM_G2P],
              tm.total[TIMER_MPM_GRID]);
    mpm_free(&a);
    mpm_free(&b);
}

/* n points whose every array holds values unique to the point */
static void numbered_points(struct mpm_points *p, long n)
{
    struct err e = {0};
    cr_assert_eq(mpm_points_init(p, 2, &e), 0, "%s", e.msg);
    cr_assert_eq(mpm_points_enable_fext(p, &e), 0, "%s", e.msg);
    for (long i = 0; i < n; i++) {
        double x[3] = {i, i + 0.25, i + 0.5}, v[3] = {-i, -i - 0.25, -i - 0.5};
        cr_assert(mpm_points_add(p, x, v, 1.0 + i, 2.0 + i, (int)(i % 5), 100 + i, &e) == i);
        p->x0[3 * i + 1] = 7.0 * i;
        for (int c = 0; c < 6; c++)
            p->stress[6 * i + c] = 10.0 * i + c;
        for (int c = 0; c < 9; c++)
            p->F[9 * i + c] = 20.0 * i + c;
        p->vol[i] = 3.0 + i;
        p->eint[i] = 4.0 + i;
        p->state[2 * i] = 5.0 + i;
        p->state[2 * i + 1] = 6.0 + i;
        for (int c = 0; c < 3; c++)
            p->fext[3 * i + c] = 30.0 * i + c;
        p->mask[i] = (uint32_t)(i * 3);
    }
}

static void check_permuted(const struct mpm_points *p, const struct mpm_points *o,
                           const int32_t *perm)
{
    for (long k = 0; k < p->n; k++) {
        long j = perm[k];
        cr_assert(memcmp(p->x + 3 * k, o->x + 3 * j, 3 * sizeof(double)) == 0, "x of %ld", k);
        cr_assert(memcmp(p->x0 + 3 * k, o->x0 + 3 * j, 3 * sizeof(double)) == 0);
        cr_assert(memcmp(p->v + 3 * k, o->v + 3 * j, 3 * sizeof(double)) == 0);
        cr_assert(memcmp(p->stress + 6 * k, o->stress + 6 * j, 6 * sizeof(double)) == 0);
        cr_assert(memcmp(p->F + 9 * k, o->F + 9 * j, 9 * sizeof(double)) == 0);
        cr_assert(memcmp(p->state + 2 * k, o->state + 2 * j, 2 * sizeof(double)) == 0);
        cr_assert(memcmp(p->fext + 3 * k, o->fext + 3 * j, 3 * sizeof(double)) == 0);
        cr_assert(p->mass[k] == o->mass[j] && p->vol0[k] == o->vol0[j] &&
                  p->vol[k] == o->vol[j] && p->eint[k] == o->eint[j], "scalars of %ld", k);
        cr_assert(p->body[k] == o->body[j] && p->id[k] == o->id[j] && p->mask[k] == o->mask[j],
                  "integers of %ld", k);
    }
}

Test(mpm_kernels, reorder_by_cycles_and_by_components_match_the_definition)
{
    const long n = 1000;
    int32_t *perm = malloc((size_t)n * sizeof *perm);
    double *tmp = malloc((size_t)n * sizeof *tmp);
    cr_assert(perm && tmp);
    for (int many = 0; many < 2; many++) {
        struct mpm_points p, o;
        numbered_points(&p, n);
        numbered_points(&o, n);
        for (long k = 0; k < n; k++)
            perm[k] = (int32_t)(many ? n - 1 - k : k);
        if (!many) {   /* a few points move: a 3-cycle, a swap and a 5-cycle */
            int32_t c3[3] = {10, 500, 999}, c5[5] = {0, 1, 2, 3, 4};
            for (int i = 0; i < 3; i++)
                perm[c3[i]] = c3[(i + 1) % 3];
            perm[20] = 21;
            perm[21] = 20;
            for (int i = 0; i < 5; i++)
                perm[c5[i]] = c5[(i + 2) % 5];
        }
        mpm_points_permute(&p, perm, tmp, 2);
        check_permuted(&p, &o, perm);
        mpm_points_free(&p);
        mpm_points_free(&o);
    }
    free(perm);
    free(tmp);
}
