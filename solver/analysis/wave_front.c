/* wave_front: front crossings at a fraction of the local peak, fitted. */
#include "analysis/wave_front.h"

#include <gsl/gsl_fit.h>
#include <math.h>
#include <stdlib.h>

const double wave_front_fractions[WAVE_FRONT_NFRAC] = {0.1, 0.2, 0.5, 0.8, 0.9};

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

/* Each probe's crossing time at fraction f (NAN where not reached). */
static void probe_times(const double *t, long nt, const double *sig, int np, const double *tmax,
                        double halfwidth, double f, double *tk)
{
    for (int k = 0; k < np; k++)
        tk[k] = wave_front_crossing(t, sig + k, nt, np, f, tmax ? tmax[k] : INFINITY, halfwidth,
                                    NULL);
}

int wave_front_fit_times(const double *times, int np, const double *x, struct wave_front_fit *fit)
{
    int m = 0;
    fit->speed = fit->stderr_ = fit->intercept = NAN;
    fit->nprobes = 0;
    double *tk = malloc((size_t)(np > 0 ? np : 1) * 2 * sizeof *tk);
    if (!tk)
        return -1;
    double *xk = tk + (np > 0 ? np : 1);
    for (int k = 0; k < np; k++) {
        if (!isfinite(times[k]))
            continue;
        tk[m] = times[k];
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

int wave_front_fit(const double *t, long nt, const double *sig, int np, const double *x,
                   const double *tmax, double halfwidth, double f, struct wave_front_fit *fit)
{
    double *tk = malloc((size_t)(np > 0 ? np : 1) * sizeof *tk);
    if (!tk) {
        fit->speed = fit->stderr_ = fit->intercept = NAN;
        fit->nprobes = 0;
        return -1;
    }
    probe_times(t, nt, sig, np, tmax, halfwidth, f, tk);
    int rc = wave_front_fit_times(tk, np, x, fit);
    free(tk);
    return rc;
}

double wave_front_centroid(const double *t, const double *s, long n, long stride, double tmax,
                           double halfwidth, int pulse)
{
    long jp = leading_peak(t, s, n, stride, tmax, halfwidth);
    if (jp < 0)
        return NAN;
    double num = 0, den = 0;
    if (!pulse) {
        /* the rise: t weighted by the increments of the running maximum
         * up to the peak, i.e. the mean over f in (0, 1) of the first
         * crossing of f times the peak (midpoint rule between samples) */
        double run = 0;
        for (long j = 0; j <= jp; j++) {
            double v = s[j * stride];
            if (!(v > run))
                continue;
            double tm = j > 0 ? 0.5 * (t[j - 1] + t[j]) : t[0];
            num += tm * (v - run);
            den += v - run;
            run = v;
        }
        return den > 0 ? num / den : NAN;
    }
    /* the pulse: t weighted by the signal, from the start of the window
     * until the signal falls back to zero after the peak (or the window
     * ends); its centroid moves with the energy of its dominant, longest
     * wavelengths */
    long m = 0;
    while (m < n && t[m] <= tmax)
        m++;
    for (long j = 0; j < m; j++) {
        double v = s[j * stride];
        if (j > jp && !(v > 0))
            break;
        if (!(v > 0))
            continue;
        double dt = 0.5 * ((j + 1 < m ? t[j + 1] : t[j]) - (j > 0 ? t[j - 1] : t[j]));
        num += t[j] * v * dt;
        den += v * dt;
    }
    return den > 0 ? num / den : NAN;
}

/* Index of fraction f in wave_front_fractions. */
static int frac_index(double f)
{
    for (int q = 0; q < WAVE_FRONT_NFRAC; q++)
        if (fabs(wave_front_fractions[q] - f) < 1e-12)
            return q;
    return -1;
}

void wave_front_measure(const double *t, long nt, const double *sig, int np, const double *x,
                        const double *tmax, double halfwidth, struct wave_front_result *r)
{
    size_t nk = (size_t)(np > 0 ? np : 1);
    double *tk = malloc(nk * (WAVE_FRONT_NFRAC + 1) * sizeof *tk);
    int ok = tk != NULL;
    for (int q = 0; q < WAVE_FRONT_NFRAC; q++) {
        if (!tk) {
            r->fit[q].speed = r->fit[q].stderr_ = r->fit[q].intercept = NAN;
            r->fit[q].nprobes = 0;
            continue;
        }
        probe_times(t, nt, sig, np, tmax, halfwidth, wave_front_fractions[q], tk + q * nk);
        if (wave_front_fit_times(tk + q * nk, np, x, &r->fit[q]))
            ok = 0;
    }
    /* the rise's centres: f = 0.5 and the midpoints of the pairs
     * symmetric about it (0.2, 0.8) and (0.1, 0.9).  A rise that only
     * broadens symmetrically moves none of them; a rise that changes shape
     * (a precursor growing ahead of the main front) moves them apart. */
    static const double pair[WAVE_FRONT_NCENTRE] = {0.5, 0.2, 0.1};
    double lo = INFINITY, hi = -INFINITY, *mid = tk ? tk + WAVE_FRONT_NFRAC * nk : NULL;
    for (int c = 0; c < WAVE_FRONT_NCENTRE; c++) {
        struct wave_front_fit *fc = &r->centre[c];
        fc->speed = fc->stderr_ = fc->intercept = NAN;
        fc->nprobes = 0;
        int a = frac_index(pair[c]), b = frac_index(1 - pair[c]);
        if (!mid || a < 0 || b < 0)
            continue;
        for (int k = 0; k < np; k++)
            mid[k] = 0.5 * (tk[a * nk + k] + tk[b * nk + k]);
        if (wave_front_fit_times(mid, np, x, fc)) {
            ok = 0;
            continue;
        }
        lo = fmin(lo, fc->speed);
        hi = fmax(hi, fc->speed);
    }
    /* the broadening: the 10-90 % rise time against the distance */
    r->rise_time = r->broadening = r->broadening_stderr = NAN;
    int a = frac_index(0.1), b = frac_index(0.9);
    if (mid && a >= 0 && b >= 0) {
        double *xs = malloc(nk * 2 * sizeof *xs);
        int m = 0;
        for (int k = 0; xs && k < np; k++) {
            double d = tk[b * nk + k] - tk[a * nk + k];
            if (!isfinite(d))
                continue;
            xs[m] = x[k];
            xs[nk + (size_t)m++] = d;
        }
        if (m >= 3) {
            double c0, c1, cov00, cov01, cov11, sumsq, xm = 0;
            gsl_fit_linear(xs, 1, xs + nk, 1, (size_t)m, &c0, &c1, &cov00, &cov01, &cov11,
                           &sumsq);
            for (int k = 0; k < m; k++)
                xm += xs[k] / m;
            r->broadening = c1;
            r->broadening_stderr = sqrt(cov11);
            r->rise_time = c0 + c1 * xm;
        }
        free(xs);
    }
    /* the threshold-free centroids */
    struct wave_front_fit *cen[2] = {&r->rise_centroid, &r->pulse_centroid};
    for (int w = 0; w < 2; w++) {
        cen[w]->speed = cen[w]->stderr_ = cen[w]->intercept = NAN;
        cen[w]->nprobes = 0;
        if (!mid)
            continue;
        for (int k = 0; k < np; k++)
            mid[k] = wave_front_centroid(t, sig + k, nt, np, tmax ? tmax[k] : INFINITY,
                                         halfwidth, w);
        wave_front_fit_times(mid, np, x, cen[w]);
    }
    free(tk);
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
