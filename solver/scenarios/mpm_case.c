/*
 * mpm_case: the material point method case (`type: mpm`) -- runs MUSL (or
 * USL) steps of the model built by mpm_case_read.c and reports, in the
 * case's units: kinetic, strain and total energy and their change, momentum,
 * mass, the time step chosen, reaction forces of rigid bodies, and the
 * kinetic energy at the `report_steps`.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "scenarios/mpm_case.h"

static int mpm_type_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct mpm_case *c = NULL;
    int rc = mpm_case_read(root, common, &c);
    *state = c;
    return rc;
}

static double case_dt(const struct mpm_case *c)
{
    return c->dt_fixed > 0 ? c->dt_fixed : c->cfl * mpm_stable_dt(&c->m);
}

static int mpm_type_run(void *state, struct run *run, struct err *e)
{
    struct mpm_case *c = state;
    struct mpm *m = &c->m;
    const struct mpm_units *u = &c->u;
    m->timers = &run->timers;
    m->nthreads = run->opt.nthreads > 0 ? run->opt.nthreads : 1;
    struct mpm_output *mo = calloc(1, sizeof *mo);
    if (!mo)
        return err_nomem(e, "mpm output");
    int rc = mpm_output_begin(mo, run, c, e);
    if (rc) {
        free(mo);
        return rc;
    }
    struct mpm_totals t0, t;
    mpm_totals(m, &t0);
    double e0 = t0.kinetic + t0.strain;
    double dt = case_dt(c);
    double dt_first = dt, dt_min = dt, dt_max = dt, de_max = 0, dec_max = 0;
    /* energy is conserved only without driving or damping: no rigid body,
     * load or damping, no fixed or sliding face; only then is a large
     * energy change a sign of divergence */
    int closed = !m->pts.fext && m->damping == 0 && m->grid.nbc == 0;
    for (int b = 0; b < m->nbody; b++)
        closed &= !m->body[b].rigid;
    run_log(run,
            "mpm: %ld points, %ld nodes (%s grid, %s), %s; time step %.6g %s from %s "
            "(explicit limit %.6g %s, Courant number %.3g)",
            m->pts.n, m->grid.nnodes, m->grid.kind == MPM_GRID_HIER ? "hierarchical" : "uniform",
            m->grid.shape == MPM_SHAPE_GIMP ? "GIMP" : "linear",
            m->algorithm == MPM_MUSL ? "MUSL" : "USL", dt / u->time, u->time_name,
            c->dt_fixed > 0 ? "mpm.timestep" : "the CFL condition", mpm_stable_dt(m) / u->time,
            u->time_name, dt / mpm_stable_dt(m));
    timer_start(&run->timers, TIMER_OUTPUT);
    if (run_due(0, c->steps, run->out.thermo_every))
        rc = mpm_output_thermo(mo, run, c, dt, &t0, e);
    if (!rc && run_due(0, c->steps, run->out.snapshot_every))
        rc = mpm_output_snapshot(mo, run, c, e);
    timer_stop(&run->timers, TIMER_OUTPUT);
    double ke_report[MPM_CASE_MAX_REPORT];
    for (int k = 0; k < c->nreport; k++)
        ke_report[k] = c->report_steps[k] == 0 ? t0.kinetic : NAN;
    progress_start(&run->progress, stderr, c->steps, dt, run->opt.progress && !run->opt.quiet);
    for (long s = 1; s <= c->steps && !rc; s++) {
        timer_start(&run->timers, TIMER_LOOP);
        if (c->adaptive && c->dt_fixed <= 0)
            dt = case_dt(c);   /* CFL with the current largest speed */
        m->fext_scale = c->load_ramp > 0 ? fmin(1.0, (m->time + dt) / c->load_ramp) : 1.0;
        rc = mpm_step(m, dt, e);
        timer_stop(&run->timers, TIMER_LOOP);
        if (rc)
            break;
        dt_min = fmin(dt_min, dt);
        dt_max = fmax(dt_max, dt);
        /* energies summed by the kernels: no extra pass over the points */
        double etot = m->ke + m->strain, ecen = mpm_energy_centred(m);
        if (e0 > 0) {
            de_max = fmax(de_max, fabs(etot - e0) / e0);
            dec_max = fmax(dec_max, fabs(ecen - e0) / e0);
        }
        if (!isfinite(etot))
            rc = err_set(e, ERR_DIVERGED, "diverged: non-finite energy at step %ld", s);
        else if (closed && c->energy_tolerance > 0 && e0 > 0 &&
                 fabs(etot - e0) > c->energy_tolerance * e0)
            rc = err_set(e, ERR_DIVERGED,
                         "diverged: total energy changed by %.3g%% at step %ld (limit "
                         "mpm.max_energy_change = %g): time step too large?",
                         100 * (etot - e0) / e0, s, c->energy_tolerance);
        for (int k = 0; k < c->nreport; k++)
            if (c->report_steps[k] == s)
                ke_report[k] = m->ke;
        if (!rc && run_due(s, c->steps, run->out.thermo_every)) {
            timer_start(&run->timers, TIMER_OUTPUT);
            mpm_totals(m, &t);
            rc = mpm_output_thermo(mo, run, c, dt, &t, e);
            timer_stop(&run->timers, TIMER_OUTPUT);
        }
        if (!rc && run_due(s, c->steps, run->out.snapshot_every)) {
            timer_start(&run->timers, TIMER_OUTPUT);
            rc = mpm_output_snapshot(mo, run, c, e);
            timer_stop(&run->timers, TIMER_OUTPUT);
        }
        progress_update(&run->progress, s);
    }
    progress_finish(&run->progress, m->step);
    /* metrics, in the case's units */
    mpm_totals(m, &t);
    struct result *res = &run->result;
    result_metric(res, "points", (double)m->pts.n, "1");
    result_metric(res, "nodes", (double)m->grid.nnodes, "1");
    result_metric(res, "steps_done", (double)m->step, "1");
    result_metric(res, "time", m->time / u->time, u->time_name);
    result_metric(res, "timestep", dt_first / u->time, u->time_name);
    result_metric(res, "timestep_min", dt_min / u->time, u->time_name);
    result_metric(res, "timestep_max", dt_max / u->time, u->time_name);
    result_metric(res, "courant_number", dt_first / (mpm_grid_min_cell(&m->grid) /
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
    result_metric(res, "energy_change_max", de_max, "1");
    result_metric(res, "energy_change_centred_max", dec_max, "1");
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
    result_metric(res, "von_mises_max", smax / u->stress, u->stress_name);
    for (int k = 0; k < c->nreport; k++) {
        char name[48];
        snprintf(name, sizeof name, "ke_step_%ld", c->report_steps[k]);
        if (isfinite(ke_report[k]))
            result_metric(res, name, ke_report[k] / u->energy, u->energy_name);
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
    result_metric(res, "model_bytes_per_point", m->pts.n ? bytes / (double)m->pts.n : 0, "B");
    int rc2 = mpm_output_end(mo, run, e);
    free(mo);
    return rc ? rc : rc2;
}

static void mpm_type_destroy(void *state)
{
    mpm_case_free(state);
}

static long mpm_type_particles(const void *state)
{
    const struct mpm_case *c = state;
    return c ? c->m.pts.n : 0;
}

static long mpm_type_steps(const void *state)
{
    const struct mpm_case *c = state;
    return c ? c->steps : 0;
}

const struct case_type mpm_case_type = {
    "mpm", "material point method (MUSL/USL, uniform or hierarchical grid)",
    mpm_type_read, mpm_type_run, mpm_type_destroy, mpm_type_particles, mpm_type_steps,
    .checkpoints = 0,
};
