/*
 * dpd_ou: one pair's exact dissipative + random update in the Shardlow
 * sweep (dpd_sweep.c, dpd_sweep_cells.c), written so that the part that
 * waits on the previous pair is short.
 *
 * The relative velocity along e_ij is an Ornstein-Uhlenbeck process over
 * the step (dpd_sweep.c):
 *     u' = u e^{-x} + sqrt(kB Theta / mu (1 - e^{-2x})) xi,
 *     x  = lambda dt = gamma_ij w^D(r) dt / mu,   w^D = (w^R)^2.
 * In DPDE gamma_ij = gamma T0 / Theta_ij with 1/Theta_ij = C_v kB (1/u_i +
 * 1/u_j) / 2, so
 *     x  = [gamma dt (w^R)^2 / mu] T0 C_v kB (u_i + u_j) / (2 u_i u_j)
 * (isothermal DPD: x = gamma dt (w^R)^2 / mu), and since kB Theta x is
 * gamma kB T0 (w^R)^2 dt / mu whatever Theta is, the noise amplitude is
 *     sqrt(kB Theta / mu (1 - e^{-2x})) = s h(x),
 *     s = sqrt(2 gamma kB T0 dt) w^R / mu,  h(x) = sqrt((1 - e^{-2x}) / (2x)):
 * the random force does not depend on the internal energies (sigma is fixed
 * by T0: Espanol 1997), only the friction does.  For x < 1e-3 (every pair
 * of the Chen 2014 runs has x < 1e-5) e^{-x} and h(x) are their Taylor
 * polynomials of degree 4, exact to a part in 1e-17, so a pair waits for
 * one division and two short polynomials after the previous pair instead of
 * four divisions, exp and sqrt; larger x, and internal energies that are
 * not positive, take the formula of dpd_sweep.c as it was written.  The
 * result is that formula's to round-off (the old 1 - e^{-2x}, computed as
 * 1 - decay^2, lost some 11 digits of its 16 to cancellation at x ~ 1e-6;
 * h(x) does not).
 */
#ifndef CASCADE_DPD_OU_H
#define CASCADE_DPD_OU_H

#include <math.h>

#include "core/units.h"

struct dpd_ou {
    int dpde;
    double gamma_dt;     /* gamma dt, amu */
    double theta_fac;    /* DPDE: T0 C_v kB / 2 (eV); 1 for DPD */
    double xfac;         /* gamma_dt theta_fac */
    double s0;           /* sqrt(2 gamma kB T0 dt), amu Å/ps */
    double kT0;          /* kB T0, amu (Å/ps)^2 */
    double gamma, dt, cvkb, T0;
};

/* heat_capacity: C_v in kB per particle (DPDE) */
static inline void dpd_ou_init(struct dpd_ou *o, int dpde, double gamma, double T0,
                               double heat_capacity, double dt)
{
    o->dpde = dpde;
    o->gamma = gamma;
    o->dt = dt;
    o->T0 = T0;
    o->cvkb = heat_capacity * UNITS_KB;
    o->kT0 = UNITS_KB * T0 * UNITS_FTM2V;
    o->gamma_dt = gamma * dt;
    o->theta_fac = dpde ? 0.5 * T0 * o->cvkb : 1.0;
    o->xfac = o->gamma_dt * o->theta_fac;
    o->s0 = sqrt(2.0 * gamma * o->kT0 * dt);
}

#define DPD_OU_XMAX 1e-3

/* The formula of the original sweep (large x, non-positive energies). */
static inline double dpd_ou_general(const struct dpd_ou *o, double urel, double wr, double invmu,
                                    double xi, double ui, double uj)
{
    double kT, gij;
    if (o->dpde) {
        double ti = ui / o->cvkb, tj = uj / o->cvkb;
        double theta = ti > 0 && tj > 0 ? 2.0 / (1.0 / ti + 1.0 / tj) : 0.0;
        kT = UNITS_KB * theta * UNITS_FTM2V;
        gij = theta > 0 ? o->gamma * o->kT0 / kT : o->kT0 > 0 ? INFINITY : 0.0;
    } else {
        kT = o->kT0;
        gij = o->gamma;
    }
    double lam = gij * wr * wr * invmu;
    double decay = isinf(lam) ? 0.0 : exp(-lam * o->dt);
    return urel * decay + sqrt(kT * invmu * (1.0 - decay * decay)) * xi;
}

/* What a pair's update needs that does not wait on earlier pairs. */
struct dpd_ou_pair {
    double xcoef;   /* theta_fac gamma dt (w^R)^2 / mu: x = xcoef (DPD),
                     * xcoef (u_i + u_j) / (u_i u_j) (DPDE) */
    double noise;   /* s0 w^R / mu * xi, Å/ps */
    double wr, invmu, xi;
};

static inline void dpd_ou_pair_set(const struct dpd_ou *o, struct dpd_ou_pair *q, double wr,
                                   double invmu, double xi)
{
    q->xcoef = o->xfac * wr * wr * invmu;
    q->noise = o->s0 * wr * invmu * xi;
    q->wr = wr;
    q->invmu = invmu;
    q->xi = xi;
}

/* u' for relative velocity urel and internal energies ui, uj (DPDE). */
static inline double dpd_ou_unew(const struct dpd_ou *o, const struct dpd_ou_pair *q, double urel,
                                 double ui, double uj)
{
    double x = o->dpde ? q->xcoef * (ui + uj) / (ui * uj) : q->xcoef;
    if (x >= 0 && x < DPD_OU_XMAX && (!o->dpde || (ui > 0 && uj > 0))) {
        /* e^{-x} = 1 - x + x^2/2 - x^3/6 + x^4/24, h(x) = 1 - x/2 + 5x^2/24 - x^3/16
         * + 79x^4/5760 (+ O(x^5) < 1e-17), in Estrin's form (c0 + c1 x) + x^2
         * (c2 + c3 x + c4 x^2): three steps deep instead of Horner's four */
        double x2 = x * x;
        double decay = fma(x2, fma(x2, 1.0 / 24, fma(x, -1.0 / 6, 0.5)), fma(x, -1.0, 1.0));
        double h = fma(x2, fma(x2, 79.0 / 5760, fma(x, -1.0 / 16, 5.0 / 24)), fma(x, -0.5, 1.0));
        return fma(urel, decay, q->noise * h);
    }
    return dpd_ou_general(o, urel, q->wr, q->invmu, q->xi, ui, uj);
}

/* The pair's velocity change along e: +aa e on a, -ab e on b (aa, ab the
 * change of the relative velocity times each one's share of the reduced
 * mass), with the fused multiply-adds every sweep order uses, so that
 * sweeps that visit a pair in the same order give the same bits. */
static inline void dpd_ou_kick(double *va, double *vb, double aa, double ab, double ex, double ey,
                               double ez)
{
    va[0] = fma(aa, ex, va[0]);
    va[1] = fma(aa, ey, va[1]);
    va[2] = fma(aa, ez, va[2]);
    vb[0] = fma(-ab, ex, vb[0]);
    vb[1] = fma(-ab, ey, vb[1]);
    vb[2] = fma(-ab, ez, vb[2]);
}

#endif
