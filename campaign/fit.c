/* fit: straight-line and power-law least squares (see fit.h), on GSL's
 * gsl_fit_linear. */
#include "fit.h"

#include <gsl/gsl_fit.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "util/mem.h"

/* Ordinary least squares on (u, v): v = c0 + c1 u.  gsl_fit_linear gives
 * the coefficients, the residual sum of squares and the covariance with
 * s^2 = SSR / (n - 2): var(c1) = s^2 / Suu, var(c0) = s^2 (1/n + mean(u)^2 /
 * Suu).  With two points there is no residual degree of freedom, so no
 * standard error (NaN); all u equal is no line at all. */
static int line(const double *u, const double *v, int n, double *c0, double *c1, double *s0,
                double *s1, double *r2)
{
    int spread = 0;
    for (int i = 1; i < n && !spread; i++)
        spread = u[i] != u[0];
    if (!spread)
        return -1;
    double cov00, cov01, cov11, ssr;
    if (gsl_fit_linear(u, 1, v, 1, (size_t)n, c0, c1, &cov00, &cov01, &cov11, &ssr) != 0 ||
        !isfinite(*c0) || !isfinite(*c1))
        return -1;
    double svv = gsl_stats_tss(v, 1, (size_t)n);
    *r2 = svv > 0 ? 1 - ssr / svv : 1.0;
    if (n > 2) {
        *s0 = sqrt(cov00);
        *s1 = sqrt(cov11);
    } else {
        *s0 = *s1 = NAN;
    }
    return 0;
}

int fit_points(enum fit_model model, const double *x, const double *y, int n,
               struct fit_result *f)
{
    f->model = model;
    f->n = 0;
    f->p0 = f->p1 = f->s0 = f->s1 = f->r2 = f->rms = NAN;
    double *u = mem_alloc((size_t)(n > 0 ? n : 1) * 2 * sizeof *u);
    if (!u)
        return -1;
    double *v = u + (n > 0 ? n : 1);
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(y[i]))
            continue;
        if (model == FIT_POWER) {
            if (!(x[i] > 0) || !(y[i] > 0))
                continue;
            u[m] = log(x[i]);
            v[m] = log(y[i]);
        } else {
            u[m] = x[i];
            v[m] = y[i];
        }
        m++;
    }
    double c0, c1, s0, s1, r2;
    int rc = m >= 2 ? line(u, v, m, &c0, &c1, &s0, &s1, &r2) : -1;
    free(u);
    if (rc)
        return -1;
    f->n = m;
    f->r2 = r2;
    if (model == FIT_POWER) {
        f->p0 = exp(c0);
        f->s0 = f->p0 * s0;   /* first-order propagation of the error of ln A */
        f->p1 = c1;
        f->s1 = s1;
    } else {
        f->p0 = c0;
        f->p1 = c1;
        f->s0 = s0;
        f->s1 = s1;
    }
    /* residuals in y itself (for a power law, not in log y) */
    double sum = 0;
    int k = 0;
    for (int i = 0; i < n; i++) {
        double fy = fit_eval(f, x[i]);
        if (isfinite(fy) && isfinite(y[i])) {
            sum += (y[i] - fy) * (y[i] - fy);
            k++;
        }
    }
    f->rms = k ? sqrt(sum / k) : NAN;
    return 0;
}

double fit_eval(const struct fit_result *f, double x)
{
    if (f->model == FIT_POWER)
        return x > 0 ? f->p0 * pow(x, f->p1) : NAN;
    return f->p0 + f->p1 * x;
}

void fit_expr(const struct fit_result *f, char *out, size_t len)
{
    if (f->model == FIT_POWER)
        snprintf(out, len, "%.10g*x**(%.10g)", f->p0, f->p1);
    else
        snprintf(out, len, "%.10g + (%.10g)*x", f->p0, f->p1);
}
