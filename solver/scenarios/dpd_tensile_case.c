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
 * Metrics: peak_stress (GPa), strain_at_peak (1), strain_rate (1/ps),
 * strain_final (1), rod_length (Å), area (Å^2), grip_particles (1).
 * Series: strain, stress (GPa), time_ps.
 */
#include <stdlib.h>

#include "scenarios/dpd_tensile_setup.h"

struct tensile_case {
    struct dpd d;
    struct dpd_tensile t;
};

static int tensile_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct tensile_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "tensile case");
    int rc = dpd_tensile_read(root, common, &c->d, &c->t);
    if (rc || root->cfg->shallow) {
        free(c);
        return rc;
    }
    *state = c;
    return 0;
}

static int dpd_only_step(void *ctx, struct err *e) { return dpd_step(ctx, e); }

static int tensile_run(void *state, struct run *run, struct err *e)
{
    struct tensile_case *c = state;
    return dpd_tensile_run(&c->d, &c->t, dpd_only_step, &c->d, run, e);
}

static void tensile_destroy(void *state)
{
    struct tensile_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    free(c);
}

static long tensile_particles(const void *state)
{
    const struct tensile_case *c = state;
    return c->d.p ? c->d.p->n_owned : 0;
}

static long tensile_steps(const void *state)
{
    const struct tensile_case *c = state;
    return c->t.steps;
}

const struct case_type dpd_tensile_case_type = {
    "dpd_tensile", "DPD tensile rod pulled by rigid ends: stress-strain curve and peak stress",
    tensile_read, tensile_run, tensile_destroy, tensile_particles, tensile_steps,
    .checkpoints = 0,
};
