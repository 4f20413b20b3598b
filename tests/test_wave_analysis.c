/*
 * Wave analysis (solver/analysis): the arrival criterion -- first crossing
 * of a threshold, linearly interpolated -- and the speed between two
 * regions; Lagrangian slab means and profiles of displacements; the block
 * standard error of a correlated mean.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "analysis/block_average.h"
#include "analysis/displacement.h"
#include "analysis/wave_arrival.h"

/* A ramp front s(t) = max(0, t - t0) * rate sampled every 0.1 ps: the
 * interpolated crossing of 0.2 is exact, also for negative signals. */
Test(wave_analysis, arrival_interpolates_the_crossing)
{
    double t[50], s1[50], s2[50], neg[50];
    for (int k = 0; k < 50; k++) {
        t[k] = 0.1 * k;
        s1[k] = fmax(0, t[k] - 1.23) * 0.5;
        s2[k] = fmax(0, t[k] - 2.53) * 0.5;
        neg[k] = -s1[k];
    }
    double t1 = wave_arrival_time(t, s1, 50, 0.2), t2 = wave_arrival_time(t, s2, 50, 0.2);
    cr_assert_float_eq(t1, 1.63, 1e-12);
    cr_assert_float_eq(t2, 2.93, 1e-12);
    cr_assert_float_eq(wave_speed(50.0, t1, t2), 50.0 / 1.3, 1e-9);
    cr_assert_float_eq(wave_arrival_time(t, neg, 50, -0.2), 1.63, 1e-12);
    cr_assert(isnan(wave_arrival_time(t, s1, 50, 100.0)), "never reached must be NAN");
    cr_assert(isnan(wave_speed(50.0, t2, t1)), "a later first arrival gives no speed");
}

/* Particles moved by u(x) = 0.01 x: the slab mean and the profile recover
 * it at the slab centres, selected by reference position even after the
 * particles have moved, with excluded groups left out. */
Test(wave_analysis, lagrangian_slabs_and_profiles)
{
    struct particles *p = particles_create(16);
    particles_type_index(p, "Cu", 63.5);
    for (int i = 0; i < 100; i++) {
        double x[3] = {i + 0.5, 0, 0};
        particles_add(p, x, NULL, 0, i + 1);
    }
    p->mask[0] |= 2u;
    struct box b = {{0, 0, 0}, {100, 1, 1}, {BOUNDARY_FREE, BOUNDARY_FREE, BOUNDARY_FREE}, {0, 0, 0}};
    struct err e = {0};
    int f = displacement_begin(p, &b, &e);
    cr_assert_geq(f, 0, "%s", e.msg);
    for (int i = 0; i < 100; i++)
        p->x[3 * i] += 0.01 * p->x[3 * i] + (i == 0 ? 50.0 : 0.0);
    long n;
    double m = displacement_slab_mean(p, &b, f, 0, 40, 60, 2u, &n);
    cr_assert_eq(n, 20);
    cr_assert_float_eq(m, 0.5, 1e-12);
    double prof[10];
    displacement_profile(p, &b, f, 0, 0.0, 10.0, 10, 2u, prof);
    for (int k = 1; k < 10; k++)
        cr_assert_float_eq(prof[k], 0.01 * (10 * k + 5), 1e-12, "bin %d: %g", k, prof[k]);
    cr_assert_float_eq(prof[0], 0.01 * 5.5, 1e-12, "excluded particle counted: %g", prof[0]);
    particles_destroy(&p);
}

/* Blocks of a series with a known mean: the error estimate is the spread
 * of block means; a constant series has none. */
Test(wave_analysis, block_standard_error)
{
    double x[100];
    for (int k = 0; k < 100; k++)
        x[k] = (k / 10) % 2 ? 1.0 : -1.0;   /* ten blocks of +-1 */
    double sem;
    double m = block_average(x, 100, 10, &sem);
    cr_assert_float_eq(m, 0.0, 1e-15);
    cr_assert_float_eq(sem, sqrt(10.0 / 9.0 / 10.0), 1e-12, "sem %g", sem);
    for (int k = 0; k < 100; k++)
        x[k] = 3.0;
    m = block_average(x, 100, 10, &sem);
    cr_assert_float_eq(m, 3.0, 1e-15);
    cr_assert_float_eq(sem, 0.0, 1e-15);
}
