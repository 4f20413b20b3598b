/* decomp: brick geometry and the choice of the rank grid (decomp.h). */
#include "core/decomp.h"

#include <math.h>
#include <stdio.h>
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
        double w = box_length(b, d) / grid[d];
        if (!(w >= range)) {
            snprintf(why, len, "bricks of %g Å along %c (box %g Å / %d) are thinner than the "
                     "interaction range %g Å (cutoff + skin): the halo exchange reaches only "
                     "the next brick", w, "xyz"[d], box_length(b, d), grid[d], range);
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
    for (int d = 0; d < 3; d++) {
        dc->blo[d] = b->lo[d];
        dc->bhi[d] = b->hi[d];
        double L = b->hi[d] - b->lo[d];
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

int decomp_coord(const struct decomp *dc, int d, double x)
{
    double L = dc->bhi[d] - dc->blo[d];
    double q = L > 0 ? (x - dc->blo[d]) / L * dc->grid[d] : 0;
    /* compared in double before the cast: NaN and far-away positions clamp */
    if (!(q >= 0))
        return 0;
    if (q >= dc->grid[d] - 1)
        return dc->grid[d] - 1;
    return (int)q;
}

int decomp_owns(const struct decomp *dc, const double x[3])
{
    for (int d = 0; d < 3; d++)
        if (decomp_coord(dc, d, x[d]) != dc->coords[d])
            return 0;
    return 1;
}
