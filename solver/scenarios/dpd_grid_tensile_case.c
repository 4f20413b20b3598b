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
 * On the engine (engine/sim.h): the rod is one instance of the dpd_mpm
 * model (engine/model_dpd_mpm.c); the stress samples are the case's
 * after_step hook and go into the checkpoints (output.checkpoint_every,
 * run --restart) with the partial sum of the sample in progress.
 *
 * Under mpirun the rod runs on bricks (docs/dpd_mpm.md "Under MPI"): the
 * DPD particles on the DPD halo's bricks (dpd_tensile_read), the grid
 * whole on every rank with its node sums over the ranks (couple/dpd_mpm.c);
 * the grips' forces, heats and counts are sums, the final state is
 * written by rank 0 a window at a time (output/final_state.h).
 *
 * Metrics: those of dpd_tensile (peak_stress, strain_at_peak, ...) and cell
 * (Å), grid_nodes, heat_dr, heat_grid (eV given to the internal energies by
 * the D + R forces and by the grid), internal_temperature (K).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "engine/models.h"
#include "output/final_state.h"
#include "output/decomp_record.h"
#include "scenarios/dpd_mpm_setup.h"
#include "output/dpd_output.h"
#include "scenarios/dpd_tensile_setup.h"

#define PARTNER_BIT (1u << 6)

struct grid_tensile_case {
    struct dpd d;
    struct dpd_mpm c;
    struct dpd_tensile t;
    struct halo *halo;                 /* bricks (owned), or NULL */
    int has_d, has_c;
    struct dpd_mpm_model model;
    /* the run's accumulators (checkpointed) */
    struct dpd_output out;
    int out_open;
    struct dpd_tensile_curve cv;       /* the stress-strain curve so far */
    double *restored_rows;             /* thermo rows read from a checkpoint */
    long nrestored;
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
    if (c->halo)
        halo_free(c->halo);
    free(c->halo);
    dpd_tensile_curve_free(&c->cv);
    free(c->restored_rows);
    free(c);
}

static int gt_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct grid_tensile_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "tensile case");
    /* under mpirun the rod runs on bricks (docs/dpd_mpm.md, "Under MPI") */
    int rc = dpd_tensile_read(root, common, &c->d, &c->t, &c->halo, 0);
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

/* --- the run on the engine (engine/sim.h) ------------------------------------ */

static int gt_begin(void *state, struct sim *s, struct err *e)
{
    struct grid_tensile_case *c = state;
    int rc = dpd_output_begin(&c->out, s->run, e);
    c->out_open = !rc;
    if (!rc && s->restarted_from >= 0)
        rc = dpd_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    return rc;
}

/* Chen 2014 Sec. 4.1.2: the stress from the forces on the rigid ends (as
 * dpd_tensile). */
static int gt_after_step(void *state, struct sim *s, struct err *e)
{
    struct grid_tensile_case *c = state;
    (void)e;
    dpd_tensile_curve_add(&c->cv, &c->t, &c->d, s->step == c->t.steps);
    return 0;
}

static int gt_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct grid_tensile_case *c = state;
    (void)due;   /* dpd_output_step reads the same schedule */
    return dpd_output_step(&c->out, s->run, &c->d, c->t.steps)
               ? err_set(e, ERR_RUNTIME, "%s: cannot write the outputs of step %ld",
                         s->run->opt.out_dir, s->step)
               : 0;
}

static int gt_report(void *state, struct sim *s, int rc, struct err *e)
{
    struct grid_tensile_case *c = state;
    struct dpd *d = &c->d;
    struct run *run = s->run;
    struct result *res = &run->result;
    dpd_tensile_curve_report(&c->cv, &c->t, d, run);
    if (c->out_open) {
        c->out_open = 0;
        int rc2 = dpd_output_end(&c->out, run, e);
        if (!rc && !rc2)
            rc2 = final_state_write(run, c->halo, d->p, &d->box, d->step, d->time, e);
        rc = rc ? rc : rc2;
    }
    /* and the grid's */
    result_metric(res, "cell", c->c.m.grid.h, "Å");
    result_metric(res, "grid_nodes", (double)c->c.m.grid.nnodes, "1");
    result_metric(res, "heat_dr", c->c.heat, "eV");
    result_metric(res, "heat_grid", c->c.subgrid_heat, "eV");
    double T = NAN;
    if (d->ufield >= 0) {
        const double *u = d->p->fields[d->ufield].data;
        double sum[2] = {0, (double)c->c.ncarried};
        for (long i = 0; i < c->c.ncarried; i++)
            sum[0] += u[i];
        if (c->halo)
            halo_sum(c->halo, sum, 2);
        if (sum[1] > 0)
            T = sum[0] / sum[1] / (d->set.heat_capacity * UNITS_KB);
    }
    result_metric(res, "internal_temperature", T, "K");
    if (c->halo)
        decomp_record_write(run, c->halo, d->p);
    return rc;
}

static int gt_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct grid_tensile_case *c = state;
    (void)e;
    int rc = dpd_tensile_curve_checkpoint_write(&c->cv, ck);
    if (!rc) rc = dpd_output_checkpoint_write(&c->out, ck);
    return rc;
}

static int gt_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct grid_tensile_case *c = state;
    int rc = dpd_tensile_curve_checkpoint_read(&c->cv, ck, e);
    if (!rc) rc = dpd_output_checkpoint_read(ck, &c->restored_rows, &c->nrestored, e);
    return rc;
}

static const struct sim_case_ops gt_ops = {
    .begin = gt_begin,
    .after_step = gt_after_step,
    .output = gt_output,
    .report = gt_report,
    .checkpoint_write = gt_checkpoint_write,
    .checkpoint_read = gt_checkpoint_read,
};

static int gt_run(void *state, struct run *run, struct err *e)
{
    struct grid_tensile_case *c = state;
    c->d.timers = &run->timers;
    c->c.m.timers = &run->timers;
    int rc = dpd_tensile_curve_init(&c->cv, &c->t, e);
    if (rc)
        return rc;
    c->model = (struct dpd_mpm_model){.c = &c->c, .snapshots = 1};
    struct sim s;
    sim_init(&s, run, c->t.steps, c->d.dt);
    s.case_ops = &gt_ops;
    s.case_state = c;
    rc = sim_add_model(&s, &sim_model_dpd_mpm, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static long gt_particles(const void *state)
{
    const struct grid_tensile_case *c = state;
    return c->d.p ? dpd_nparticles(&c->d) : 0;
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
    .checkpoints = 1,
    .decomposes = 1,
};
