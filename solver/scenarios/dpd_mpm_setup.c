/* dpd_mpm_setup: the grid section and the grid over the material. */
#include "scenarios/dpd_mpm_setup.h"

#include <math.h>

#include "core/halo.h"

int dpd_mpm_grid_read(struct cfg_obj *root, double cutoff, struct dpd_mpm_grid_keys *k)
{
    struct cfg_obj o;
    int rc;
    if ((rc = cfg_section_required(root, "grid", &o)) ||
        (rc = cfg_real(&o, "cell", 4.0, CFG_GT(0), &k->cell)) ||
        (rc = cfg_real(&o, "margin", 0.0, CFG_GE(0), &k->margin)) ||
        (rc = cfg_real(&o, "small_mass", 1e-12, CFG_GE(0), &k->small_mass)) ||
        (rc = cfg_close(&o)))
        return rc;
    if (cutoff > 0 && !(k->cell < cutoff)) {
        char kp[CFG_PATH_MAX];
        snprintf(kp, sizeof kp, "%s.cell", o.path);
        return cfg_error_at(o.cfg, kp,
                            "cell edge %g Å is not smaller than the DPD cutoff %g Å: within the "
                            "MPM framework the DPD forces must reach beyond a cell (Chen 2014, "
                            "Sec. 3)",
                            k->cell, cutoff);
    }
    return 0;
}

void dpd_mpm_grid_place(const struct particles *p, uint32_t exclude, const double lo[3],
                        const double hi[3], const struct dpd_mpm_grid_keys *k,
                        struct dpd_mpm_grid *g)
{
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & exclude)
            continue;
        for (int d = 0; d < 3; d++) {
            mn[d] = fmin(mn[d], p->x[3 * i + d]);
            mx[d] = fmax(mx[d], p->x[3 * i + d]);
        }
    }
    if (p->halo) {   /* bricks: the extent of every rank's particles */
        double ext[6] = {-mn[0], -mn[1], -mn[2], mx[0], mx[1], mx[2]};
        halo_max(p->halo, ext, 6);
        for (int d = 0; d < 3; d++) {
            mn[d] = -ext[d];
            mx[d] = ext[3 + d];
        }
    }
    g->cell = k->cell;
    g->small_mass = k->small_mass;
    for (int d = 0; d < 3; d++) {
        g->lo[d] = mn[d] - lo[d];
        g->ncell[d] = (long)ceil((mx[d] + hi[d] - g->lo[d]) / k->cell);
        if (g->ncell[d] < 1)
            g->ncell[d] = 1;
    }
}
