/* wave_front: front crossings at a fraction of the local peak, fitted. */
#include "analysis/wave_front.h"

#include <gsl/gsl_fit.h>
#include <math.h>
#include <stdlib.h>

const double wave_front_fractions[WAVE_FRONT_NFRAC] = {0.1, 0.2, 0.5};

/* The leading pulse's peak: the first sample above the floor that is the
 * largest within +-halfwidth (in the window); without one (a monotone
 * rise) the window's largest value.  Returns its index, -1 if none. */
static long leading_peak(const double *t, const double *s, long n, long stride, double tmax,
                         double halfwidth)
{
    long m = 0, jmax = -1;
    for (; m < n && t[m] <= tmax; m++)
        if (isfinite(s[m * stride]) && (jmax < 0 || s[m * stride] > s[jmax * stride]))
            jmax = m;
    if (jmax < 0 || !(s[jmax * stride] > 0))
        return -1;
    double floor_ = WAVE_FRONT_PEAK_FLOOR * s[jmax * stride];
    if (!(halfwidth > 0))
        return jmax;
    long lo = 0, hi = 0;
    for (long j = 0; j < m; j++) {
        double v = s[j * stride];
        if (!(v > floor_))
            continue;
        while (t[lo] < t[j] - halfwidth)
            lo++;
        if (hi < j)
            hi = j;
        while (hi + 1 < m && t[hi + 1] <= t[j] + halfwidth)
            hi++;
        if (t[j] + halfwidth > t[m - 1])
            break;   /* its neighbourhood leaves the window: not known to be a peak */
        int is_max = 1;
        for (long q = lo; q <= hi && is_max; q++)
            if (isfinite(s[q * stride]) && s[q * stride] > v)
                is_max = 0;
        if (is_max)
            return j;
    }
    return jmax;
}

double wave_front_crossing(const double *t, const double *s, long n, long stride, double f,
                           double tmax, double halfwidth, double *peak)
{
    long jp = leading_peak(t, s, n, stride, tmax, halfwidth);
    double pk = jp >= 0 ? s[jp * stride] : NAN;
    if (peak)
        *peak = pk;
    if (jp < 0 || !(f > 0))
        return NAN;
    double lv = f * pk;
    for (long j = 0; j <= jp; j++) {
        double v = s[j * stride];
        if (!(v >= lv))
            continue;
        if (j == 0)
            return t[0];
        double prev = s[(j - 1) * stride];
        if (!isfinite(prev) || v == prev)
            return t[j];
        return t[j - 1] + (lv - prev) / (v - prev) * (t[j] - t[j - 1]);
    }
    return NAN;
}

int wave_front_fit(const double *t, long nt, const double *sig, int np, const double *x,
                   const double *tmax, double halfwidth, double f, struct wave_front_fit *fit)
{
    int m = 0;
    fit->speed = fit->stderr_ = fit->intercept = NAN;
    fit->nprobes = 0;
    double *tk = malloc((size_t)(np > 0 ? np : 1) * 2 * sizeof *tk);
    if (!tk)
        return -1;
    double *xk = tk + (np > 0 ? np : 1);
    for (int k = 0; k < np; k++) {
        double tc = wave_front_crossing(t, sig + k, nt, np, f, tmax ? tmax[k] : INFINITY,
                                        halfwidth, NULL);
        if (!isfinite(tc))
            continue;
        tk[m] = tc;
        xk[m++] = x[k];
    }
    fit->nprobes = m;
    int rc = m < 3 ? -1 : 0;
    double tmin = rc ? 0 : tk[0], tmx = tmin;
    for (int k = 1; k < m; k++) {
        tmin = fmin(tmin, tk[k]);
        tmx = fmax(tmx, tk[k]);
    }
    if (!rc && !(tmx > tmin))
        rc = -1;
    if (!rc) {
        double c0, c1, cov00, cov01, cov11, sumsq;
        gsl_fit_linear(tk, 1, xk, 1, (size_t)m, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
        /* gsl scales the covariance of an unweighted fit by the residual
         * variance sumsq / (m - 2): sqrt(cov11) is the slope's standard error */
        fit->speed = c1;
        fit->stderr_ = sqrt(cov11);
        fit->intercept = c0;
    }
    free(tk);
    return rc;
}

void wave_front_measure(const double *t, long nt, const double *sig, int np, const double *x,
                        const double *tmax, double halfwidth, struct wave_front_result *r)
{
    int ok = 1;
    double lo = INFINITY, hi = -INFINITY;
    for (int q = 0; q < WAVE_FRONT_NFRAC; q++) {
        if (wave_front_fit(t, nt, sig, np, x, tmax, halfwidth, wave_front_fractions[q],
                           &r->fit[q])) {
            ok = 0;
            continue;
        }
        lo = fmin(lo, r->fit[q].speed);
        hi = fmax(hi, r->fit[q].speed);
    }
    const struct wave_front_fit *p = &r->fit[WAVE_FRONT_PRIMARY];
    r->speed_fit = p->speed;
    r->stderr_ = p->stderr_;
    r->spread = ok && p->speed != 0 ? (hi - lo) / fabs(p->speed) : NAN;
    if (!ok)
        r->flag = WAVE_FRONT_NO_FIT;
    else if (!(r->spread <= WAVE_FRONT_SPREAD_MAX))
        r->flag = WAVE_FRONT_SPREAD;
    else
        r->flag = WAVE_FRONT_OK;
    r->speed = r->flag == WAVE_FRONT_OK ? p->speed : NAN;
}

double wave_front_arrival_speed(const double *t, long n, const double *s1, double tmax1,
                                const double *s2, double tmax2, double halfwidth, double distance,
                                double f, double *t1, double *t2)
{
    double a = wave_front_crossing(t, s1, n, 1, f, tmax1, halfwidth, NULL);
    double b = wave_front_crossing(t, s2, n, 1, f, tmax2, halfwidth, NULL);
    if (t1)
        *t1 = a;
    if (t2)
        *t2 = b;
    if (!isfinite(a) || !isfinite(b) || !(b > a))
        return NAN;
    return distance / (b - a);
}
