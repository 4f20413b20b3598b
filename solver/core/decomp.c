/* decomp: brick geometry and the choice of the rank grid (decomp.h). */
#include "core/decomp.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"

int decomp_check_grid(const int grid[3], const struct box *b, double range, char *why,
                      size_t len)
{
    for (int d = 0; d < 3; d++) {
        if (grid[d] < 1) {
            snprintf(why, len, "grid[%d] = %d: every axis needs at least one brick", d, grid[d]);
            return -1;
        }
        if (grid[d] == 1 && b->bc[d] != BOUNDARY_PERIODIC)
            continue;
        /* a tilted box's bricks are as thick as its height across the
         * faces of the edge, shared */
        int tilted = box_tilted(b);
        double full = tilted ? box_height(b, d) : box_length(b, d);
        double w = full / grid[d];
        if (!(w >= range)) {
            snprintf(why, len, "bricks of %g Å along %c (box %g Å %s/ %d) are thinner than the "
                     "interaction range %g Å (cutoff + skin): the halo exchange reaches only "
                     "the next brick", w, "xyz"[d], full, tilted ? "high across its faces " : "",
                     grid[d], range);
            return -1;
        }
    }
    return 0;
}

int decomp_choose_grid(int nranks, const struct box *b, double range, int grid[3])
{
    double best = INFINITY;
    char why[256];
    for (int px = 1; px <= nranks; px++) {
        if (nranks % px)
            continue;
        for (int py = 1; py <= nranks / px; py++) {
            if ((nranks / px) % py)
                continue;
            int g[3] = {px, py, nranks / px / py};
            if (decomp_check_grid(g, b, range, why, sizeof why) != 0)
                continue;
            double w[3];
            for (int d = 0; d < 3; d++)
                w[d] = box_length(b, d) / g[d];
            double area = w[0] * w[1] + w[1] * w[2] + w[0] * w[2];
            if (area < best * (1 - 1e-12)) {
                best = area;
                memcpy(grid, g, sizeof g);
            }
        }
    }
    return isfinite(best) ? 0 : -1;
}

void decomp_set_box(struct decomp *dc, const struct box *b)
{
    dc->tilted = box_tilted(b);
    for (int d = 0; d < 3; d++) {
        dc->tilt[d] = b->tilt[d];
        dc->height[d] = dc->tilted ? box_height(b, d) : b->hi[d] - b->lo[d];
    }
    for (int d = 0; d < 3; d++) {
        dc->blo[d] = b->lo[d];
        dc->bhi[d] = b->hi[d];
        double L = b->hi[d] - b->lo[d];
        if (dc->frac[d]) {
            int c = dc->coords[d];
            dc->lo[d] = c == 0 ? b->lo[d] : b->lo[d] + L * dc->frac[d][c];
            dc->hi[d] = c + 1 == dc->grid[d] ? b->hi[d] : b->lo[d] + L * dc->frac[d][c + 1];
            continue;
        }
        dc->lo[d] = b->lo[d] + L * dc->coords[d] / dc->grid[d];
        dc->hi[d] = dc->coords[d] + 1 == dc->grid[d] ? b->hi[d]
                                                     : b->lo[d] + L * (dc->coords[d] + 1) / dc->grid[d];
    }
}

int decomp_init(struct decomp *dc, const struct parallel *par, const int grid[3],
                const struct box *b, struct err *e)
{
    memset(dc, 0, sizeof *dc);
    dc->par = par;
    memcpy(dc->grid, grid, sizeof dc->grid);
    for (int d = 0; d < 3; d++)
        dc->periodic[d] = b->bc[d] == BOUNDARY_PERIODIC;
    int rc = parallel_cart(par, dc->grid, dc->periodic, dc->coords, dc->nbr, e);
    if (rc)
        return rc;
    decomp_set_box(dc, b);
    return 0;
}

void decomp_free(struct decomp *dc)
{
    for (int d = 0; d < 3; d++) {
        free(dc->frac[d]);
        dc->frac[d] = NULL;
    }
}

void decomp_box(const struct decomp *dc, struct box *b)
{
    memset(b, 0, sizeof *b);
    for (int d = 0; d < 3; d++) {
        b->lo[d] = dc->blo[d];
        b->hi[d] = dc->bhi[d];
        b->tilt[d] = dc->tilt[d];
    }
}

/* The fraction of the box along axis d where x lies: (x_d - lo_d) / L_d
 * in an orthogonal box, the fractional coordinate s_d in a tilted one. */
static double box_fraction(const struct decomp *dc, int d, const double x[3])
{
    if (!dc->tilted)
        return (x[d] - dc->blo[d]) / (dc->bhi[d] - dc->blo[d]);
    struct box b;
    decomp_box(dc, &b);
    double s[3];
    box_to_fractional(&b, x, s);
    return s[d];
}

double decomp_cut_coord(const struct decomp *dc, int d, const double x[3])
{
    if (!dc->tilted)
        return x[d];
    return dc->blo[d] + box_fraction(dc, d, x) * (dc->bhi[d] - dc->blo[d]);
}

int decomp_coord_at(const struct decomp *dc, int d, const double x[3])
{
    return decomp_coord(dc, d, decomp_cut_coord(dc, d, x));
}

double decomp_range_along(const struct decomp *dc, int d, double r)
{
    if (!dc->tilted)
        return r;
    return r * ((dc->bhi[d] - dc->blo[d]) / dc->height[d]);
}

double decomp_min_width(const struct decomp *dc, int d)
{
    double L = dc->bhi[d] - dc->blo[d], w = INFINITY;
    for (int c = 0; c < dc->grid[d]; c++)
        w = fmin(w, dc->frac[d] ? L * (dc->frac[d][c + 1] - dc->frac[d][c]) : L / dc->grid[d]);
    return w;
}

enum { SHIFT_BINS = 4096 };

int decomp_shift(struct decomp *dc, const double *x, int n, double range, struct err *e)
{
    double *hist = malloc(SHIFT_BINS * sizeof *hist);
    int bad = hist == NULL;
    if (parallel_any(dc->par, bad)) {
        free(hist);
        return err_nomem(e, "balance histogram");
    }
    int rc = 0;
    for (int d = 0; d < 3 && !rc; d++) {
        int g = dc->grid[d];
        double L = dc->bhi[d] - dc->blo[d];
        if (g == 1 || !(L > 0))
            continue;
        double *frac = calloc((size_t)g + 1, sizeof *frac);
        if (parallel_any(dc->par, frac == NULL)) {
            free(frac);
            rc = err_nomem(e, "balance cuts");
            break;
        }
        memset(hist, 0, SHIFT_BINS * sizeof *hist);
        for (int i = 0; i < n; i++) {
            double q = box_fraction(dc, d, x + 3 * i) * SHIFT_BINS;
            int b = !(q >= 0) ? 0 : q >= SHIFT_BINS - 1 ? SHIFT_BINS - 1 : (int)q;
            hist[b] += 1.0;
        }
        parallel_sum(dc->par, hist, SHIFT_BINS);
        double total = 0;
        for (int b = 0; b < SHIFT_BINS; b++)
            total += hist[b];
        /* cut c where the cumulative count reaches c / g of the total,
         * linear within the bin */
        double cum = 0;
        int b = 0;
        for (int c = 1; c < g; c++) {
            double want = total * c / g;
            while (b < SHIFT_BINS - 1 && cum + hist[b] < want)
                cum += hist[b++];
            double in = hist[b] > 0 ? (want - cum) / hist[b] : 0.0;
            frac[c] = (b + fmin(fmax(in, 0.0), 1.0)) / SHIFT_BINS;
        }
        frac[0] = 0.0;
        frac[g] = 1.0;
        /* every brick at least the range wide (the halo reaches one brick):
         * push cuts up from below, then down from above; equal bricks are
         * wide enough (decomp_check_grid), so this always fits */
        double wmin = decomp_range_along(dc, d, range) / L * (1 + 1e-12);
        for (int c = 1; c < g; c++)
            frac[c] = fmax(frac[c], frac[c - 1] + wmin);
        for (int c = g - 1; c >= 1; c--)
            frac[c] = fmin(frac[c], frac[c + 1] - wmin);
        free(dc->frac[d]);
        dc->frac[d] = frac;
    }
    free(hist);
    if (!rc) {
        struct box b;
        decomp_box(dc, &b);
        decomp_set_box(dc, &b);
    }
    return rc;
}

int decomp_coord(const struct decomp *dc, int d, double x)
{
    double L = dc->bhi[d] - dc->blo[d];
    if (dc->frac[d]) {   /* the last cut at or below x */
        const double *f = dc->frac[d];
        double q = L > 0 ? (x - dc->blo[d]) / L : 0;
        if (!(q >= f[1]))
            return 0;
        int lo = 1, hi = dc->grid[d] - 1;
        while (lo < hi) {
            int mid = (lo + hi + 1) / 2;
            if (q >= f[mid])
                lo = mid;
            else
                hi = mid - 1;
        }
        return lo;
    }
    double q = L > 0 ? (x - dc->blo[d]) / L * dc->grid[d] : 0;
    /* compared in double before the cast: NaN and far-away positions clamp */
    if (!(q >= 0))
        return 0;
    if (q >= dc->grid[d] - 1)
        return dc->grid[d] - 1;
    return (int)q;
}

int decomp_owner(const struct decomp *dc, const double x[3])
{
    int c[3];
    for (int d = 0; d < 3; d++)
        c[d] = decomp_coord_at(dc, d, x);
    /* MPI_Cart_create without reordering: row-major, the last axis fastest */
    return (c[0] * dc->grid[1] + c[1]) * dc->grid[2] + c[2];
}

int decomp_owns(const struct decomp *dc, const double x[3])
{
    for (int d = 0; d < 3; d++)
        if (decomp_coord_at(dc, d, x) != dc->coords[d])
            return 0;
    return 1;
}

int decomp_owns_point(const void *dc, const double x[3])
{
    return decomp_owns(dc, x);
}
