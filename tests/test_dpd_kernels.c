/*
 * The DPD sweep's arithmetic (solver/dpd/dpd_normal.h, dpd_ou.h): the
 * inline inverse normal CDF gives GSL's numbers bit for bit (the random
 * stream of the pair sweep is unchanged), and the pair update's series
 * form matches the exact Ornstein-Uhlenbeck step (computed with expm1, no
 * cancellation) to round-off and the old formula to its cancellation error.
 */
#include <criterion/criterion.h>
#include <gsl/gsl_cdf.h>
#include <math.h>

#include "core/rng.h"
#include "dpd/dpd_normal.h"
#include "dpd/dpd_ou.h"

Test(dpd_kernels, normal_is_gsl_bit_for_bit)
{
    long tails = 0;
    for (uint64_t k = 0; k < 1000000; k++) {
        double P = rng_uniform(rng_key(7, RNG_SITE_DPDE_PAIR, k / 1000, k, 3 * k), 0);
        double a = gsl_cdf_ugaussian_Pinv(P), b = dpd_normal_of_uniform(P);
        tails += fabs(P - 0.5) > 0.425;
        cr_assert(a == b, "P = %.17g: GSL %.17g, inline %.17g", P, a, b);
    }
    /* both branches met (15 % of the draws lie in the tails) */
    cr_assert(tails > 140000 && tails < 160000, "tails %ld", tails);
    /* the far tail (r > 5) and the ends of the stream's range */
    const double far[] = {1e-12, 1e-15, 1 - 1e-12, 0x1p-54, 1.0 - 0x1p-53, 1.0};
    for (unsigned k = 0; k < sizeof far / sizeof far[0]; k++)
        cr_assert(gsl_cdf_ugaussian_Pinv(far[k]) == dpd_normal_of_uniform(far[k]),
                  "P = %.17g", far[k]);
}

/* The exact step: u e^{-x} + sqrt(kB Theta / mu (1 - e^{-2x})) xi with
 * 1 - e^{-2x} = -expm1(-2x). */
static double exact_unew(const struct dpd_ou *o, double urel, double wr, double invmu, double xi,
                         double ui, double uj)
{
    double theta = o->dpde ? 2.0 / (o->cvkb / ui + o->cvkb / uj) : o->T0;
    double kT = UNITS_KB * theta * UNITS_FTM2V;
    double x = o->gamma * o->T0 / theta * wr * wr * invmu * o->dt;
    return urel * exp(-x) + sqrt(kT * invmu * -expm1(-2 * x)) * xi;
}

Test(dpd_kernels, ou_series_matches_exact_step)
{
    /* Chen 2014's particles (508.368 amu), DPDE with C_v = 3 kB * 8 atoms;
     * gammas from the runs' 0.2 amu/ps up to where x approaches 1e-3 and
     * beyond (the exact formula takes over) */
    const double gammas[] = {0.2, 5, 50, 2000, 20000};
    const double invmu = 2.0 / 508.368, urel = 0.731, xi = -1.37;
    for (int dpde = 0; dpde <= 1; dpde++)
        for (unsigned g = 0; g < sizeof gammas / sizeof gammas[0]; g++)
            for (double wr = 0.05; wr < 1; wr += 0.1) {
                struct dpd_ou o;
                dpd_ou_init(&o, dpde, gammas[g], 298, 24, 0.005);
                double cv = 24 * UNITS_KB, ui = cv * 350, uj = cv * 280;
                struct dpd_ou_pair q;
                dpd_ou_pair_set(&o, &q, wr, invmu, xi);
                double got = dpd_ou_unew(&o, &q, urel, ui, uj);
                double want = exact_unew(&o, urel, wr, invmu, xi, ui, uj);
                double old = dpd_ou_general(&o, urel, wr, invmu, xi, ui, uj);
                /* the change of u is what matters: compare it */
                double scale = fabs(want - urel) + 1e-300;
                cr_assert(fabs(got - want) <= 1e-12 * scale + 1e-15 * fabs(urel),
                          "dpde %d gamma %g wr %g: series %.17g exact %.17g", dpde, gammas[g], wr,
                          got, want);
                /* the old form loses digits to 1 - decay^2 at small x only */
                cr_assert(fabs(old - want) <= 1e-6 * scale + 1e-15 * fabs(urel),
                          "dpde %d gamma %g wr %g: old %.17g exact %.17g", dpde, gammas[g], wr, old,
                          want);
            }
}

Test(dpd_kernels, ou_non_positive_energy_takes_the_old_rule)
{
    /* an internal energy at zero: infinite friction, no noise (Theta = 0):
     * the pair's relative velocity along e_ij is stopped */
    struct dpd_ou o;
    dpd_ou_init(&o, 1, 0.2, 298, 24, 0.005);
    struct dpd_ou_pair q;
    dpd_ou_pair_set(&o, &q, 0.5, 2.0 / 508.368, 0.8);
    cr_assert_eq(dpd_ou_unew(&o, &q, 0.9, 0.0, 1.0), 0.0);
}
