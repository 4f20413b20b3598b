/* crater: height map, flood fill from the impact point, projected widths. */
#include "analysis/crater.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int crater_measure(const double *x, int n, const unsigned char *use, const struct crater_params *p,
                   unsigned char *floor_atom, struct crater_stats *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    out->rim = -INFINITY;
    if (!(p->bin > 0) || !(p->hi[0] > p->lo[0]) || !(p->hi[1] > p->lo[1]))
        return err_set(e, ERR_INPUT, "crater: bin and lateral extent must be positive");
    int nx = (int)ceil((p->hi[0] - p->lo[0]) / p->bin), ny = (int)ceil((p->hi[1] - p->lo[1]) / p->bin);
    long nc = (long)nx * ny;
    double *top = malloc((size_t)nc * sizeof *top);
    int *who = malloc((size_t)nc * sizeof *who);
    int *queue = malloc((size_t)nc * sizeof *queue);
    unsigned char *in = calloc((size_t)nc, 1);
    if (!top || !who || !queue || !in) {
        free(top); free(who); free(queue); free(in);
        return err_nomem(e, "crater height map");
    }
    for (long c = 0; c < nc; c++) {
        top[c] = -INFINITY;
        who[c] = -1;
    }
    for (int i = 0; i < n; i++) {
        if (use && !use[i])
            continue;
        int cx = (int)floor((x[3 * i] - p->lo[0]) / p->bin), cy = (int)floor((x[3 * i + 1] - p->lo[1]) / p->bin);
        if (cx < 0 || cy < 0 || cx >= nx || cy >= ny)
            continue;
        long c = (long)cy * nx + cx;
        double z = x[3 * i + 2];
        if (z > top[c] || (z == top[c] && i < who[c])) {
            top[c] = z;
            who[c] = i;
        }
        if (z - p->surface > out->rim)
            out->rim = z - p->surface;
    }
    if (!isfinite(out->rim))
        out->rim = 0;
    /* seed: deepest column within two bins of the impact point */
    int sx = (int)floor((p->center[0] - p->lo[0]) / p->bin), sy = (int)floor((p->center[1] - p->lo[1]) / p->bin);
    long seed = -1;
    double best = p->threshold;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) {
            int cx = sx + dx, cy = sy + dy;
            if (cx < 0 || cy < 0 || cx >= nx || cy >= ny)
                continue;
            long c = (long)cy * nx + cx;
            if (who[c] >= 0 && p->surface - top[c] > best) {
                best = p->surface - top[c];
                seed = c;
            }
        }
    long head = 0, tail = 0;
    if (seed >= 0) {
        queue[tail++] = (int)seed;
        in[seed] = 1;
    }
    double pmin[4], pmax[4];
    for (int k = 0; k < 4; k++) {
        pmin[k] = INFINITY;
        pmax[k] = -INFINITY;
    }
    const double r2 = 1.0 / sqrt(2.0);
    while (head < tail) {
        long c = queue[head++];
        int cx = (int)(c % nx), cy = (int)(c / nx);
        double d = p->surface - top[c];
        out->columns++;
        out->volume += d * p->bin * p->bin;
        if (d > out->depth)
            out->depth = d;
        double X = p->lo[0] + (cx + 0.5) * p->bin, Y = p->lo[1] + (cy + 0.5) * p->bin;
        double proj[4] = {X, Y, (X + Y) * r2, (X - Y) * r2};
        for (int k = 0; k < 4; k++) {
            if (proj[k] < pmin[k]) pmin[k] = proj[k];
            if (proj[k] > pmax[k]) pmax[k] = proj[k];
        }
        const int nbx[4] = {1, -1, 0, 0}, nby[4] = {0, 0, 1, -1};
        for (int q = 0; q < 4; q++) {
            int ax = cx + nbx[q], ay = cy + nby[q];
            if (ax < 0 || ay < 0 || ax >= nx || ay >= ny)
                continue;
            long a = (long)ay * nx + ax;
            if (!in[a] && who[a] >= 0 && p->surface - top[a] > p->threshold) {
                in[a] = 1;
                queue[tail++] = (int)a;
            }
        }
    }
    if (floor_atom) {
        memset(floor_atom, 0, (size_t)n);
        for (long h = 0; h < tail; h++)
            floor_atom[who[queue[h]]] = 1;
    }
    if (out->columns > 0) {
        /* one column seen along an axis is `bin` wide, along a diagonal bin sqrt 2 */
        const double w[4] = {p->bin, p->bin, p->bin * sqrt(2.0), p->bin * sqrt(2.0)};
        for (int k = 0; k < 4; k++)
            out->extent[k] = pmax[k] - pmin[k] + w[k];
    }
    free(top); free(who); free(queue); free(in);
    return 0;
}
