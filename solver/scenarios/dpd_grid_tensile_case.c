/*
 * dpd_grid_tensile_case: the tensile rod of Chen et al. 2014, Sec. 4.1.2
 * (Figs. 5, 6) with the DPD/MPM-grid model (`type: dpd_grid_tensile`): the
 * rod's DPD particles are carried by the MPM grid (couple/dpd_mpm.h), their
 * pair forces mapped to the nodes with N_i (Eq. (s3b)); the two rigid ends
 * are DPD bodies pulled apart at constant velocity that act on the rod
 * through their pair forces, exactly as in the DPD-only `dpd_tensile`.  The
 * stress is (F_left - F_right) / (2 A) from the forces on the ends, the
 * strain 2 v t / L0 -- the same measurement as dpd_tensile.
 *
 * Sections: system, dpd (dpd_setup.h; default variant dpde), tensile
 * (dpd_tensile_setup.h), grid (dpd_mpm_setup.h; the automatic margin leaves
 * room for the ends' travel over the run).
 *
 * Metrics: those of dpd_tensile (peak_stress, strain_at_peak, ...) and cell
 * (Å), grid_nodes, heat_dr, heat_grid (eV given to the internal energies by
 * the D + R forces and by the grid), internal_temperature (K).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "scenarios/dpd_mpm_setup.h"
#include "scenarios/dpd_tensile_setup.h"

#define PARTNER_BIT (1u << 6)

struct grid_tensile_case {
    struct dpd d;
    struct dpd_mpm c;
    struct dpd_tensile t;
    int has_d, has_c;
};

static void gt_destroy(void *state)
{
    struct grid_tensile_case *c = state;
    if (!c)
        return;
    if (c->has_c)
        dpd_mpm_free(&c->c);
    if (c->has_d)
        dpd_free(&c->d);
    free(c);
}

static int gt_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct grid_tensile_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "tensile case");
    int rc = dpd_tensile_read(root, common, &c->d, &c->t);
    c->has_d = !rc && !root->cfg->shallow;
    struct dpd_mpm_grid_keys gk;
    if (!rc)
        rc = dpd_mpm_grid_read(root, c->has_d ? fmax(c->d.prm.sc.rc, c->d.set.cutoff) : 0.0, &gk);
    if (!rc && c->has_d && c->d.thermo.style != THERMOSTAT_NONE)
        rc = cfg_error_at(root->cfg, "dpd.thermostat.style",
                          "the grid-carried models take no thermostat: equilibrate with the "
                          "DPD-only `dpd` case type and read its final state");
    if (rc || root->cfg->shallow) {
        gt_destroy(c);
        return rc;
    }
    struct err *e = root->cfg->err;
    struct dpd *d = &c->d;
    /* the rod only (the grips are bodies); room for the ends' travel */
    double mlo[3], mhi[3];
    for (int k = 0; k < 3; k++) {
        mlo[k] = mhi[k] = gk.margin > 0 ? gk.margin : 2 * gk.cell + 0.5 * d->prm.lattice_constant;
        if (k == c->t.axis && gk.margin <= 0) {
            mlo[k] += c->t.v * d->dt * (double)c->t.steps;
            mhi[k] += c->t.v * d->dt * (double)c->t.steps;
        }
    }
    struct dpd_mpm_grid g;
    dpd_mpm_grid_place(d->p, DPD_GRIP_LO_BIT | DPD_GRIP_HI_BIT, mlo, mhi, &gk, &g);
    rc = dpd_mpm_order(d, PARTNER_BIT, e);
    if (!rc) {
        c->has_c = 1;
        rc = dpd_mpm_init(&c->c, d, &g, PARTNER_BIT, 0, e);
    }
    if (!rc)
        rc = dpd_mpm_prepare(&c->c, e);
    if (rc) {
        gt_destroy(c);
        return rc;
    }
    *state = c;
    return 0;
}

static int gt_step(void *ctx, struct err *e) { return dpd_mpm_step(ctx, e); }

static int gt_run(void *state, struct run *run, struct err *e)
{
    struct grid_tensile_case *c = state;
    c->c.m.timers = &run->timers;
    int rc = dpd_tensile_run(&c->d, &c->t, gt_step, &c->c, run, e);
    struct result *res = &run->result;
    result_metric(res, "cell", c->c.m.grid.h, "Å");
    result_metric(res, "grid_nodes", (double)c->c.m.grid.nnodes, "1");
    result_metric(res, "heat_dr", c->c.heat, "eV");
    result_metric(res, "heat_grid", c->c.subgrid_heat, "eV");
    double T = NAN;
    if (c->d.ufield >= 0 && c->c.ncarried > 0) {
        const double *u = c->d.p->fields[c->d.ufield].data;
        double s = 0;
        for (long i = 0; i < c->c.ncarried; i++)
            s += u[i];
        T = s / (double)c->c.ncarried / (c->d.set.heat_capacity * UNITS_KB);
    }
    result_metric(res, "internal_temperature", T, "K");
    return rc;
}

static long gt_particles(const void *state)
{
    const struct grid_tensile_case *c = state;
    return c->d.p ? c->d.p->n_owned : 0;
}

static long gt_steps(const void *state)
{
    const struct grid_tensile_case *c = state;
    return c->t.steps;
}

const struct case_type dpd_grid_tensile_case_type = {
    "dpd_grid_tensile",
    "DPD/MPM-grid tensile rod pulled by rigid ends: stress-strain curve and peak stress",
    gt_read, gt_run, gt_destroy, gt_particles, gt_steps,
    .checkpoints = 0,
};
