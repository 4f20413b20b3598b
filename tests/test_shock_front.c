/*
 * Shock-front detection and the equation-of-state relations
 * (solver/analysis/shock_front.h, eos.h).
 *
 *   - a synthetic shock: 1-D particles with velocity up/2 (1 + tanh((x_f -
 *     x) / w)), thermal noise, and an elastic precursor of 0.2 up running
 *     ahead; the front moves at Us = 48 Å/ps.  The half-height front is
 *     found within a quarter slab of the truth at every time, the fitted
 *     speed is within 0.5 % of Us, and a level of 0.1 up finds the
 *     precursor instead (faster);
 *   - the Rankine-Hugoniot momentum condition in metal units against a
 *     hand calculation for copper; the Us-up fit recovers c0 and s from
 *     exact data and honours the fit range; the linearised Vinet fit
 *     recovers B0 and B0' from a synthetic isotherm.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/eos.h"
#include "analysis/shock_front.h"
#include "core/rng.h"

#define NP 40000
#define NB 400

static void synthetic(double t, double *x, double *v, struct rng_seq *r)
{
    const double up = 10.0, us = 48.0, w = 2.0, L = 800.0;
    const double x_f = 20.0 + us * t, x_e = 20.0 + 62.0 * t;   /* precursor at 62 Å/ps */
    for (int i = 0; i < NP; i++) {
        x[i] = L * (i + 0.5) / NP;
        double main = 0.5 * 0.8 * up * (1 + tanh((x_f - x[i]) / w));
        double pre = 0.5 * 0.2 * up * (1 + tanh((x_e - x[i]) / w));
        v[i] = main + pre + 2.0 * rng_seq_gaussian(r);   /* thermal noise 2 Å/ps per particle */
    }
}

Test(shock_front, synthetic_profile_front_and_speed)
{
    double *x = malloc(NP * sizeof *x), *v = malloc(NP * sizeof *v);
    double mean[NB];
    long count[NB];
    double t[8], xf[8], xp[8];
    struct rng_seq *r = rng_seq_create(42);
    for (int k = 0; k < 8; k++) {
        t[k] = 2.0 + 1.0 * k;
        synthetic(t[k], x, v, r);
        shock_profile(x, 1, v, 1, NP, 0.0, 2.0, NB, mean, count);
        /* level: midway between the precursor plateau (0.2 up) and up */
        cr_assert_eq(shock_front_locate(mean, count, NB, 0.0, 2.0, 6.0, +1, 10, &xf[k]), 0);
        double truth = 20.0 + 48.0 * t[k];
        cr_assert_lt(fabs(xf[k] - truth), 0.5, "t = %g: front at %g, truth %g", t[k], xf[k], truth);
        cr_assert_eq(shock_front_locate(mean, count, NB, 0.0, 2.0, 1.0, +1, 10, &xp[k]), 0);
    }
    double us, err, x0;
    struct err e = {0};
    cr_assert_eq(shock_speed_fit(t, xf, 8, &us, &err, &x0, &e), 0, "%s", e.msg);
    cr_assert_lt(fabs(us - 48.0) / 48.0, 0.005, "Us = %g +- %g Å/ps, truth 48", us, err);
    cr_assert_lt(err, 0.2);
    double up_pre;
    cr_assert_eq(shock_speed_fit(t, xp, 8, &up_pre, &err, &x0, &e), 0);
    cr_assert_lt(fabs(up_pre - 62.0), 1.0, "precursor speed %g, truth 62", up_pre);
    /* a level nothing reaches */
    double pos;
    cr_assert_eq(shock_front_locate(mean, count, NB, 0.0, 2.0, 50.0, +1, 10, &pos), -1);
    /* a shock running towards -x: mirror the last profile */
    double mm[NB];
    long cc[NB];
    for (int k = 0; k < NB; k++) {
        mm[k] = mean[NB - 1 - k];
        cc[k] = count[NB - 1 - k];
    }
    cr_assert_eq(shock_front_locate(mm, cc, NB, 0.0, 2.0, 6.0, -1, 10, &pos), 0);
    cr_assert_lt(fabs(pos - (800.0 - xf[7])), 1e-9, "mirrored front %g vs %g", pos, 800.0 - xf[7]);
    cr_assert_eq(shock_speed_fit(t, xf, 2, &us, &err, &x0, &e), ERR_RUNTIME);
    rng_seq_destroy(&r);
    free(x);
    free(v);
}

Test(shock_front, rankine_hugoniot_and_fits)
{
    /* copper, rho0 = 8.93 g/cm^3 = 5.378 amu/Å^3 ... in amu/Å^3:
     * 8.93e3 kg/m^3 / 1660.539 = 5.3777 amu/Å^3; Us = 5.43, up = 1 km/s:
     * P = rho0 Us up = 8930 * 5430 * 1000 Pa = 48.49 GPa */
    double rho0 = 8930.0 / 1660.5390666;
    double p = eos_rh_pressure(rho0, 54.3, 10.0) * 160.21766208;
    cr_assert_lt(fabs(p - 48.4899) / 48.4899, 1e-4, "P = %g GPa", p);
    cr_assert_float_eq(eos_rh_compression(54.3, 10.0), 54.3 / 44.3, 1e-14);

    double up[6] = {0.5, 1.0, 1.5, 2.0, 2.5, 3.0}, us[6];
    for (int k = 0; k < 6; k++)
        us[k] = 3.94 + 1.49 * up[k];
    us[0] = 5.5;   /* an outlier outside the fit range */
    double c0, s, c0e, se;
    int used;
    struct err e = {0};
    cr_assert_eq(eos_fit_us_up(up, us, 6, 1.5, 3.0, &c0, &s, &c0e, &se, &used, &e), 0, "%s", e.msg);
    cr_assert_eq(used, 4);
    cr_assert_float_eq(c0, 3.94, 1e-10);
    cr_assert_float_eq(s, 1.49, 1e-10);
    cr_assert_eq(eos_fit_us_up(up, us, 6, 5.0, 6.0, &c0, &s, &c0e, &se, &used, &e), ERR_RUNTIME);

    double vr[8], pv[8];
    for (int k = 0; k < 8; k++) {
        vr[k] = 1.0 - 0.05 * k;
        pv[k] = eos_vinet_pressure(vr[k], 137.0, 5.2);
    }
    double b0, b0p;
    cr_assert_eq(eos_fit_vinet(vr, pv, 8, &b0, &b0p, &e), 0, "%s", e.msg);
    cr_assert_float_eq(b0, 137.0, 1e-8);
    cr_assert_float_eq(b0p, 5.2, 1e-8);
}
