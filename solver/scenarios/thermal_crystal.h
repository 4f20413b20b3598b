/*
 * thermal_crystal: periodic crystals at a temperature -- built, thermalised
 * with a Langevin bath, their pressure tensor averaged, and the lattice
 * constant at which the mean pressure vanishes at that temperature (the
 * reference state of the Hugoniot and of the isotherm).
 *
 * The zero-pressure search is Newton's method with a frozen slope: two
 * short runs at a and 1.003 a give dP/da, then a <- a - P / (dP/da) until
 * |P| < tol or 6 runs.  Every run thermalises from Maxwell-Boltzmann
 * velocities at 2T (equipartition) under Langevin at T for t_eq and
 * averages over t_avg.
 */
#ifndef CASCADE_THERMAL_CRYSTAL_H
#define CASCADE_THERMAL_CRYSTAL_H

#include <stdint.h>

#include "core/lattice.h"
#include "md/md.h"

struct thermal_spec {
    enum lattice_style style;
    const char *element;
    long cells[3];
    double temperature;     /* K */
    double dt, skin;        /* ps, Å */
    double tau;             /* ps: Langevin damping time */
    double t_eq, t_avg;     /* ps */
    uint64_t seed;
    int nthreads;
};

/* A periodic crystal of lattice constant a (edges scaled by scale[3], NULL
 * = 1) with velocities at 2T and a Langevin bath at T; the md borrows pot
 * (detach it with md->pot = NULL before md_free). */
int thermal_crystal_md(struct md *md, struct potential *pot, const struct thermal_spec *s, double a,
                       const double *scale, struct err *e);

/* Run `t_run` ps (thermostat as set), averaging the pressure tensor
 * (eV/Å^3) and the temperature over the last t_avg ps. */
int thermal_average(struct md *md, double t_run, double t_avg, double P[6], double *T,
                    struct err *e);

/* Lattice constant of zero mean pressure at s->temperature, from a_guess;
 * *p_left is the mean pressure left at the answer (eV/Å^3). */
int thermal_lattice_constant(struct potential *pot, const struct thermal_spec *s, double a_guess,
                             double tol, double *a_T, double *p_left, struct err *e);

#endif
