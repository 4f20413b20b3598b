/* stacking_faults: peak, burst time and rise time of the hcp-atom count. */
#include "analysis/stacking_faults.h"

#include <math.h>

/* First time the series reaches `level` (interpolated); NaN if never. */
static double first_crossing(const double *t, const double *n, long m, long stride, double level)
{
    for (long k = 0; k < m; k++) {
        double nk = n[k * stride];
        if (nk >= level) {
            if (k == 0)
                return t[0];
            double np = n[(k - 1) * stride], tp = t[(k - 1) * stride], tk = t[k * stride];
            return tp + (level - np) / (nk - np) * (tk - tp);
        }
    }
    return NAN;
}

void stacking_faults_burst(const double *t, const double *n, long m, long stride,
                           double min_atoms, struct sf_burst *out)
{
    out->peak = 0;
    out->peak_time = m > 0 ? t[0] : NAN;
    out->burst_time = out->rise_time = NAN;
    for (long k = 0; k < m; k++)
        if (n[k * stride] > out->peak) {
            out->peak = n[k * stride];
            out->peak_time = t[k * stride];
        }
    if (m == 0 || !(out->peak >= min_atoms))
        return;
    out->burst_time = first_crossing(t, n, m, stride, 0.5 * out->peak);
    out->rise_time = first_crossing(t, n, m, stride, 0.9 * out->peak) -
                     first_crossing(t, n, m, stride, 0.1 * out->peak);
}
