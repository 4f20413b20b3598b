/*
 * Elastic waves in MPM bars (1-D: one cell across, sliding lateral faces,
 * so the strain is uniaxial and the longitudinal modulus is C11):
 *
 * - a step load launches a wave whose front (half amplitude) travels at
 *   sqrt(C11 / rho) within 2 %;
 * - the same wave measured as the cases do (analysis/wave_front.h: 21
 *   probes from 50 to 150 Å, each at f = 0.1/0.2/0.5 of its own peak,
 *   least-squares fit): within 2 % of sqrt(C11 / rho), standard error
 *   below 1 %, spread over the fractions below 3 % (not flagged);
 * - a 100 MPa step stress wave passes from fine cells into 2x coarser cells
 *   of a hierarchical grid (Guo & Yang 2005, Fig. 2) with its amplitude
 *   within 5 % of the analytical 100 MPa on both sides.
 */
#include <criterion/criterion.h>
#include <math.h>

#include <stdlib.h>

#include "analysis/wave_front.h"
#include "core/units.h"
#include "helpers/th_mpm.h"

#define E_MOD 1.0      /* eV/Å^3 */
#define NU 0.25
#define RHO 5.0        /* amu/Å^3 */
#define SIGMA0 (0.1 / UNITS_EVA3_TO_GPA)   /* 100 MPa in eV/Å^3 */

static double c11(void)
{
    return E_MOD * (1 - NU) / ((1 + NU) * (1 - 2 * NU));
}

/* A bar [0, 256) x [0, w)^2 loaded by a step traction SIGMA0 (compressive)
 * on its first layer of points. */
static void bar(struct mpm *m, int hier)
{
    long w = hier ? 2 : 1;
    long nc[3] = {256, w, w};
    if (hier) {
        struct mpm_hlevel lv = {7, {.shape = REGION_SLAB, .axis = 0, .lo = {96, 0, 0},
                                    .hi = {1e9, 0, 0}}};
        th_mpm_hier(m, nc, 1.0, &lv, 1, MPM_HANGING_MODIFIED, th_mpm_faces_bar, 1);
    } else {
        th_mpm_uniform(m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_bar, 1);
    }
    int mat = th_mpm_material(m, mpm_material_linear_elastic("s", RHO, E_MOD, NU));
    double lo[3] = {0, 0, 0}, hi[3] = {256, (double)w, (double)w};
    th_mpm_box(m, "bar", mat, lo, hi, 2, NULL, 0);
    struct err e = {0};
    cr_assert_eq(mpm_points_enable_fext(&m->pts, &e), 0);
    /* the layer x = 0.25 (spacing 0.5) carries t x area: f = t V / 0.5 */
    for (long p = 0; p < m->pts.n; p++)
        if (m->pts.x[3 * p] < 0.5)
            m->pts.fext[3 * p] = SIGMA0 * m->pts.vol[p] / 0.5;
}

/* Time when the mean -sigma_xx / SIGMA0 of the points in [x, x + dx)
 * first reaches 1/2, interpolated between steps; runs until then. */
static double arrival(struct mpm *m, double x, double dx, double *prev, double *t_prev)
{
    struct err e = {0};
    for (int s = 0; s < 4000; s++) {
        double a = -th_mpm_mean_stress(m, 0, x, x + dx) / SIGMA0;
        if (a >= 0.5 && s > 0)
            return m->time - (m->time - *t_prev) * (a - 0.5) / (a - *prev);
        *prev = a;
        *t_prev = m->time;
        cr_assert_eq(mpm_step(m, 0.5 * mpm_stable_dt(m), &e), 0, "%s", e.msg);
    }
    cr_assert_fail("the wave never reached x = %g", x);
    return 0;
}

Test(mpm_wave, longitudinal_speed_is_sqrt_c11_over_rho)
{
    struct mpm m;
    bar(&m, 0);
    double prev = 0, tp = 0;
    double t1 = arrival(&m, 50, 1, &prev, &tp);
    prev = 0;
    double t2 = arrival(&m, 150, 1, &prev, &tp);
    double c = 100.0 / (t2 - t1);
    double c0 = sqrt(c11() / RHO * UNITS_FTM2V);
    cr_assert(fabs(c / c0 - 1) < 0.02, "wave speed %g Å/ps, sqrt(C11/rho) = %g Å/ps (%.2f %%)", c,
              c0, 100 * (c / c0 - 1));
    mpm_free(&m);
}

Test(mpm_wave, front_fit_gives_sqrt_c11_over_rho)
{
    struct mpm m;
    bar(&m, 0);
    enum { NPROBE = 21, CAP = 4000 };
    double x[NPROBE];
    for (int k = 0; k < NPROBE; k++)
        x[k] = 50.0 + 5.0 * k;
    double c0 = sqrt(c11() / RHO * UNITS_FTM2V);
    double *t = malloc(CAP * sizeof *t), *sig = malloc((size_t)CAP * NPROBE * sizeof *sig);
    cr_assert(t && sig);
    struct err e = {0};
    long n = 0;
    /* until the front is 20 Å past the last probe */
    while (n < CAP && m.time * c0 < 170) {
        t[n] = m.time;
        for (int k = 0; k < NPROBE; k++)
            sig[n * NPROBE + k] = -th_mpm_mean_stress(&m, 0, x[k], x[k] + 1) / SIGMA0;
        n++;
        cr_assert_eq(mpm_step(&m, 0.5 * mpm_stable_dt(&m), &e), 0, "%s", e.msg);
    }
    /* probe centres: the slabs are [x, x + 1) */
    for (int k = 0; k < NPROBE; k++)
        x[k] += 0.5;
    struct wave_front_result r;
    wave_front_measure(t, n, sig, NPROBE, x, NULL, 0.0, &r);
    cr_log_info("front fit %.4f +- %.4f Å/ps (sqrt(C11/rho) %.4f, %+.2f %%), spread %.4f, f = "
                "0.1/0.2/0.5: %.4f %.4f %.4f",
                r.speed_fit, r.stderr_, c0, 100 * (r.speed_fit / c0 - 1), r.spread,
                r.fit[0].speed, r.fit[1].speed, r.fit[2].speed);
    cr_expect_eq(r.flag, WAVE_FRONT_OK, "flag %d, spread %g", r.flag, r.spread);
    cr_expect(fabs(r.speed / c0 - 1) < 0.02, "front fit %g Å/ps, sqrt(C11/rho) = %g (%.2f %%)",
              r.speed, c0, 100 * (r.speed / c0 - 1));
    cr_expect(r.stderr_ < 0.01 * c0, "standard error %g Å/ps", r.stderr_);
    cr_expect(r.spread < 0.03, "spread %g", r.spread);
    free(t);
    free(sig);
    mpm_free(&m);
}

Test(mpm_wave, step_wave_passes_from_fine_to_coarse_cells)
{
    struct mpm m;
    bar(&m, 1);
    cr_assert(m.grid.hg->ncell_level[1] > 0);
    double c0 = sqrt(c11() / RHO * UNITS_FTM2V);
    struct err e = {0};
    /* until the front is at x = 210: 114 Å into the coarse region */
    while (m.time * c0 < 210)
        cr_assert_eq(mpm_step(&m, 0.5 * mpm_stable_dt(&m), &e), 0, "%s", e.msg);
    double fine = -th_mpm_mean_stress(&m, 0, 20, 70) / SIGMA0;
    double coarse = -th_mpm_mean_stress(&m, 0, 110, 180) / SIGMA0;
    cr_assert(fabs(fine - 1) < 0.05, "fine-cell amplitude %.4f x 100 MPa", fine);
    cr_assert(fabs(coarse - 1) < 0.05, "coarse-cell amplitude %.4f x 100 MPa", coarse);
    /* the wave has not reached the far end yet: points beyond the front unstressed */
    double ahead = th_mpm_mean_stress(&m, 0, 230, 256) / SIGMA0;
    cr_assert(fabs(ahead) < 0.05, "stress ahead of the front %.3g", ahead);
    mpm_free(&m);
}
