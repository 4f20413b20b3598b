/*
 * cg_lattice: the perfect fcc crystal of the coarse-grained Sutton-Chen form
 * by direct lattice sums -- what the MD->DPD fit needs to predict the
 * pressure of the DPD material at a density without running it.
 *
 *   static energy and pressure       e(aL) per particle, P = -de/dOmega,
 *                                    Omega = aL^3 / 4
 *   Einstein force constant          k = (1/3) tr d^2E/du^2 for one particle
 *                                    displaced in the otherwise perfect
 *                                    crystal (its own and its neighbours'
 *                                    densities change), omega_E = sqrt(k/M)
 *   quasi-harmonic thermal pressure  classical Einstein crystal:
 *                                    F_th = 3 N kB T ln(hbar omega_E / kB T),
 *                                    P_th = -dF_th/dV = 3 n kB T gamma_E with
 *                                    gamma_E = -d ln omega_E / d ln V
 *   static elastic constants         C11, C12, C44 from second derivatives of
 *                                    the energy under homogeneous strain (a
 *                                    Bravais lattice: no internal relaxation)
 *
 * Units: Å, eV, eV/Å^3.  The model isotherm P(aL, T) = P_static + P_th is
 * an approximation of the DPD material's pressure (the Einstein spectrum
 * stands in for the full phonon spectrum); the `dpd` case type measures the
 * real one for comparison.
 */
#ifndef CASCADE_CG_LATTICE_H
#define CASCADE_CG_LATTICE_H

#include "core/sc_form.h"

/* Energy per particle (eV) of the fcc crystal of lattice constant aL under
 * the homogeneous deformation gradient F (row-major 3x3; NULL = identity). */
double cg_lattice_energy(const struct sc_params *sc, double aL, const double *F);

/* Static pressure (eV/Å^3) and energy per particle (eV) of the undeformed
 * crystal; either output may be NULL. */
void cg_lattice_static(const struct sc_params *sc, double aL, double *e, double *P);

/* Einstein force constant (eV/Å^2). */
double cg_lattice_einstein_k(const struct sc_params *sc, double aL);

/* Thermal pressure (eV/Å^3) of the classical quasi-harmonic Einstein crystal. */
double cg_lattice_thermal_pressure(const struct sc_params *sc, double aL, double T);

/* Model pressure P_static + (thermal ? P_th : 0), eV/Å^3. */
double cg_lattice_pressure(const struct sc_params *sc, double aL, double T, int thermal);

/* Lattice constant in [lo, hi] where the model pressure equals P0 (eV/Å^3);
 * returns 0, or -1 when P - P0 does not change sign on the interval. */
int cg_lattice_solve_pressure(const struct sc_params *sc, double T, int thermal, double P0,
                              double lo, double hi, double *aL);

/* Static cubic elastic constants at aL (eV/Å^3). */
void cg_lattice_elastic(const struct sc_params *sc, double aL, double *c11, double *c12,
                        double *c44);

#endif
