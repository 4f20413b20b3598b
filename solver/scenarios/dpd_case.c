/*
 * dpd_case: DPD or DPDE dynamics of one configuration (`type: dpd`).
 *
 *   system:  see md_system.h (for the coarse-grained crystal: fcc with the
 *            coarse lattice constant, a = 7.23 Å for copper)
 *   dpd:     see dpd_setup.h
 *   output:  output.final_state writes the last state for later cases
 *
 * Uses: the equilibration at 298 K (Berendsen) whose final state the
 * impact and tensile cases start from (Chen 2014 Sec. 4.1.1), and points of
 * the DPD material's own isotherm (periodic crystal at a given lattice
 * constant) to check the MD->DPD fit against.
 *
 * Metrics: particles, pe, ke, internal_energy, etotal (eV); temperature
 * (final) and temperature_mean, pressure_mean, pressure_sem over the second
 * half of the run; density (g/cm^3, periodic boxes); energy_drift
 * (relative change of pe + ke + internal); momentum (amu Å/ps).
 */
#include <math.h>
#include <stdlib.h>

#include "analysis/block_average.h"
#include "core/units.h"
#include "scenarios/dpd_output.h"
#include "scenarios/dpd_setup.h"
#include "input/md_system.h"

struct dpd_case {
    struct dpd d;
    long steps;
};

static int dpd_case_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box;
    struct md_system_info info;
    struct dpd_input in;
    int rc = md_system_read(root, common->seed, &p, &box, &info);
    if (!rc)
        rc = dpd_section_read(root, DPD_ISOTHERMAL, &in);
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        return rc;
    }
    struct dpd_case *c = calloc(1, sizeof *c);
    if (!c) {
        particles_destroy(&p);
        return err_nomem(root->cfg->err, "dpd case");
    }
    c->steps = in.steps;
    rc = dpd_init_velocities(&in, p, common, root->cfg->err);
    if (rc) {
        particles_destroy(&p);
        free(c);
        return rc;
    }
    rc = dpd_build(&in, p, &box, common, root->cfg->err, &c->d);
    if (rc) {
        dpd_free(&c->d);
        free(c);
        return rc;
    }
    *state = c;
    return 0;
}

static int all_periodic(const struct box *b)
{
    return b->bc[0] == BOUNDARY_PERIODIC && b->bc[1] == BOUNDARY_PERIODIC &&
           b->bc[2] == BOUNDARY_PERIODIC;
}

static int dpd_case_run(void *state, struct run *run, struct err *e)
{
    struct dpd_case *c = state;
    struct dpd *d = &c->d;
    d->timers = &run->timers;
    struct dpd_output out;
    int rc = dpd_output_begin(&out, run, e);
    if (rc)
        return rc;
    long nlate = c->steps - c->steps / 2;
    double *plate = malloc((size_t)(nlate > 0 ? nlate : 1) * sizeof *plate);
    double *tlate = malloc((size_t)(nlate > 0 ? nlate : 1) * sizeof *tlate);
    long ns = 0;
    if (!plate || !tlate) {
        free(plate);
        free(tlate);
        return err_nomem(e, "samples");
    }
    d->peratom = run_due(0, c->steps, run->out.snapshot_every);
    rc = dpd_compute_forces(d, e);
    double e0 = dpd_total_energy(d);
    if (!rc)
        rc = dpd_output_step(&out, run, d, c->steps);
    progress_start(&run->progress, stderr, c->steps, d->dt, run->opt.progress && !run->opt.quiet);
    timer_start(&run->timers, TIMER_LOOP);
    for (long s = 1; s <= c->steps && !rc; s++) {
        d->peratom = run_due(s, c->steps, run->out.snapshot_every);
        if ((rc = dpd_step(d, e)))
            break;
        double et = dpd_total_energy(d);
        if (!isfinite(et)) {
            rc = err_set(e, ERR_DIVERGED, "diverged: non-finite energy at step %ld", s);
            break;
        }
        if (s > c->steps / 2 && ns < nlate) {
            double P[6];
            dpd_pressure_tensor(d, P);
            plate[ns] = (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA;
            tlate[ns++] = dpd_temperature(d);
        }
        rc = dpd_output_step(&out, run, d, c->steps);
        progress_update(&run->progress, s);
    }
    timer_stop(&run->timers, TIMER_LOOP);
    progress_finish(&run->progress, d->step);

    struct result *res = &run->result;
    long n = d->p->n_owned;
    double ke = dpd_kinetic_energy(d), u = dpd_internal_energy(d), P[6], mom[3];
    double et = d->epot + ke + u;
    dpd_pressure_tensor(d, P);
    dpd_momentum(d, mom);
    result_metric(res, "particles", (double)n, "1");
    result_metric(res, "pe", d->epot, "eV");
    result_metric(res, "ke", ke, "eV");
    result_metric(res, "internal_energy", u, "eV");
    result_metric(res, "etotal", et, "eV");
    result_metric(res, "energy_drift", (et - e0) / fabs(e0 != 0 ? e0 : 1.0), "1");
    result_metric(res, "temperature", dpd_temperature(d), "K");
    double sem;
    result_metric(res, "temperature_mean", ns ? block_average(tlate, ns, 10, NULL) : NAN, "K");
    double pm = ns ? block_average(plate, ns, 10, &sem) : NAN;
    result_metric(res, "pressure_mean", pm, "GPa");
    result_metric(res, "pressure_sem", ns ? sem : NAN, "GPa");
    if (all_periodic(&d->box))
        result_metric(res, "density",
                      n * d->prm.mass / box_volume(&d->box) * UNITS_AMU_A3_TO_KG_M3 / 1000.0,
                      "g/cm^3");
    result_metric(res, "momentum", sqrt(mom[0] * mom[0] + mom[1] * mom[1] + mom[2] * mom[2]),
                  "amu Å/ps");
    result_metric(res, "neighbor_rebuilds", (double)d->nrebuilds, "1");
    free(plate);
    free(tlate);
    int rc2 = dpd_output_end(&out, run, e);
    if (!rc && !rc2)
        rc2 = run_write_final_state(run, d->p, &d->box, d->step, d->time, e);
    return rc ? rc : rc2;
}

static void dpd_case_destroy(void *state)
{
    struct dpd_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    free(c);
}

static long dpd_case_particles(const void *state)
{
    const struct dpd_case *c = state;
    return c->d.p ? c->d.p->n_owned : 0;
}

static long dpd_case_steps(const void *state)
{
    const struct dpd_case *c = state;
    return c->steps;
}

const struct case_type dpd_case_type = {
    "dpd", "DPD or DPDE dynamics of one configuration (equilibration, isotherm points)",
    dpd_case_read, dpd_case_run, dpd_case_destroy, dpd_case_particles, dpd_case_steps,
    .checkpoints = 0,
};
