/*
 * eos: shock and isotherm relations for the Hugoniot and P-V cases.
 *
 * Rankine-Hugoniot jump conditions for a steady shock of speed Us running
 * into material at rest (density rho0, pressure P0), with particle
 * velocity up behind it:
 *   mass      rho / rho0 = Us / (Us - up)
 *   momentum  P - P0 = rho0 Us up
 *   energy    E - E0 = (P + P0) / 2 (1/rho0 - 1/rho)      (per unit mass)
 * The experimental Hugoniot of many metals is a line Us = c0 + s up
 * (copper: c0 = 3.94 km/s, s = 1.49; Mitchell & Nellis, J. Appl. Phys.
 * 52, 3363 (1981)).
 *
 * Vinet isotherm: P = 3 B0 (1 - x) / x^2 exp(eta (1 - x)), x = (V/V0)^(1/3),
 * eta = 3/2 (B0' - 1) (Vinet et al., J. Geophys. Res. 92, 9319 (1987)).
 * Taking logs, ln[P x^2 / (3 (1 - x))] = ln B0 + eta (1 - x) is linear, so
 * B0 and B0' come from a straight-line fit.
 *
 * Units: metal (amu/Å^3, Å/ps, eV/Å^3) unless stated.
 */
#ifndef CASCADE_EOS_H
#define CASCADE_EOS_H

#include "util/err.h"

/* P - P0 (eV/Å^3) from rho0 (amu/Å^3), Us and up (Å/ps). */
double eos_rh_pressure(double rho0, double us, double up);
/* rho / rho0 from the mass condition. */
double eos_rh_compression(double us, double up);

/* Least-squares Us = c0 + s up over the points with lo <= up <= hi; the
 * standard errors of c0 and s from the residuals.  Needs 2 points (errors
 * need 3; with 2 they are reported as 0). */
int eos_fit_us_up(const double *up, const double *us, int n, double lo, double hi, double *c0,
                  double *s, double *c0_err, double *s_err, int *used, struct err *e);

/* Vinet fit of P(V/V0) (P in any unit; B0 comes out in the same unit),
 * using the points with V/V0 < 1 and P > 0. */
int eos_fit_vinet(const double *v_ratio, const double *p, int n, double *b0, double *b0p,
                  struct err *e);
double eos_vinet_pressure(double v_ratio, double b0, double b0p);

#endif
