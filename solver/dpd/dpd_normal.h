/*
 * dpd_normal: the standard normal number of a uniform P in (0, 1) by the
 * inverse normal CDF of Wichura (Appl. Stat. 37, 477 (1988), algorithm
 * AS 241, PPND16: rational approximations of degree 7/7, relative error
 * 1e-16), written inline so that the pair sweep's compiler sees through it.
 *
 * The coefficients are the paper's and the polynomials are evaluated in the
 * paper's nested (Horner) order, the evaluation GSL's
 * gsl_cdf_ugaussian_Pinv uses too, so with the expression contraction off
 * (-std=c11 turns GCC's -ffp-contract off) the value is the same to the
 * last bit (tests/test_dpd_normal.c checks this on 10^6 draws): the DPD
 * random stream is unchanged.  As in GSL, P = 1 gives +inf (the stream's
 * uniform rounds to 1 once in 2^53 draws; it is never 0).
 */
#ifndef CASCADE_DPD_NORMAL_H
#define CASCADE_DPD_NORMAL_H

#include <math.h>

/* a[7] x^7 + ... + a[0] over b[7] x^7 + ... + b[0], Horner from the top */
static inline double dpd_normal_rat(const double a[8], const double b[8], double x)
{
    double u = a[7], v = b[7];
    for (int k = 6; k >= 0; k--) {
        u = x * u + a[k];
        v = x * v + b[k];
    }
    return u / v;
}

/* |P - 1/2| <= 0.425: x = q A(r) / B(r), r = 0.180625 - q^2 */
static const double dpd_normal_a0[8] = {
    3.387132872796366608,  133.14166789178437745, 1971.5909503065514427, 13731.693765509461125,
    45921.953931549871457, 67265.770927008700853, 33430.575583588128105, 2509.0809287301226727};
static const double dpd_normal_b0[8] = {
    1.0,                   42.313330701600911252, 687.1870074920579083,  5394.1960214247511077,
    21213.794301586595867, 39307.89580009271061,  28729.085735721942674, 5226.4952788528545610};
/* tails, r = sqrt(-log(min(P, 1 - P))) <= 5: C(r - 1.6) / D(r - 1.6) */
static const double dpd_normal_a1[8] = {
    1.42343711074968357734,  4.6303378461565452959,    5.7694972214606914055,
    3.64784832476320460504,  1.27045825245236838258,   0.24178072517745061177,
    0.0227238449892691845833, 7.7454501427834140764e-4};
static const double dpd_normal_b1[8] = {
    1.0,                    2.05319162663775882187,   1.6763848301838038494,
    0.68976733498510000455, 0.14810397642748007459,   0.0151986665636164571966,
    5.475938084995344946e-4, 1.05075007164441684324e-9};
/* r > 5: E(r - 5) / F(r - 5) */
static const double dpd_normal_a2[8] = {
    6.6579046435011037772,   5.4637849111641143699,    1.7848265399172913358,
    0.29656057182850489123,  0.026532189526576123093,  0.0012426609473880784386,
    2.71155556874348757815e-5, 2.01033439929228813265e-7};
static const double dpd_normal_b2[8] = {
    1.0,                      0.59983220655588793769,   0.13692988092273580531,
    0.0148753612908506148525, 7.868691311456132591e-4,  1.8463183175100546818e-5,
    1.4215117583164458887e-7, 2.04426310338993978564e-15};

/* 1 when P needs the tails' form (15 % of the draws) */
static inline int dpd_normal_is_tail(double P) { return !(fabs(P - 0.5) <= 0.425); }

/* The central form, for P with dpd_normal_is_tail(P) == 0: no branch, so
 * a loop of them vectorises. */
static inline double dpd_normal_central(double P)
{
    double q = P - 0.5;
    return q * dpd_normal_rat(dpd_normal_a0, dpd_normal_b0, 0.180625 - q * q);
}

static inline double dpd_normal_of_uniform(double P)
{
    if (P == 1.0)
        return INFINITY;
    if (!dpd_normal_is_tail(P))
        return dpd_normal_central(P);
    double r = sqrt(-log(P < 0.5 ? P : 1.0 - P));
    double x = r <= 5.0 ? dpd_normal_rat(dpd_normal_a1, dpd_normal_b1, r - 1.6)
                        : dpd_normal_rat(dpd_normal_a2, dpd_normal_b2, r - 5.0);
    return P < 0.5 ? -x : x;
}

#endif
