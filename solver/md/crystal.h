/*
 * crystal: zero-temperature properties of a perfect crystal under a
 * potential -- energy and stress under homogeneous strain, the equilibrium
 * lattice constant and cohesive energy, and the cubic elastic constants.
 *
 * Elastic constants come from the stress response to small strains
 * (central differences, strain 1e-5):
 *   C11 = d sigma_xx / d eps_xx,  C12 = d sigma_yy / d eps_xx  ([100] crystal)
 *   C'11 = (C11 + C12 + 2 C44) / 2 from a uniaxial strain along [110]
 *   (crystal oriented [110] [-110] [001]), so C44 = C'11 - (C11 + C12) / 2.
 * In fcc, bcc and sc every site is a centre of inversion, so a
 * homogeneous strain moves no site off its affine place.  Diamond's two
 * fcc sublattices are not: a shear eps_xy in the cube axes shifts the
 * second against the first along z (Kleinman 1962),
 *   u_B - u_A = -zeta (a/4) (gamma_yz, gamma_xz, gamma_xy),  gamma = 2 eps,
 * and the relaxed C44 (the shift free, as in MD) is well below the
 * unrelaxed one (sublattices held): SW Si 56.4 against about 110 GPa.
 * crystal_elastic_constants finds the shift by zeroing the mean force on
 * the second sublattice under the [110] strain and gives both C44 and
 * zeta.  Stress is the virial stress, sigma = -P.
 */
#ifndef CASCADE_CRYSTAL_H
#define CASCADE_CRYSTAL_H

#include "core/lattice.h"
#include "md/potential.h"
#include "util/err.h"

struct crystal_spec {
    enum lattice_style style;
    const char *element;
    double mass;            /* amu (0: standard) */
    long cells;             /* repeats of the cell along each axis (>= 1) */
};

/* Energy per atom (eV) and virial pressure tensor (eV/Å^3, xx yy zz xy xz
 * yz) of the crystal with lattice constant a, orientation `orient` (NULL =
 * cubic) and diagonal strain eps[3]. */
int crystal_energy(struct potential *pot, const struct crystal_spec *c, double a,
                   const int (*orient)[3], const double eps[3], double *e_atom, double P[6],
                   struct err *e);

/* Lattice constant minimising the energy in [a_lo, a_hi] (Brent, GSL) and
 * the cohesive energy -E/N there (eV/atom, positive for a bound crystal). */
int crystal_equilibrium(struct potential *pot, const struct crystal_spec *c, double a_lo,
                        double a_hi, double *a0, double *ecoh, struct err *e);

/* Cubic elastic constants at lattice constant a (eV/Å^3): C44 the
 * relaxed one (diamond: the sublattice shift free). */
struct crystal_elastic {
    double c11, c12, c44;   /* relaxed (eV/Å^3) */
    double c44_unrelaxed;   /* diamond: both sublattices affine; others = c44 */
    double zeta;            /* Kleinman's internal-strain parameter (diamond; else 0) */
    double optical_k;       /* eV/Å^2: force per atom of sublattice B per Å of shift (diamond) */
};
int crystal_elastic_constants(struct potential *pot, const struct crystal_spec *c, double a,
                              struct crystal_elastic *out, struct err *e);
int crystal_elastic_cubic(struct potential *pot, const struct crystal_spec *c, double a,
                          double *c11, double *c12, double *c44, struct err *e);

#endif
