/*
 * mpm_case: the material point method case (`type: mpm`) -- runs MUSL (or
 * USL) steps of the model built by mpm_case_read.c on the engine (the mpm
 * model, engine/model_mpm.c, which owns the CFL time step) and reports, in
 * the case's units: kinetic, strain and total energy and their change,
 * momentum, mass, the time step chosen, reaction forces of rigid bodies, and
 * the kinetic energy at the `report_steps`.  Checkpoints hold the model's
 * state and the run's accumulators (time step range, largest energy
 * changes, kinetic energy at the report steps, thermo rows).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_bricks.h"
#include "mpm/mpm_hgrid.h"
#include "output/decomp_record.h"
#include "scenarios/mpm_case.h"

static int mpm_type_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct mpm_case *c = NULL;
    int rc = mpm_case_read(root, common, &c);
    *state = c;
    return rc;
}

/* --- the run on the engine (engine/sim.h) --------------------------------- */

/* The accumulators of step m->step: time step range, largest energy
 * changes, kinetic energy at the report steps. */
static void accumulate(struct mpm_case *c, const struct sim *s)
{
    const struct mpm *m = &c->m;
    double e0 = c->t0.kinetic + c->t0.strain;
    c->dt_min = fmin(c->dt_min, s->dt);
    c->dt_max = fmax(c->dt_max, s->dt);
    /* energies summed by the kernels: no extra pass over the points */
    double etot = m->ke + m->strain, ecen = mpm_energy_centred(m);
    if (e0 > 0) {
        c->de_max = fmax(c->de_max, fabs(etot - e0) / e0);
        c->dec_max = fmax(c->dec_max, fabs(ecen - e0) / e0);
    }
    for (int k = 0; k < c->nreport; k++)
        if (c->report_steps[k] == m->step)
            c->ke_report[k] = m->ke;
    c->acc_step = s->step;
}

static int mpm_case_begin(void *state, struct sim *s, struct err *e)
{
    struct mpm_case *c = state;
    int rc = mpm_output_begin(&c->out, s->run, c, e);
    if (!rc && s->restarted_from >= 0)
        rc = mpm_output_resume(&c->out, s->run, c->restored_rows, c->nrestored,
                               c->restored_cols, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    return rc;
}

static int mpm_case_after_step(void *state, struct sim *s, struct err *e)
{
    (void)e;
    accumulate(state, s);
    return 0;
}

static int mpm_case_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct mpm_case *c = state;
    int rc = 0;
    if (due & SIM_DUE_THERMO) {
        struct mpm_totals t = c->t0;
        if (s->step > 0)
            mpm_bricks_totals(c->bricks, &c->m, &t);   /* over all ranks on bricks */
        rc = mpm_output_thermo(&c->out, s->run, c, s->dt, &t, e);
    }
    if (!rc && (due & SIM_DUE_SNAPSHOT))
        rc = mpm_output_snapshot(&c->out, s->run, c, e);
    return rc;
}

static int mpm_case_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct mpm_case *c = state;
    struct mpm *m = &c->m;
    const struct mpm_units *u = &c->u;
    (void)run_rc;
    /* a step the engine's divergence check stopped at (the model finished
     * it) still counts in the extremes, as before the engine */
    if (c->acc_step < s->step && m->step == s->step)
        accumulate(c, s);
    const struct mpm_totals t0 = c->t0;
    double e0 = t0.kinetic + t0.strain;
    /* metrics, in the case's units */
    struct mpm_totals t;
    mpm_bricks_totals(c->bricks, m, &t);
    struct result *res = &s->run->result;
    /* bricks: the counts of the serial grid and of all points */
    result_metric(res, "points", (double)c->npoints_total, "1");
    result_metric(res, "nodes", c->bricks ? (double)c->bricks->serial_nodes
                                          : (double)m->grid.nnodes, "1");
    result_metric(res, "steps_done", (double)m->step, "1");
    result_metric(res, "time", m->time / u->time, u->time_name);
    result_metric(res, "timestep", c->dt_first / u->time, u->time_name);
    result_metric(res, "timestep_min", c->dt_min / u->time, u->time_name);
    result_metric(res, "timestep_max", c->dt_max / u->time, u->time_name);
    result_metric(res, "courant_number", c->dt_first / (mpm_grid_min_cell(&m->grid) /
                                                        (m->cmax + t0.vmax)), "1");
    result_metric(res, "wave_speed", m->cmax / u->velocity, u->velocity_name);
    result_metric(res, "mass", t.mass / u->mass, u->mass_name);
    result_metric(res, "ke_initial", t0.kinetic / u->energy, u->energy_name);
    result_metric(res, "ke", t.kinetic / u->energy, u->energy_name);
    result_metric(res, "strain_energy", t.strain / u->energy, u->energy_name);
    result_metric(res, "etotal", (t.kinetic + t.strain) / u->energy, u->energy_name);
    result_metric(res, "energy_change",
                  e0 > 0 ? (t.kinetic + t.strain - e0) / e0 : t.kinetic + t.strain, "1");
    /* largest |kinetic + strain - initial| / initial over all steps, and the
     * same for the time-centred energy (mpm.h), which the explicit step
     * conserves to O(dt^2) while the plain sum oscillates by O(dt) */
    result_metric(res, "energy_change_max", c->de_max, "1");
    result_metric(res, "energy_change_centred_max", c->dec_max, "1");
    for (int d = 0; d < 3; d++) {
        char name[32];
        snprintf(name, sizeof name, "momentum_%c", "xyz"[d]);
        result_metric(res, name, t.momentum[d] / u->momentum, u->momentum_name);
    }
    double dp = 0, pscale = 0;
    for (long i = 0; i < m->pts.n; i++)
        pscale += m->pts.mass[i] * sqrt(m->pts.v[3 * i] * m->pts.v[3 * i] +
                                         m->pts.v[3 * i + 1] * m->pts.v[3 * i + 1] +
                                         m->pts.v[3 * i + 2] * m->pts.v[3 * i + 2]);
    mpm_bricks_sum(c->bricks, &pscale, 1);
    for (int d = 0; d < 3; d++)
        dp += (t.momentum[d] - t0.momentum[d]) * (t.momentum[d] - t0.momentum[d]);
    result_metric(res, "momentum_change", pscale > 0 ? sqrt(dp) / pscale : sqrt(dp), "1");
    result_metric(res, "vmax", t.vmax / u->velocity, u->velocity_name);
    double smax = 0;
    for (long i = 0; i < m->pts.n; i++) {
        const double *sg = m->pts.stress + 6 * i;
        double mean = (sg[0] + sg[1] + sg[2]) / 3;
        double j2 = 0.5 * ((sg[0] - mean) * (sg[0] - mean) + (sg[1] - mean) * (sg[1] - mean) +
                           (sg[2] - mean) * (sg[2] - mean)) +
                    sg[3] * sg[3] + sg[4] * sg[4] + sg[5] * sg[5];
        smax = fmax(smax, sqrt(3 * j2));
    }
    mpm_bricks_max(c->bricks, &smax, 1);
    result_metric(res, "von_mises_max", smax / u->stress, u->stress_name);
    for (int k = 0; k < c->nreport; k++) {
        char name[48];
        snprintf(name, sizeof name, "ke_step_%ld", c->report_steps[k]);
        if (isfinite(c->ke_report[k]))
            result_metric(res, name, c->ke_report[k] / u->energy, u->energy_name);
    }
    /* mass-weighted mean velocity of every deformable body */
    for (int b = 0; b < m->nbody; b++) {
        if (m->body[b].rigid)
            continue;
        double mb = 0, pb[3] = {0, 0, 0};
        for (long i = 0; i < m->pts.n; i++) {
            if (m->pts.body[i] != b)
                continue;
            mb += m->pts.mass[i];
            for (int d = 0; d < 3; d++)
                pb[d] += m->pts.mass[i] * m->pts.v[3 * i + d];
        }
        double sb[4] = {mb, pb[0], pb[1], pb[2]};
        mpm_bricks_sum(c->bricks, sb, 4);
        mb = sb[0];
        memcpy(pb, sb + 1, sizeof pb);
        for (int d = 0; d < 3; d++) {
            char name[64];
            snprintf(name, sizeof name, "%s_velocity_%c", m->body[b].name, "xyz"[d]);
            result_metric(res, name, mb > 0 ? pb[d] / mb / u->velocity : 0, u->velocity_name);
        }
    }
    for (int k = 0; k < c->nprobes; k++) {
        double sg[6], disp[3];
        mpm_probe_means(c, k, sg, disp);
        char name[64];
        snprintf(name, sizeof name, "%s_sxx", c->probe[k].name);
        result_metric(res, name, sg[0] / u->stress, u->stress_name);
        snprintf(name, sizeof name, "%s_ux", c->probe[k].name);
        result_metric(res, name, disp[0] / u->length, u->length_name);
    }
    for (int b = 0; b < m->nbody; b++) {
        if (!m->body[b].rigid)
            continue;
        for (int d = 0; d < 3; d++) {
            char name[64];
            snprintf(name, sizeof name, "%s_force_%c", m->body[b].name, "xyz"[d]);
            result_metric(res, name, m->body[b].reaction[d] / u->force, u->force_name);
        }
    }
    double bytes = mpm_points_bytes_per_point(&m->pts) * (double)m->pts.n +
                   mpm_grid_bytes(&m->grid);
    mpm_bricks_sum(c->bricks, &bytes, 1);   /* bricks: the patches' ghost nodes count */
    long np = c->npoints_total;
    result_metric(res, "model_bytes_per_point", np ? bytes / (double)np : 0, "B");
    if (c->bricks) {
        decomp_record_write_counts(s->run, c->bricks->par, c->bricks->grid, m->pts.n);
        long shared = 0, plans = 0;
        mpm_bricks_shared_counts(c->bricks, &shared, &plans);
        if (c->bricks->shared) {
            decomp_record_add_integer(res, "mpm_shared_nodes_max", shared);
            decomp_record_add_integer(res, "mpm_shared_node_plans", plans);
            decomp_record_add_cell_tables(res, c->bricks->par, m->grid.hg->ncell,
                                          m->grid.hg->ncell_made);
        }
        const struct mpm_bricks *b = c->bricks;
        struct decomp_balance_record bal = {b->balance_every, b->balance_threshold,
                                            b->balance_checks, b->balance_shifts,
                                            b->balance_worst};
        decomp_record_add_balance(res, &bal);
    }
    return mpm_output_end(&c->out, s->run, e);
}

static int mpm_case_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct mpm_case *c = state;
    const struct mpm_totals *t = &c->t0;
    double t0[7] = {t->mass, t->momentum[0], t->momentum[1], t->momentum[2], t->kinetic,
                    t->strain, t->vmax};
    (void)e;
    int rc = ckpt_put_doubles(ck, "initial_totals", t0, 7);
    if (!rc) rc = ckpt_put_double(ck, "dt_first", c->dt_first);
    if (!rc) rc = ckpt_put_double(ck, "dt_min", c->dt_min);
    if (!rc) rc = ckpt_put_double(ck, "dt_max", c->dt_max);
    if (!rc) rc = ckpt_put_double(ck, "energy_change_max", c->de_max);
    if (!rc) rc = ckpt_put_double(ck, "energy_change_centred_max", c->dec_max);
    if (!rc) rc = ckpt_put_doubles(ck, "ke_report", c->ke_report, c->nreport);
    if (!rc) rc = ckpt_put_long(ck, "accumulated_step", c->acc_step);
    if (!rc) rc = ckpt_put_long(ck, "thermo_cols", c->out.ncols);
    if (!rc) rc = ckpt_put_doubles(ck, "thermo_rows", c->out.series, c->out.nrows * c->out.ncols);
    return rc;
}

static int mpm_case_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct mpm_case *c = state;
    double t0[7];
    long cols = 0;
    int rc = ckpt_get_doubles(ck, "initial_totals", t0, 7);
    if (!rc) rc = ckpt_get_double(ck, "dt_first", &c->dt_first);
    if (!rc) rc = ckpt_get_double(ck, "dt_min", &c->dt_min);
    if (!rc) rc = ckpt_get_double(ck, "dt_max", &c->dt_max);
    if (!rc) rc = ckpt_get_double(ck, "energy_change_max", &c->de_max);
    if (!rc) rc = ckpt_get_double(ck, "energy_change_centred_max", &c->dec_max);
    if (!rc) rc = ckpt_get_doubles(ck, "ke_report", c->ke_report, c->nreport);
    if (!rc) rc = ckpt_get_long(ck, "accumulated_step", &c->acc_step);
    if (!rc) rc = ckpt_get_long(ck, "thermo_cols", &cols);
    if (!rc && (cols <= 0 || cols > MPM_OUTPUT_MAX_COLS))
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld thermo columns, at most %d",
                     ck->path, cols, MPM_OUTPUT_MAX_COLS);
    if (!rc)
        rc = ckpt_get_rows(ck, "thermo_rows", (int)cols, &c->restored_rows, &c->nrestored);
    c->restored_cols = cols;
    if (!rc)
        c->t0 = (struct mpm_totals){t0[0], {t0[1], t0[2], t0[3]}, t0[4], t0[5], t0[6]};
    return rc;
}

static const struct sim_case_ops mpm_case_ops = {
    .begin = mpm_case_begin,
    .after_step = mpm_case_after_step,
    .output = mpm_case_output,
    .report = mpm_case_report,
    .checkpoint_write = mpm_case_checkpoint_write,
    .checkpoint_read = mpm_case_checkpoint_read,
};

static int mpm_type_run(void *state, struct run *run, struct err *e)
{
    struct mpm_case *c = state;
    struct mpm *m = &c->m;
    const struct mpm_units *u = &c->u;
    m->timers = &run->timers;
    m->nthreads = run->opt.nthreads > 0 ? run->opt.nthreads : 1;
    c->model = (struct mpm_model){.m = m,
                                  .dt_fixed = c->dt_fixed,
                                  .cfl = c->cfl,
                                  .adaptive = c->adaptive,
                                  .load_ramp = c->load_ramp,
                                  .max_energy_change = c->energy_tolerance,
                                  .bricks = c->bricks};
    /* the accumulators from the state at step 0 (a restart reads them back) */
    mpm_bricks_totals(c->bricks, m, &c->t0);
    double dt = mpm_model_timestep(&c->model);
    c->dt_first = c->dt_min = c->dt_max = dt;
    c->de_max = c->dec_max = 0;
    for (int k = 0; k < c->nreport; k++)
        c->ke_report[k] = c->report_steps[k] == 0 ? c->t0.kinetic : NAN;
    c->acc_step = 0;
    run_log(run,
            "mpm: %ld points, %ld nodes (%s grid, %s), %s; time step %.6g %s from %s "
            "(explicit limit %.6g %s, Courant number %.3g)",
            c->npoints_total, c->bricks ? c->bricks->serial_nodes : m->grid.nnodes,
            m->grid.kind == MPM_GRID_HIER ? "hierarchical" : "uniform",
            m->grid.shape == MPM_SHAPE_GIMP ? "GIMP" : "linear",
            m->algorithm == MPM_MUSL ? "MUSL" : "USL", dt / u->time, u->time_name,
            c->dt_fixed > 0 ? "mpm.timestep" : "the CFL condition", mpm_stable_dt(m) / u->time,
            u->time_name, dt / mpm_stable_dt(m));
    struct sim s;
    sim_init(&s, run, c->steps, dt);
    s.case_ops = &mpm_case_ops;
    s.case_state = c;
    int rc = sim_add_model(&s, &sim_model_mpm, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void mpm_type_destroy(void *state)
{
    mpm_case_free(state);
}

static long mpm_type_particles(const void *state)
{
    const struct mpm_case *c = state;
    return c ? c->npoints_total : 0;
}

static long mpm_type_steps(const void *state)
{
    const struct mpm_case *c = state;
    return c ? c->steps : 0;
}

const struct case_type mpm_case_type = {
    "mpm", "material point method (MUSL/USL, uniform or hierarchical grid)",
    mpm_type_read, mpm_type_run, mpm_type_destroy, mpm_type_particles, mpm_type_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
