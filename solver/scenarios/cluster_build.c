/* cluster_build: spherical cuts with an exact site count. */
#include "scenarios/cluster_build.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct site {
    double d2;
    double x[3];
};

static int by_distance(const void *a, const void *b)
{
    const struct site *p = a, *q = b;
    if (p->d2 != q->d2)
        return p->d2 < q->d2 ? -1 : 1;
    for (int k = 0; k < 3; k++)
        if (p->x[k] != q->x[k])
            return p->x[k] < q->x[k] ? -1 : 1;
    return 0;
}

/* Sites around centre c (units of a) sorted by distance; *ns returned. */
static struct site *sorted_sites(enum lattice_style style, double a, long n, const double c[3],
                                 long *ns)
{
    struct lattice l = {style, a, {0, 0, 0}, {{0}}};
    double basis[8][3];
    int nb = lattice_basis(&l, basis);
    /* cells enough for a sphere of n sites with a margin of two cells */
    double r_cells = cbrt(3.0 * n / (4.0 * M_PI * nb)) + 2.0;
    int m = (int)ceil(r_cells);
    long cap = (long)(2 * m + 1) * (2 * m + 1) * (2 * m + 1) * nb;
    struct site *s = malloc((size_t)cap * sizeof *s);
    if (!s)
        return NULL;
    long k = 0;
    for (int i = -m; i <= m; i++)
        for (int j = -m; j <= m; j++)
            for (int q = -m; q <= m; q++)
                for (int b = 0; b < nb; b++) {
                    double f[3] = {i + basis[b][0] - c[0], j + basis[b][1] - c[1], q + basis[b][2] - c[2]};
                    s[k].d2 = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) * a * a;
                    for (int d = 0; d < 3; d++)
                        s[k].x[d] = f[d] * a;
                    k++;
                }
    qsort(s, (size_t)k, sizeof *s, by_distance);
    *ns = k;
    return s;
}

/* 1 when the n-th and (n+1)-th sites are at different distances. */
static int cuts_cleanly(const struct site *s, long ns, long n, double a)
{
    if (n >= ns)
        return 0;
    return sqrt(s[n].d2) - sqrt(s[n - 1].d2) > 1e-6 * a;
}

int cluster_cut_sphere(enum lattice_style style, double a, long n, const double *center_frac,
                       struct cluster_cut *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (n < 1)
        return err_set(e, ERR_INPUT, "a cluster needs at least one atom");
    double cand[64][3];
    int nc = 0;
    if (center_frac) {
        memcpy(cand[nc++], center_frac, sizeof cand[0]);
    } else {
        static const double fixed[3][3] = {{0, 0, 0}, {0.5, 0.5, 0.5}, {0.25, 0.25, 0.25}};
        for (int k = 0; k < 3; k++)
            memcpy(cand[nc++], fixed[k], sizeof cand[0]);
        for (int i = 0; i <= 4; i++)
            for (int j = 0; j <= i; j++)
                for (int k = 0; k <= j; k++)
                    if (nc < 64)
                        memcpy(cand[nc++], (double[3]){i / 8.0, j / 8.0, k / 8.0}, sizeof cand[0]);
    }
    long below = 0, above = 0;
    for (int c = 0; c < nc; c++) {
        long ns;
        struct site *s = sorted_sites(style, a, n, cand[c], &ns);
        if (!s)
            return err_nomem(e, "cluster sites");
        if (cuts_cleanly(s, ns, n, a)) {
            out->n = n;
            out->pos = malloc((size_t)n * sizeof *out->pos);
            if (!out->pos) {
                free(s);
                return err_nomem(e, "cluster sites");
            }
            for (long k = 0; k < n; k++)
                memcpy(out->pos[k], s[k].x, sizeof out->pos[k]);
            memcpy(out->center, cand[c], sizeof out->center);
            out->extent = sqrt(s[n - 1].d2);
            out->radius = 0.5 * (sqrt(s[n - 1].d2) + sqrt(s[n].d2));
            free(s);
            return 0;
        }
        /* the reachable counts next to n around this centre */
        long lo = n - 1, hi = n + 1;
        while (lo > 0 && !cuts_cleanly(s, ns, lo, a))
            lo--;
        while (hi < ns && !cuts_cleanly(s, ns, hi, a))
            hi++;
        if (lo > below)
            below = lo;
        if (!above || hi < above)
            above = hi;
        free(s);
    }
    return err_set(e, ERR_INPUT,
                   "no spherical cut of the %s lattice holds exactly %ld atoms around the centres "
                   "tried; nearest possible counts: %ld and %ld",
                   lattice_style_names[style], n, below, above);
}

void cluster_cut_free(struct cluster_cut *c)
{
    free(c->pos);
    memset(c, 0, sizeof *c);
}
