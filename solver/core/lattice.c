/* lattice: site generation for cubic and hcp crystals. */
#include "core/lattice.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

const char *const lattice_style_names[] = {"sc", "bcc", "fcc", "diamond", "hcp", NULL};

/* Oriented unless the rows are all zero (default) or the identity. */
static int is_oriented(const struct lattice *l)
{
    int zero = 1, ident = 1;
    for (int d = 0; d < 3; d++)
        for (int k = 0; k < 3; k++) {
            zero &= l->orient[d][k] == 0;
            ident &= l->orient[d][k] == (d == k);
        }
    return !zero && !ident;
}

static double orient_len(const struct lattice *l, int d)
{
    const int *v = l->orient[d];
    return sqrt((double)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

int lattice_check_orient(const struct lattice *l, char *why, size_t len)
{
    if (!is_oriented(l))
        return 0;
    if (l->style == LATTICE_HCP) {
        snprintf(why, len, "hcp lattices cannot be re-oriented");
        return -1;
    }
    for (int d = 0; d < 3; d++)
        if (orient_len(l, d) == 0) {
            snprintf(why, len, "orientation of %c is the zero vector", "xyz"[d]);
            return -1;
        }
    for (int d = 0; d < 3; d++)
        for (int q = d + 1; q < 3; q++) {
            int dot = 0;
            for (int k = 0; k < 3; k++)
                dot += l->orient[d][k] * l->orient[q][k];
            if (dot != 0) {
                snprintf(why, len, "orientations of %c and %c are not orthogonal", "xyz"[d],
                         "xyz"[q]);
                return -1;
            }
        }
    const int *x = l->orient[0], *y = l->orient[1], *z = l->orient[2];
    int cx = x[1] * y[2] - x[2] * y[1], cy = x[2] * y[0] - x[0] * y[2], cz = x[0] * y[1] - x[1] * y[0];
    if (cx * z[0] + cy * z[1] + cz * z[2] <= 0) {
        snprintf(why, len, "orientation is left-handed (x cross y must point along z)");
        return -1;
    }
    return 0;
}

void lattice_cell(const struct lattice *l, double cell[3])
{
    cell[0] = cell[1] = cell[2] = l->a;
    if (is_oriented(l)) {
        for (int d = 0; d < 3; d++)
            cell[d] = l->a * orient_len(l, d);
        return;
    }
    if (l->style == LATTICE_HCP) {
        cell[1] = sqrt(3.0) * l->a;
        cell[2] = sqrt(8.0 / 3.0) * l->a;
    }
}

int lattice_basis(const struct lattice *l, double b[8][3])
{
    static const double fcc[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    /* hcp in the orthorhombic cell: A layer at z=0, B layer at z=1/2 */
    static const double hcp[4][3] = {
        {0, 0, 0}, {0.5, 0.5, 0}, {0.5, 5.0 / 6.0, 0.5}, {0, 1.0 / 3.0, 0.5}};
    int n = 0;
    switch (l->style) {
    case LATTICE_SC:
        b[0][0] = b[0][1] = b[0][2] = 0;
        return 1;
    case LATTICE_BCC:
        b[0][0] = b[0][1] = b[0][2] = 0;
        b[1][0] = b[1][1] = b[1][2] = 0.5;
        return 2;
    case LATTICE_FCC:
        for (n = 0; n < 4; n++)
            for (int d = 0; d < 3; d++)
                b[n][d] = fcc[n][d];
        return 4;
    case LATTICE_DIAMOND:
        for (n = 0; n < 4; n++)
            for (int d = 0; d < 3; d++) {
                b[n][d] = fcc[n][d];
                b[n + 4][d] = fcc[n][d] + 0.25;
            }
        return 8;
    case LATTICE_HCP:
        for (n = 0; n < 4; n++)
            for (int d = 0; d < 3; d++)
                b[n][d] = hcp[n][d];
        return 4;
    }
    return 0;
}

/* Sites of one repeating cell in fractional coordinates (caller frees). */
static int cell_sites(const struct lattice *l, double (**out)[3])
{
    double basis[8][3];
    int nb = lattice_basis(l, basis);
    if (!is_oriented(l)) {
        double(*s)[3] = malloc((size_t)nb * sizeof *s);
        if (!s)
            return -1;
        for (int k = 0; k < nb; k++)
            for (int d = 0; d < 3; d++)
                s[k][d] = basis[k][d];
        *out = s;
        return nb;
    }
    /* rotated: unit rows R, cell edges L = |orient| (in units of a); visit the
     * cubic cells covering the rotated cell and keep sites inside it */
    double R[3][3], L[3];
    for (int d = 0; d < 3; d++) {
        L[d] = orient_len(l, d);
        for (int k = 0; k < 3; k++)
            R[d][k] = l->orient[d][k] / L[d];
    }
    int span = 0;
    for (int d = 0; d < 3; d++)
        for (int k = 0; k < 3; k++)
            span += abs(l->orient[d][k]);
    int cap = 64, n = 0;
    double(*s)[3] = malloc((size_t)cap * sizeof *s);
    if (!s)
        return -1;
    const double tol = 1e-9;
    for (int i = -span; i <= span; i++)
        for (int j = -span; j <= span; j++)
            for (int k = -span; k <= span; k++)
                for (int b = 0; b < nb; b++) {
                    double r[3] = {i + basis[b][0], j + basis[b][1], k + basis[b][2]};
                    double f[3];
                    int inside = 1;
                    for (int d = 0; d < 3 && inside; d++) {
                        f[d] = (R[d][0] * r[0] + R[d][1] * r[1] + R[d][2] * r[2]) / L[d];
                        if (f[d] > 1.0 - tol && f[d] < 1.0 + tol)
                            inside = 0;   /* the face at 1 is the image of 0 */
                        else if (f[d] > -tol && f[d] < tol)
                            f[d] = 0.0;
                        else if (f[d] < 0 || f[d] >= 1)
                            inside = 0;
                    }
                    if (!inside)
                        continue;
                    if (n == cap) {
                        cap *= 2;
                        double(*ns)[3] = realloc(s, (size_t)cap * sizeof *ns);
                        if (!ns) {
                            free(s);
                            return -1;
                        }
                        s = ns;
                    }
                    for (int d = 0; d < 3; d++)
                        s[n][d] = f[d];
                    n++;
                }
    *out = s;
    return n;
}

int lattice_cell_sites(const struct lattice *l)
{
    double(*sites)[3] = NULL;
    int ns = cell_sites(l, &sites);
    free(sites);
    return ns;
}

long lattice_fill(const struct lattice *l, const long n[3], const struct region *region,
                  struct particles *p, int type, int64_t *next_id, struct err *e)
{
    return lattice_fill_where(l, n, region, NULL, NULL, p, type, next_id, e);
}

long lattice_fill_where(const struct lattice *l, const long n[3], const struct region *region,
                        int (*keep)(const void *ctx, const double x[3]), const void *keep_ctx,
                        struct particles *p, int type, int64_t *next_id, struct err *e)
{
    double cell[3];
    lattice_cell(l, cell);
    double(*sites)[3] = NULL;
    int ns = cell_sites(l, &sites);
    if (ns < 0) {
        err_nomem(e, "lattice sites");
        return -1;
    }
    long added = 0;
    for (long i = 0; i < n[0]; i++)
        for (long j = 0; j < n[1]; j++)
            for (long k = 0; k < n[2]; k++)
                for (int s = 0; s < ns; s++) {
                    double x[3] = {l->origin[0] + (i + sites[s][0]) * cell[0],
                                   l->origin[1] + (j + sites[s][1]) * cell[1],
                                   l->origin[2] + (k + sites[s][2]) * cell[2]};
                    if (region && !region_contains(region, x))
                        continue;
                    /* the id counts every site of the region, kept or not,
                     * so a rank building its brick numbers the atoms as
                     * the whole system does */
                    int64_t id = (*next_id)++;
                    added++;
                    if (keep && !keep(keep_ctx, x))
                        continue;
                    if (particles_add(p, x, NULL, type, id) < 0) {
                        free(sites);
                        err_nomem(e, "lattice sites");
                        return -1;
                    }
                }
    free(sites);
    return added;
}

struct site_extent {
    double *lo, *hi;
};

static int extent_of_site(const void *ctx, const double x[3])
{
    const struct site_extent *t = ctx;
    for (int d = 0; d < 3; d++) {
        t->lo[d] = fmin(t->lo[d], x[d]);
        t->hi[d] = fmax(t->hi[d], x[d]);
    }
    return 0;   /* store none */
}

long lattice_extent(const struct lattice *l, const long n[3], const struct region *region,
                    double lo[3], double hi[3], struct err *e)
{
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    struct site_extent ext = {lo, hi};
    int64_t id = 1;
    return lattice_fill_where(l, n, region, extent_of_site, &ext, NULL, 0, &id, e);
}

double lattice_nn_distance(const struct lattice *l)
{
    switch (l->style) {
    case LATTICE_SC: return l->a;
    case LATTICE_BCC: return l->a * sqrt(3.0) / 2.0;
    case LATTICE_FCC: return l->a / sqrt(2.0);
    case LATTICE_DIAMOND: return l->a * sqrt(3.0) / 4.0;
    case LATTICE_HCP: return l->a;
    }
    return l->a;
}
