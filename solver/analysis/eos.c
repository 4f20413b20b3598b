/* eos: Rankine-Hugoniot relations, Us-up and Vinet fits (GSL). */
#include "analysis/eos.h"

#include <gsl/gsl_fit.h>
#include <math.h>
#include <stdlib.h>

#include "core/units.h"

double eos_rh_pressure(double rho0, double us, double up)
{
    return rho0 * us * up * UNITS_MVV2E;   /* amu/Å^3 (Å/ps)^2 -> eV/Å^3 */
}

double eos_rh_compression(double us, double up) { return us / (us - up); }

static int fit_line(const double *x, const double *y, int n, double *a, double *b, double *a_err,
                    double *b_err)
{
    double c0, c1, cov00, cov01, cov11, sumsq;
    gsl_fit_linear(x, 1, y, 1, (size_t)n, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
    *a = c0;
    *b = c1;
    /* the unweighted fit's covariance already carries the residual variance
     * sumsq / (n - 2); two points fit exactly */
    (void)sumsq;
    (void)cov01;
    *a_err = n > 2 ? sqrt(cov00) : 0.0;
    *b_err = n > 2 ? sqrt(cov11) : 0.0;
    return 0;
}

int eos_fit_us_up(const double *up, const double *us, int n, double lo, double hi, double *c0,
                  double *s, double *c0_err, double *s_err, int *used, struct err *e)
{
    double *x = malloc((size_t)(n + 1) * sizeof *x), *y = malloc((size_t)(n + 1) * sizeof *y);
    if (!x || !y) {
        free(x); free(y);
        return err_nomem(e, "Hugoniot fit");
    }
    int m = 0;
    for (int k = 0; k < n; k++)
        if (up[k] >= lo && up[k] <= hi && isfinite(us[k])) {
            x[m] = up[k];
            y[m] = us[k];
            m++;
        }
    *used = m;
    int rc = 0;
    if (m < 2)
        rc = err_set(e, ERR_RUNTIME, "Hugoniot fit: %d points with %g <= up <= %g, 2 needed", m, lo, hi);
    else
        fit_line(x, y, m, c0, s, c0_err, s_err);
    free(x);
    free(y);
    return rc;
}

int eos_fit_vinet(const double *v_ratio, const double *p, int n, double *b0, double *b0p,
                  struct err *e)
{
    double *x = malloc((size_t)(n + 1) * sizeof *x), *y = malloc((size_t)(n + 1) * sizeof *y);
    if (!x || !y) {
        free(x); free(y);
        return err_nomem(e, "Vinet fit");
    }
    int m = 0;
    for (int k = 0; k < n; k++) {
        double xx = cbrt(v_ratio[k]);
        if (v_ratio[k] < 1.0 - 1e-6 && p[k] > 0) {
            x[m] = 1.0 - xx;
            y[m] = log(p[k] * xx * xx / (3.0 * (1.0 - xx)));
            m++;
        }
    }
    int rc = 0;
    if (m < 2) {
        rc = err_set(e, ERR_RUNTIME, "Vinet fit: %d compressed points with positive pressure, 2 "
                                     "needed", m);
    } else {
        double a, b, ae, be;
        fit_line(x, y, m, &a, &b, &ae, &be);
        *b0 = exp(a);
        *b0p = 1.0 + 2.0 * b / 3.0;
    }
    free(x);
    free(y);
    return rc;
}

double eos_vinet_pressure(double v_ratio, double b0, double b0p)
{
    double x = cbrt(v_ratio), eta = 1.5 * (b0p - 1.0);
    return 3.0 * b0 * (1.0 - x) / (x * x) * exp(eta * (1.0 - x));
}
