/* damage_shape: second-moment tensor and <100>/<110> extents of a top view. */
#include "analysis/damage_shape.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The q-quantile of v[0..m) (sorted in place), linear between order
 * statistics. */
static double quantile(double *v, long m, double q)
{
    qsort(v, (size_t)m, sizeof *v, cmp_double);
    double pos = q * (double)(m - 1);
    long k = (long)floor(pos);
    if (k >= m - 1)
        return v[m - 1];
    return v[k] + (pos - (double)k) * (v[k + 1] - v[k]);
}

int damage_shape_measure(const double *x, int n, const unsigned char *use, double *scratch,
                         struct damage_shape *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    out->eig_ratio = out->axis_deg = out->extent_ratio = NAN;
    double sx = 0, sy = 0;
    long cnt = 0;
    for (int i = 0; i < n; i++)
        if (!use || use[i]) {
            sx += x[3 * i];
            sy += x[3 * i + 1];
            cnt++;
        }
    out->n = cnt;
    if (cnt == 0)
        return 0;
    double cx = sx / (double)cnt, cy = sy / (double)cnt;
    out->centroid[0] = cx;
    out->centroid[1] = cy;
    double mxx = 0, myy = 0, mxy = 0;
    for (int i = 0; i < n; i++)
        if (!use || use[i]) {
            double dx = x[3 * i] - cx, dy = x[3 * i + 1] - cy;
            mxx += dx * dx;
            myy += dy * dy;
            mxy += dx * dy;
        }
    mxx /= (double)cnt;
    myy /= (double)cnt;
    mxy /= (double)cnt;
    out->m[0] = mxx;
    out->m[1] = myy;
    out->m[2] = mxy;
    double mean = 0.5 * (mxx + myy), half = 0.5 * (mxx - myy);
    double r = sqrt(half * half + mxy * mxy);
    out->lmax = mean + r;
    out->lmin = fmax(mean - r, 0.0);
    if (cnt < 3 || !(out->lmax > 0))
        return 0;
    out->eig_ratio = out->lmin / out->lmax;
    /* major axis: tan 2 theta = 2 Mxy / (Mxx - Myy) */
    double th = 0.5 * atan2(2.0 * mxy, mxx - myy) * 180.0 / M_PI;
    out->axis_deg = th <= -90.0 ? th + 180.0 : th;
    double *v = scratch ? scratch : malloc((size_t)(2 * cnt) * sizeof *v);
    if (!v)
        return err_nomem(e, "damage shape");
    const double r2 = 1.0 / sqrt(2.0);
    for (int fam = 0; fam < 2; fam++) {
        long m = 0;
        for (int i = 0; i < n; i++)
            if (!use || use[i]) {
                double dx = x[3 * i] - cx, dy = x[3 * i + 1] - cy;
                if (fam == 0) {
                    v[m++] = fabs(dx);
                    v[m++] = fabs(dy);
                } else {
                    v[m++] = fabs(dx + dy) * r2;
                    v[m++] = fabs(dx - dy) * r2;
                }
            }
        double w = 2.0 * quantile(v, m, DAMAGE_SHAPE_QUANTILE);
        if (fam == 0)
            out->extent_100 = w;
        else
            out->extent_110 = w;
    }
    if (!scratch)
        free(v);
    out->extent_ratio = out->extent_100 > 0 ? out->extent_110 / out->extent_100 : NAN;
    return 0;
}
