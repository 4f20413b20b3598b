/* crater: height map, flood fill from the impact point, projected widths. */
#include "analysis/crater.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int crater_map_init(struct crater_map *m, const struct crater_params *p, struct err *e)
{
    memset(m, 0, sizeof *m);
    if (!(p->bin > 0) || !(p->hi[0] > p->lo[0]) || !(p->hi[1] > p->lo[1]))
        return err_set(e, ERR_INPUT, "crater: bin and lateral extent must be positive");
    m->nx = (int)ceil((p->hi[0] - p->lo[0]) / p->bin);
    m->ny = (int)ceil((p->hi[1] - p->lo[1]) / p->bin);
    long nc = (long)m->nx * m->ny;
    m->top = malloc((size_t)nc * sizeof *m->top);
    m->who = malloc((size_t)nc * sizeof *m->who);
    if (!m->top || !m->who) {
        crater_map_free(m);
        return err_nomem(e, "crater height map");
    }
    for (long c = 0; c < nc; c++) {
        m->top[c] = -INFINITY;
        m->who[c] = -1;
    }
    m->rim = -INFINITY;
    return 0;
}

void crater_map_free(struct crater_map *m)
{
    free(m->top);
    free(m->who);
    memset(m, 0, sizeof *m);
}

long crater_column(const struct crater_map *m, const struct crater_params *p, const double *x)
{
    int cx = (int)floor((x[0] - p->lo[0]) / p->bin), cy = (int)floor((x[1] - p->lo[1]) / p->bin);
    if (cx < 0 || cy < 0 || cx >= m->nx || cy >= m->ny)
        return -1;
    return (long)cy * m->nx + cx;
}

void crater_map_add(struct crater_map *m, const double *x, int n, const unsigned char *use,
                    const int64_t *key, const struct crater_params *p)
{
    for (int i = 0; i < n; i++) {
        if (use && !use[i])
            continue;
        long c = crater_column(m, p, x + 3 * i);
        if (c < 0)
            continue;
        double z = x[3 * i + 2];
        int64_t k = key ? key[i] : i;
        if (z > m->top[c] || (z == m->top[c] && k < m->who[c])) {
            m->top[c] = z;
            m->who[c] = k;
        }
        if (z - p->surface > m->rim)
            m->rim = z - p->surface;
    }
}

int crater_flood(const struct crater_map *m, const struct crater_params *p,
                 unsigned char *in_crater, struct crater_stats *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    out->rim = isfinite(m->rim) ? m->rim : 0;
    int nx = m->nx, ny = m->ny;
    long nc = (long)nx * ny;
    const double *top = m->top;
    const int64_t *who = m->who;
    int *queue = malloc((size_t)nc * sizeof *queue);
    unsigned char *in = calloc((size_t)nc, 1);
    if (!queue || !in) {
        free(queue); free(in);
        return err_nomem(e, "crater height map");
    }
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
    if (out->columns > 0) {
        /* one column seen along an axis is `bin` wide, along a diagonal bin sqrt 2 */
        const double w[4] = {p->bin, p->bin, p->bin * sqrt(2.0), p->bin * sqrt(2.0)};
        for (int k = 0; k < 4; k++)
            out->extent[k] = pmax[k] - pmin[k] + w[k];
    }
    if (in_crater)
        memcpy(in_crater, in, (size_t)nc);
    free(queue); free(in);
    return 0;
}

int crater_measure(const double *x, int n, const unsigned char *use, const struct crater_params *p,
                   unsigned char *floor_atom, struct crater_stats *out, struct err *e)
{
    struct crater_map m;
    memset(out, 0, sizeof *out);
    int rc = crater_map_init(&m, p, e);
    if (rc)
        return rc;
    long nc = (long)m.nx * m.ny;
    unsigned char *in = floor_atom ? malloc((size_t)nc) : NULL;
    if (floor_atom && !in)
        rc = err_nomem(e, "crater height map");
    if (!rc) {
        crater_map_add(&m, x, n, use, NULL, p);   /* keys: the atoms' indices */
        rc = crater_flood(&m, p, in, out, e);
    }
    if (!rc && floor_atom) {
        memset(floor_atom, 0, (size_t)n);
        for (long c = 0; c < nc; c++)
            if (in[c])
                floor_atom[m.who[c]] = 1;
    }
    free(in);
    crater_map_free(&m);
    return rc;
}
