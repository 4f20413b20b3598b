/*
 * The MD->DPD bridge (solver/dpd/cg_lattice, cg_fit): lattice sums of the
 * coarse-grained Sutton-Chen crystal against the atomistic potential they
 * scale from, elastic constants against the pressure they must agree with,
 * and the GSL fit recovering known parameters from a synthetic isotherm.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "dpd/cg_fit.h"
#include "dpd/cg_lattice.h"

static struct sc_params params(double eps, double c, double n, double m, double a, double rc)
{
    struct sc_params s = {eps, c, a, n, m, rc, 0, 0, 0, 0, 0, 0};
    sc_params_finish(&s);
    return s;
}

/* Sutton-Chen is scale-covariant: lengths x2 and eps x8 give the same
 * energy per particle x8 at twice the lattice constant and the same
 * pressure.  Checked against the atomistic values of test_crystal (a0 =
 * 3.6099 Å, Ec = 3.4514 eV with the 3a cutoff). */
Test(cg_lattice, scaling_and_atomistic_reference)
{
    struct sc_params at = params(1.2382e-2, 39.432, 9, 6, 3.61, 10.83);
    struct sc_params cg = params(8 * 1.2382e-2, 39.432, 9, 6, 7.22, 21.66);
    double a0;
    cr_assert_eq(cg_lattice_solve_pressure(&at, 0, 0, 0, 3.4, 3.8, &a0), 0);
    double e_at, P_at, e_cg, P_cg;
    cg_lattice_static(&at, a0, &e_at, &P_at);
    cr_assert_lt(fabs(a0 - 3.6099), 5e-4, "a0 = %.5f Å", a0);
    cr_assert_lt(fabs(-e_at - 3.4514), 5e-4, "Ec = %.5f eV", -e_at);
    cg_lattice_static(&at, 0.97 * a0, &e_at, &P_at);
    cg_lattice_static(&cg, 2 * 0.97 * a0, &e_cg, &P_cg);
    cr_assert_lt(fabs(e_cg - 8 * e_at), 1e-10 * fabs(e_cg), "%.12g vs 8 x %.12g", e_cg, e_at);
    cr_assert_lt(fabs(P_cg - P_at), 1e-10 * fabs(P_at), "%.12g vs %.12g", P_cg, P_at);
}

/* Elastic constants from strain energies agree with the pressure:
 * dP/dlnV = -B and B = (C11 + 2 C12) / 3 at zero pressure; the thermal
 * pressure of an expanded lattice is positive and of the classical size
 * 3 n kB T gamma with gamma between 1 and 4. */
Test(cg_lattice, elastic_constants_and_thermal_pressure)
{
    struct sc_params cg = params(0.1, 39.0, 9, 6, 7.23, 10.845);
    double a0;
    cr_assert_eq(cg_lattice_solve_pressure(&cg, 0, 0, 0, 6.5, 8.0, &a0), 0);
    double c11, c12, c44;
    cg_lattice_elastic(&cg, a0, &c11, &c12, &c44);
    double h = 1e-5 * a0, Pp, Pm;
    cg_lattice_static(&cg, a0 + h, NULL, &Pp);
    cg_lattice_static(&cg, a0 - h, NULL, &Pm);
    double B = -a0 / 3.0 * (Pp - Pm) / (2 * h);
    cr_assert_lt(fabs(B / ((c11 + 2 * c12) / 3) - 1), 1e-4, "B = %g vs (C11 + 2 C12)/3 = %g", B,
                 (c11 + 2 * c12) / 3);
    cr_assert(c11 > c12 && c44 > 0, "cubic stability: C11 %g C12 %g C44 %g", c11, c12, c44);
    double Pth = cg_lattice_thermal_pressure(&cg, a0, 298);
    double nkT = 4.0 / (a0 * a0 * a0) * UNITS_KB * 298;
    cr_assert(Pth > 3 * nkT * 1.0 && Pth < 3 * nkT * 4.0, "P_th = %g, 3 n kB T = %g", Pth,
              3 * nkT);
}

/* A synthetic 298 K isotherm from known parameters, fitted from a start
 * 15 % off: the parameters come back to 1e-6 and the residual vanishes. */
static void recover(int fit_n)
{
    struct sc_params truth = params(0.105, 38.0, 9.5, 6, 7.23, 10.845);
    const double M = 8 * 63.546, T = 298;
    struct cg_fit_point pts[9];
    for (int i = 0; i < 9; i++) {
        double aL = 7.23 * (0.94 + 0.0125 * i);
        double rho = 4 * M / (aL * aL * aL) * UNITS_AMU_A3_TO_KG_M3 / 1000;
        pts[i] = (struct cg_fit_point){rho, cg_fit_model_pressure(&truth, M, T, 1, rho), 0};
    }
    struct cg_fit_spec spec = {params(0.09, 43.0, fit_n ? 10.5 : 9.5, 6, 7.23, 10.845),
                               M, T, 1, 0, {1, 1, fit_n, 0, 0}, 500};
    struct cg_fit_result res;
    struct err e = {0};
    cr_assert_eq(cg_fit_isotherm(&spec, pts, 9, &res, &e), 0, "%s", e.msg);
    cr_assert_lt(fabs(res.sc.eps / truth.eps - 1), 1e-6, "eps %.9g vs %.9g", res.sc.eps, truth.eps);
    cr_assert_lt(fabs(res.sc.c / truth.c - 1), 1e-6, "c %.9g vs %.9g", res.sc.c, truth.c);
    cr_assert_lt(fabs(res.sc.n / truth.n - 1), 1e-6, "n %.9g vs %.9g", res.sc.n, truth.n);
    cr_assert_lt(res.rms, 1e-6, "rms residual %g GPa", res.rms);
}

Test(cg_fit, recovers_epsilon_and_c) { recover(0); }
Test(cg_fit, recovers_epsilon_c_and_n) { recover(1); }

/* Too few points or a degenerate choice is refused. */
Test(cg_fit, refuses_underdetermined_fits)
{
    struct cg_fit_point pts[1] = {{9.0, 1.0, 0}};
    struct cg_fit_spec spec = {params(0.1, 39, 9, 6, 7.23, 10.845), 508.368, 298, 1, 0,
                               {1, 1, 0, 0, 0}, 100};
    struct cg_fit_result res;
    struct err e = {0};
    cr_assert_eq(cg_fit_isotherm(&spec, pts, 1, &res, &e), ERR_INPUT);
    cr_assert(strstr(e.msg, "1 isotherm points cannot determine 2 parameters"), "%s", e.msg);
}
