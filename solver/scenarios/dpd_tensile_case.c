/*
 * dpd_tensile_case: a DPD rod pulled apart by its rigid ends (`type:
 * dpd_tensile`), Chen et al. 2014 Sec. 4.1.2: rod 216 x 72.3 x 72.3 Å, the
 * two ends (15 Å each) rigid and moved apart at 2.169 Å/ps each (strain
 * rate 2 v / L = 0.02/ps); the stress-strain curve from the forces on the
 * rigid ends over the cross-section, and its peak.
 *
 *   system:   the rod (md_system.h): read_data of the equilibrated bar, or a lattice
 *   dpd:      dpd_setup.h (default variant dpde)
 *   tensile:  (dpd_tensile_setup.h)
 *     axis: x                   the rod axis
 *     grip_length: 15.0         Å of material at each end held rigid
 *     velocity: 2.169           Å/ps of each end, outward
 *     lattice_constant: 0       Å for the plane spacing a/2 that sets the rod's length
 *                               and cross-section (0: the parameter file's)
 *     area: 0                   Å^2 cross-section (0: measured, (extent + a/2)^2 per axis)
 *     velocity_ramp: true       start the rod at the homogeneous strain rate: every
 *                               free particle gets v (2 x - x_lo - x_hi) / (x_hi - x_lo)
 *                               along the axis on top of its thermal velocity
 *     sample_every: 20          steps per stress-strain point (forces averaged over them)
 *
 * Strain: engineering, 2 v t / L0 with L0 the rod's length (faces + a/2).
 * Stress: (F_left - F_right) / (2 A) along the axis, F the total force of
 * the rest of the rod on each grip (conservative + dissipative + random),
 * tension positive.
 *
 * Without the velocity ramp the ends start at full speed into a rod at rest
 * and the first picoseconds carry its dynamic response instead: the stress
 * jumps to about rho c v (7 GPa for the paper's rod) and waves cross the
 * rod every 2 L / c.  The ramp (the usual start of constant-strain-rate MD
 * tension) removes that jump, so the peak is the rod's strength.
 *
 * Under mpirun the rod runs on bricks (docs/dpd.md, docs/parallel.md): the
 * particles on the DPD halo's bricks with the cell-colour Shardlow sweep
 * (dpd.sweep: cells, the same order on any rank count), the grips
 * prescribed bodies whose forces and impulses are sums over the ranks
 * (dpd_sweep_cells.c); the final state is written by rank 0 a window at a time.
 *
 * Metrics: peak_stress (GPa), strain_at_peak (1), strain_rate (1/ps),
 * strain_final (1), rod_length (Å), area (Å^2), grip_particles (1).
 * Series: strain, stress (GPa), time_ps.
 */
#include <stdlib.h>

#include "core/halo.h"
#include "engine/models.h"
#include "output/final_state.h"
#include "output/decomp_record.h"
#include "output/dpd_output.h"
#include "scenarios/dpd_tensile_setup.h"

struct tensile_case {
    struct dpd d;
    struct dpd_tensile t;
    struct halo *halo;           /* bricks (owned), or NULL */
    struct dpd_model model;
    /* the run's accumulators (checkpointed) */
    struct dpd_output out;
    struct dpd_tensile_curve cv;
    double *restored_rows;       /* thermo rows read from a checkpoint */
    long nrestored;
};

static int tensile_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct tensile_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "tensile case");
    int rc = dpd_tensile_read(root, common, &c->d, &c->t, &c->halo, 1);
    if (rc || root->cfg->shallow) {
        if (c->halo)
            halo_free(c->halo);
        free(c->halo);
        free(c);
        return rc;
    }
    *state = c;
    return 0;
}

/* --- the run on the engine (engine/sim.h) --------------------------------- */

static int tensile_begin(void *state, struct sim *s, struct err *e)
{
    struct tensile_case *c = state;
    int rc = dpd_output_begin(&c->out, s->run, e);
    if (!rc && s->restarted_from >= 0)
        rc = dpd_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    return rc;
}

static int tensile_after_step(void *state, struct sim *s, struct err *e)
{
    (void)e;
    struct tensile_case *c = state;
    dpd_tensile_curve_add(&c->cv, &c->t, &c->d, s->step == c->t.steps);
    return 0;
}

static int tensile_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct tensile_case *c = state;
    (void)due;   /* dpd_output_step reads the same schedule */
    int rc = dpd_output_step(&c->out, s->run, &c->d, c->t.steps);
    return rc ? err_set(e, ERR_RUNTIME, "%s: cannot write the outputs of step %ld",
                        s->run->opt.out_dir, s->step)
              : 0;
}

static int tensile_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct tensile_case *c = state;
    struct dpd *d = &c->d;
    dpd_tensile_curve_report(&c->cv, &c->t, d, s->run);
    if (c->halo)
        decomp_record_write(s->run, c->halo, d->p);
    int rc = dpd_output_end(&c->out, s->run, e);
    if (!run_rc && !rc) {
        rc = final_state_write(s->run, c->halo, d->p, &d->box, d->step, d->time, e);
    }
    return rc;
}

static int tensile_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    (void)e;
    struct tensile_case *c = state;
    int rc = dpd_tensile_curve_checkpoint_write(&c->cv, ck);
    if (!rc) rc = dpd_output_checkpoint_write(&c->out, ck);
    return rc;
}

static int tensile_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct tensile_case *c = state;
    int rc = dpd_tensile_curve_checkpoint_read(&c->cv, ck, e);
    if (!rc) rc = dpd_output_checkpoint_read(ck, &c->restored_rows, &c->nrestored, e);
    return rc;
}

static const struct sim_case_ops tensile_ops = {
    .begin = tensile_begin,
    .after_step = tensile_after_step,
    .output = tensile_output,
    .report = tensile_report,
    .checkpoint_write = tensile_checkpoint_write,
    .checkpoint_read = tensile_checkpoint_read,
};

static int tensile_run(void *state, struct run *run, struct err *e)
{
    struct tensile_case *c = state;
    c->d.timers = &run->timers;
    int rc = dpd_tensile_curve_init(&c->cv, &c->t, e);
    if (rc)
        return rc;
    c->model = (struct dpd_model){.d = &c->d, .snapshots = 1};
    struct sim s;
    sim_init(&s, run, c->t.steps, c->d.dt);
    s.case_ops = &tensile_ops;
    s.case_state = c;
    rc = sim_add_model(&s, &sim_model_dpd, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void tensile_destroy(void *state)
{
    struct tensile_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    if (c->halo)
        halo_free(c->halo);
    free(c->halo);
    dpd_tensile_curve_free(&c->cv);
    free(c->restored_rows);
    free(c);
}

static long tensile_particles(const void *state)
{
    const struct tensile_case *c = state;
    return c->d.p ? dpd_nparticles(&c->d) : 0;
}

static long tensile_steps(const void *state)
{
    const struct tensile_case *c = state;
    return c->t.steps;
}

const struct case_type dpd_tensile_case_type = {
    "dpd_tensile", "DPD tensile rod pulled by rigid ends: stress-strain curve and peak stress",
    tensile_read, tensile_run, tensile_destroy, tensile_particles, tensile_steps,
    .checkpoints = 1,
    .decomposes = 1,
};
