/* wave_arrival: threshold crossing with linear interpolation. */
#include "analysis/wave_arrival.h"

#include <math.h>

double wave_arrival_time(const double *t, const double *s, long n, double threshold)
{
    double sign = threshold < 0 ? -1.0 : 1.0, th = fabs(threshold);
    for (long k = 0; k < n; k++) {
        double v = sign * s[k];
        if (!(v >= th))
            continue;
        if (k == 0)
            return t[0];
        double prev = sign * s[k - 1];
        if (!isfinite(prev) || v == prev)
            return t[k];
        return t[k - 1] + (th - prev) / (v - prev) * (t[k] - t[k - 1]);
    }
    return NAN;
}

double wave_speed(double distance, double t1, double t2)
{
    if (!isfinite(t1) || !isfinite(t2) || !(t2 > t1))
        return NAN;
    return distance / (t2 - t1);
}
