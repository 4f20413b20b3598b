/*
 * crystal_thermal: the stress of a perfect periodic crystal at a
 * temperature, as a time series from Langevin MD -- the raw material of
 * finite-temperature lattice constants and elastic constants by finite
 * strain averages (type: elastic).  The 0 K counterparts are in crystal.h.
 */
#ifndef CASCADE_CRYSTAL_THERMAL_H
#define CASCADE_CRYSTAL_THERMAL_H

#include <stdint.h>

#include "md/crystal.h"

struct crystal_md {
    double temperature;    /* K */
    double dt;             /* ps */
    double tau;            /* ps: Langevin damping time */
    long equilibrate;      /* steps before sampling */
    long sample;           /* steps sampled */
    long sample_every;     /* steps between samples */
    uint64_t seed;
    int nthreads;
};

/* Run the crystal of lattice constant a (orientation `orient`, NULL =
 * cubic) under the diagonal strain eps (box and sites scaled by 1 + eps)
 * at run->temperature, and store the virial pressure tensor (eV/Å^3, xx yy
 * zz xy xz yz, kinetic part included) every sample_every steps of the
 * sampling stage into P (room for sample / sample_every + 1 tensors); *n
 * gets the count. */
int crystal_pressure_md(struct potential *pot, const struct crystal_spec *c, double a,
                        const int (*orient)[3], const double eps[3], const struct crystal_md *run,
                        double *P, long *n, struct err *e);

#endif
