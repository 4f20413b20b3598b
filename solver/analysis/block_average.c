/* block_average: blocked standard error of a mean. */
#include "analysis/block_average.h"

#include <math.h>

double block_average(const double *x, long n, int nblocks, double *sem)
{
    double mean = 0;
    for (long k = 0; k < n; k++)
        mean += x[k];
    mean = n > 0 ? mean / n : NAN;
    if (!sem)
        return mean;
    *sem = NAN;
    if (nblocks > 1024)
        nblocks = 1024;
    if (nblocks < 2 || n < nblocks)
        return mean;
    long len = n / nblocks;
    double s2 = 0, bm_mean = 0;
    double bm[1024];
    for (int b = 0; b < nblocks; b++) {
        double s = 0;
        for (long k = b * len; k < (b + 1) * len; k++)
            s += x[k];
        bm[b] = s / len;
        bm_mean += bm[b];
    }
    bm_mean /= nblocks;
    for (int b = 0; b < nblocks; b++)
        s2 += (bm[b] - bm_mean) * (bm[b] - bm_mean);
    *sem = sqrt(s2 / (nblocks - 1) / nblocks);
    return mean;
}
