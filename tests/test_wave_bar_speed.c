/*
 * The longitudinal front against the bar (Pochhammer) speed, measured
 * without a chosen threshold (analysis/wave_front.h: the pulse centroid),
 * on MPM bars where the answer is known (E = 1 eV/Å^3, nu = 0.25, so
 * sqrt(C11/rho) is sqrt(1.2) = 9.5 % above sqrt(E/rho)):
 *
 * - a pulse 20 Å long (a traction held for 0.45 ps) in a bar 2 Å wide with
 *   free lateral faces: the bar contracts laterally (uniaxial stress), and
 *   the pulse centroid fitted over 21 probes travels at sqrt(E/rho) within
 *   2 % (wavelength ten times the width: the Pochhammer correction is
 *   below 1e-3);
 * - the same bar with sliding lateral faces (uniaxial strain, as a
 *   laterally periodic slab): sqrt(C11/rho) within 2 %;
 * - in both, the rise's centres (f = 0.5, mid(0.2, 0.8), mid(0.1, 0.9))
 *   agree within 3 % (not flagged), and the f = 0.5 front agrees with the
 *   pulse centroid within 3 %: a pulse ten widths long has no separate
 *   precursor.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/wave_front.h"
#include "core/units.h"
#include "helpers/th_mpm.h"

#define E_MOD 1.0   /* eV/Å^3 */
#define NU 0.25
#define RHO 5.0     /* amu/Å^3 */
#define SIGMA0 (0.1 / UNITS_EVA3_TO_GPA)
#define LEN 256
#define WIDTH 2

static const enum mpm_face_bc faces_free_sides[6] = {MPM_FACE_FREE, MPM_FACE_FREE,
                                                     MPM_FACE_FREE, MPM_FACE_FREE,
                                                     MPM_FACE_FREE, MPM_FACE_FREE};

/* Mean x velocity of the points that started in [x, x + 1). */
static double slab_velocity(const struct mpm *m, double x)
{
    double sum = 0;
    long n = 0;
    for (long p = 0; p < m->pts.n; p++) {
        double x0 = m->pts.x0[3 * p];
        if (x0 >= x && x0 < x + 1) {
            sum += m->pts.v[3 * p];
            n++;
        }
    }
    return n ? sum / n : 0;
}

/* The pulse of the file's comment in a bar with the given lateral faces;
 * the wave_front measurement of the slab velocities. */
static void measure(const enum mpm_face_bc faces[6], struct wave_front_result *r)
{
    struct mpm m;
    long nc[3] = {LEN, WIDTH, WIDTH};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, faces, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", RHO, E_MOD, NU));
    double lo[3] = {0, 0, 0}, hi[3] = {LEN, WIDTH, WIDTH};
    th_mpm_box(&m, "bar", mat, lo, hi, 2, NULL, 0);
    struct err e = {0};
    cr_assert_eq(mpm_points_enable_fext(&m.pts, &e), 0);
    double cbar = sqrt(E_MOD / RHO * UNITS_FTM2V), hold = 20.0 / cbar;
    enum { NPROBE = 21, CAP = 6000 };
    double x[NPROBE];
    for (int k = 0; k < NPROBE; k++)
        x[k] = 50.0 + 5.0 * k;
    double *t = malloc(CAP * sizeof *t), *sig = malloc((size_t)CAP * NPROBE * sizeof *sig);
    cr_assert(t && sig);
    long n = 0;
    double dt = 0.5 * mpm_stable_dt(&m);
    /* until the pulse's tail is 20 Å past the last probe at the longitudinal speed */
    while (n < CAP && m.time * cbar < 1.2 * (x[NPROBE - 1] + 60)) {
        double on = m.time < hold ? 1.0 : 0.0;
        for (long p = 0; p < m.pts.n; p++)
            if (m.pts.x0[3 * p] < 0.5)
                m.pts.fext[3 * p] = on * SIGMA0 * m.pts.vol0[p] / 0.5;
        t[n] = m.time;
        for (int k = 0; k < NPROBE; k++)
            sig[n * NPROBE + k] = slab_velocity(&m, x[k]);
        n++;
        cr_assert_eq(mpm_step(&m, dt, &e), 0, "%s", e.msg);
    }
    for (int k = 0; k < NPROBE; k++)
        x[k] += 0.5;
    wave_front_measure(t, n, sig, NPROBE, x, NULL, 0.1, r);
    free(t);
    free(sig);
    mpm_free(&m);
}

static double c11(void) { return E_MOD * (1 - NU) / ((1 + NU) * (1 - 2 * NU)); }

static void check(const struct wave_front_result *r, double expect, const char *what)
{
    double cp = r->pulse_centroid.speed, cf = r->speed_fit;
    cr_log_info("%s: pulse centroid %.4f +- %.4f Å/ps (%+.2f %% from %.4f), f = 0.5 front %.4f "
                "(%+.2f %%), centres spread %.4f, rise centroid %.4f, broadening %.5f ps/Å",
                what, cp, r->pulse_centroid.stderr_, 100 * (cp / expect - 1), expect, cf,
                100 * (cf / expect - 1), r->spread, r->rise_centroid.speed, r->broadening);
    cr_expect(fabs(cp / expect - 1) < 0.02, "%s: pulse centroid %g against %g", what, cp, expect);
    cr_expect_eq(r->flag, WAVE_FRONT_OK, "%s: flag %d, spread %g", what, r->flag, r->spread);
    cr_expect(fabs(cf / cp - 1) < 0.03, "%s: front %g, centroid %g", what, cf, cp);
}

Test(wave_bar_speed, free_sides_give_the_bar_speed, .timeout = 120)
{
    struct wave_front_result r;
    measure(faces_free_sides, &r);
    check(&r, sqrt(E_MOD / RHO * UNITS_FTM2V), "free lateral faces, sqrt(E/rho)");
}

Test(wave_bar_speed, sliding_sides_give_the_longitudinal_speed, .timeout = 120)
{
    struct wave_front_result r;
    measure(th_mpm_faces_bar, &r);
    check(&r, sqrt(c11() / RHO * UNITS_FTM2V), "sliding lateral faces, sqrt(C11/rho)");
}
