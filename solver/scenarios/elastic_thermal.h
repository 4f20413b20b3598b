/*
 * elastic_thermal: the lattice constant a(T) and the isothermal cubic
 * elastic constants at a temperature from MD finite-strain averages -- the
 * computation of `type: elastic` (elastic_case.c), shared with the cases
 * that need the constants at their temperature and compute them themselves
 * (handshake_thermal with `thermal.from_potential`, cluster_impact with
 * `target.handshake.thermal.from_potential`: impact_from_potential.h).
 *
 * 1. The 0 K lattice constant a0 and constants (crystal.h).
 * 2. The lattice constant at T: a <- a (1 + P / (3 B)) from the mean
 *    pressure of an NVT run, `iterations` times, B the 0 K bulk modulus
 *    (the thermal pressure is removed to the statistical error).
 * 3. At that a, NVT runs under uniaxial strains +-eps along [100] give
 *    C11 = -dP_xx/deps and C12 = -dP_yy/deps, and along [110] (crystal
 *    oriented [110] [-110] [001]) C'11 = (C11 + C12 + 2 C44) / 2, so
 *    C44 = C'11 - (C11 + C12) / 2 -- central differences of time averages,
 *    the same construction as at 0 K.  The errors are standard errors
 *    carried through the differences: with repeats >= 2 from the spread of
 *    the independent runs, else block-averaged within the one run (which
 *    underestimates them: the slow acoustic modes of a small periodic
 *    crystal outlast the blocks).  These are the isothermal constants of
 *    the crystal at its zero-pressure volume at T; diamond's C44 is the
 *    relaxed one (the MD atoms relax their sublattices freely).
 */
#ifndef CASCADE_ELASTIC_THERMAL_H
#define CASCADE_ELASTIC_THERMAL_H

#include "output/run.h"
#include "scenarios/crystal_thermal.h"
#include "util/cfg.h"

struct elastic_thermal_settings {
    struct crystal_md md;   /* temperature, time step, bath, run lengths, seed, threads */
    double strain;          /* amplitude of the +- strains */
    long iterations;        /* runs that correct a(T) */
    long repeats;           /* independent runs (other velocities) per strain */
};

struct elastic_thermal {
    double a0, c0[3];       /* Å, eV/Å^3: at 0 K */
    double a;               /* Å: a(T) */
    double p_mean, p_err;   /* eV/Å^3: the mean pressure of the last a(T) iteration */
    double c[3], c_err[3];  /* eV/Å^3: C11, C12, C44 at T and their standard errors */
};

/* Read the keys of a `type: elastic` section from o: temperature (when
 * with_temperature; else s->md.temperature is the caller's), strain,
 * timestep, tau, equilibrate, sample, lattice_iterations, repeats.  The
 * seed and the threads are the caller's to set.  Does not close o. */
int elastic_thermal_read(struct cfg_obj *o, int with_temperature,
                         struct elastic_thermal_settings *s);

/* Steps of MD the computation runs (every run: equilibrate + sample). */
long elastic_thermal_steps(const struct elastic_thermal_settings *s);

/* The computation above for the crystal `spec` of potential pot (its 0 K
 * minimum searched in [a_min, a_max]); logs each a(T) iteration to run
 * (NULL: silent).  The potential stays the caller's. */
int elastic_thermal_compute(struct potential *pot, const struct crystal_spec *spec, double a_min,
                            double a_max, const struct elastic_thermal_settings *s,
                            struct run *run, struct elastic_thermal *out, struct err *e);

/* The same for a case that needs the values at its temperature (`who`
 * names it in the log): logs what it is about to run and what it found. */
int elastic_thermal_compute_logged(const char *who, struct potential *pot,
                                   const struct crystal_spec *spec, double a_min, double a_max,
                                   const struct elastic_thermal_settings *s, struct run *run,
                                   struct elastic_thermal *out, struct err *e);

/* What such a computation gave, into a case's result: thermal_expansion
 * (a(T) / a0 - 1), c11_T_err, c12_T_err, c44_T_err (GPa) and
 * from_potential_md_steps (the values used are the case's own metrics). */
void elastic_thermal_report(const struct elastic_thermal *out,
                            const struct elastic_thermal_settings *s, struct result *r);

#endif
