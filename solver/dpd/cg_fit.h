/*
 * cg_fit: the MD->DPD hierarchical bridge -- fit the coarse-grained
 * Sutton-Chen parameters to a pressure-density isotherm measured by MD.
 *
 * Chen et al. 2014 (Sec. 2.2) fitted the DPD force to the 298 K
 * pressure-density relation of Sutton-Chen copper with a genetic algorithm;
 * here a nonlinear least-squares fit (GSL gsl_multifit_nlinear, trust-region
 * Levenberg-Marquardt with geodesic acceleration off, finite-difference
 * Jacobian) does it.  The model pressure of the coarse-grained fcc crystal at
 * mass density rho is the lattice sum of cg_lattice.h:
 *
 *   aL = (4 M / rho)^(1/3),   P(rho) = P_static(aL) + P_th(aL, T)
 *
 * with M the particle mass and P_th the classical quasi-harmonic (Einstein)
 * thermal pressure at the isotherm temperature.  Residuals are
 * (P_model - P_MD) / s_k with s_k the point's standard error when weights are
 * asked for, else 1 GPa.  Free parameters are fitted in logarithms, which
 * keeps them positive.  Parameters not fitted keep their start values.
 */
#ifndef CASCADE_CG_FIT_H
#define CASCADE_CG_FIT_H

#include "core/sc_form.h"
#include "util/err.h"

struct cg_fit_point {
    double density;    /* g/cm^3 */
    double pressure;   /* GPa */
    double sigma;      /* GPa: standard error (0: unknown) */
};

enum cg_fit_param { CG_FIT_EPS, CG_FIT_C, CG_FIT_N, CG_FIT_M, CG_FIT_A, CG_FIT_NPAR };
extern const char *const cg_fit_param_names[CG_FIT_NPAR + 1];   /* epsilon c n m a; NULL */

struct cg_fit_spec {
    struct sc_params start;      /* start values; the cutoff stays fixed (Å) */
    double mass;                 /* amu per particle */
    double temperature;          /* K */
    int thermal;                 /* include the thermal pressure in the model */
    int weighted;                /* weight residuals by 1 / sigma */
    int free[CG_FIT_NPAR];       /* 1: fitted */
    long max_iter;
};

struct cg_fit_result {
    struct sc_params sc;         /* fitted (sc_params_finish applied) */
    double rms;                  /* GPa: root-mean-square of P_model - P_MD */
    double max_abs;              /* GPa */
    double chi2;                 /* sum of squared (weighted) residuals */
    double stderr_par[CG_FIT_NPAR];   /* standard errors of the free parameters */
    long iterations;
    const char *stop;            /* why the iteration stopped */
};

/* Model pressure (GPa) of the coarse-grained crystal at a mass density. */
double cg_fit_model_pressure(const struct sc_params *sc, double mass, double T, int thermal,
                             double density);

/* Lattice constant (Å) of the fcc crystal of particles of `mass` amu at a
 * mass density in g/cm^3. */
double cg_fit_lattice_constant(double mass, double density);

int cg_fit_isotherm(const struct cg_fit_spec *spec, const struct cg_fit_point *pts, int npts,
                    struct cg_fit_result *res, struct err *e);

#endif
