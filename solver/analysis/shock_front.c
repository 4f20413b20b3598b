/* shock_front: slab profiles, front location, front speed. */
#include "analysis/shock_front.h"

#include <gsl/gsl_fit.h>
#include <math.h>
#include <string.h>

void shock_profile(const double *s, int stride, const double *val, int vstride, int n, double lo,
                   double w, int nbins, double *mean, long *count)
{
    memset(mean, 0, (size_t)nbins * sizeof *mean);
    memset(count, 0, (size_t)nbins * sizeof *count);
    for (int i = 0; i < n; i++) {
        double k = floor((s[(long)stride * i] - lo) / w);
        if (k < 0 || k >= nbins)
            continue;
        mean[(int)k] += val[(long)vstride * i];
        count[(int)k]++;
    }
    for (int k = 0; k < nbins; k++)
        if (count[k] > 0)
            mean[k] /= count[k];
}

int shock_front_locate(const double *mean, const long *count, int nbins, double lo, double w,
                       double level, int dir, long min_count, double *pos)
{
    int start = dir > 0 ? nbins - 1 : 0, step = dir > 0 ? -1 : 1;
    int prev = -1;
    /* the sign of the jump: the level lies between the undisturbed value
     * (taken from the first populated slab) and the shocked one */
    double ahead = NAN;
    for (int k = start; k >= 0 && k < nbins; k += step) {
        if (count[k] < min_count)
            continue;
        if (isnan(ahead))
            ahead = mean[k];
        int reached = level >= ahead ? mean[k] >= level : mean[k] <= level;
        if (reached) {
            double xc = lo + (k + 0.5) * w;
            if (prev < 0) {
                *pos = xc;
                return 0;
            }
            double xp = lo + (prev + 0.5) * w, vp = mean[prev], vk = mean[k];
            double t = vk != vp ? (level - vp) / (vk - vp) : 1.0;
            *pos = xp + t * (xc - xp);
            return 0;
        }
        prev = k;
    }
    return -1;
}

int shock_speed_fit(const double *t, const double *x, int n, double *speed, double *speed_err,
                    double *intercept, struct err *e)
{
    if (n < 3)
        return err_set(e, ERR_RUNTIME, "shock speed: %d front positions, at least 3 needed", n);
    double c0, c1, cov00, cov01, cov11, sumsq;
    gsl_fit_linear(t, 1, x, 1, (size_t)n, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
    /* the unweighted fit's covariance is already scaled by the residual
     * variance sumsq / (n - 2) */
    *speed = c1;
    *speed_err = sqrt(cov11);
    if (intercept)
        *intercept = c0;
    (void)cov00;
    (void)cov01;
    (void)sumsq;
    return 0;
}
