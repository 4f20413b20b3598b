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
#include "core/halo.h"
#include "core/parallel.h"
#include "core/units.h"
#include "core/velocity.h"
#include "engine/models.h"
#include "output/final_state.h"
#include "output/decomp_record.h"
#include "output/dpd_output.h"
#include "scenarios/dpd_setup.h"
#include "input/md_system.h"

struct dpd_case {
    struct dpd d;
    struct halo *halo;           /* bricks (owned), or NULL */
    struct dpd_model model;
    long steps;
    /* the run's accumulators (checkpointed) */
    struct dpd_output out;
    double *plate, *tlate;       /* pressure (GPa) and temperature (K) samples of the
                                  * second half of the run */
    long nlate, ns;
    double *restored_rows;       /* thermo rows read from a checkpoint */
    long nrestored;
};

static void dpd_case_free_halo(struct dpd_case *c)
{
    if (c->halo)
        halo_free(c->halo);
    free(c->halo);
    c->halo = NULL;
}

static int dpd_case_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    struct dpd_input in;
    struct halo *halo = NULL;
    /* the dpd section first: its ranges size the bricks, and under mpirun
     * each rank builds (a lattice) or receives (a file rank 0 read) only
     * its brick's particles */
    int rc = dpd_section_read(root, DPD_ISOTHERMAL, &in);
    struct dpd_split_plan plan = {&in, common, root->cfg, 0};
    struct md_system_split split = {dpd_split_plan_bricks, &plan, 0, common->par, 0};
    if (!rc)
        rc = md_system_read_split(root, common->seed, root->cfg->shallow ? NULL : &split, &p,
                                  &box, &info, &halo);
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        return rc;
    }
    struct dpd_case *c = calloc(1, sizeof *c);
    if (!c) {
        particles_destroy(&p);
        if (halo)
            halo_free(halo);
        free(halo);
        return err_nomem(root->cfg->err, "dpd case");
    }
    c->steps = in.steps;
    c->halo = halo;
    if (halo) {
        p->halo = halo;
        p->par = NULL;   /* no replicated sums: each rank owns its brick */
        /* parallel.balance: the first list build cuts at the particles
         * (its range is the sweep's), balance_every checks again */
        const struct parallel_settings *ps = &common->parallel;
        halo_balance_schedule(halo, ps->balance_every, ps->balance_threshold,
                              ps->balance == BALANCE_SHIFT);
    }
    /* the k-th Maxwell draw to the k-th id of all ranks: the serial
     * velocities (to round-off on bricks, bitwise serially) */
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = in.prm.mass;
    if (in.t_init > 0)
        rc = velocity_maxwell_split(p, in.t_init, common->seed, 1u, halo, root->cfg->err);
    if (rc) {
        particles_destroy(&p);
        dpd_case_free_halo(c);
        free(c);
        return rc;
    }
    rc = dpd_build(&in, p, &box, common, root->cfg->err, &c->d);
    if (rc) {
        dpd_free(&c->d);
        dpd_case_free_halo(c);
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

/* --- the run on the engine (engine/sim.h) --------------------------------- */

static int dpd_case_begin(void *state, struct sim *s, struct err *e)
{
    struct dpd_case *c = state;
    int rc = dpd_output_begin(&c->out, s->run, e);
    if (!rc && s->restarted_from >= 0)
        rc = dpd_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    return rc;
}

static int dpd_case_after_step(void *state, struct sim *s, struct err *e)
{
    (void)e;
    struct dpd_case *c = state;
    struct dpd *d = &c->d;
    if (s->step > c->steps / 2 && c->ns < c->nlate) {
        double P[6];
        dpd_pressure_tensor(d, P);
        c->plate[c->ns] = (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA;
        c->tlate[c->ns++] = dpd_temperature(d);
    }
    return 0;
}

static int dpd_case_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct dpd_case *c = state;
    (void)due;   /* dpd_output_step reads the same schedule */
    int rc = dpd_output_step(&c->out, s->run, &c->d, c->steps);
    return rc ? err_set(e, ERR_RUNTIME, "%s: cannot write the outputs of step %ld",
                        s->run->opt.out_dir, s->step)
              : 0;
}

static int dpd_case_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct dpd_case *c = state;
    struct dpd *d = &c->d;
    struct result *res = &s->run->result;
    long n = dpd_nparticles(d), ns = c->ns;
    double e0 = s->e0[0].total;
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
    result_metric(res, "temperature_mean", ns ? block_average(c->tlate, ns, 10, NULL) : NAN, "K");
    double pm = ns ? block_average(c->plate, ns, 10, &sem) : NAN;
    result_metric(res, "pressure_mean", pm, "GPa");
    result_metric(res, "pressure_sem", ns ? sem : NAN, "GPa");
    if (all_periodic(&d->box))
        result_metric(res, "density",
                      n * d->prm.mass / box_volume(&d->box) * UNITS_AMU_A3_TO_KG_M3 / 1000.0,
                      "g/cm^3");
    result_metric(res, "momentum", sqrt(mom[0] * mom[0] + mom[1] * mom[1] + mom[2] * mom[2]),
                  "amu Å/ps");
    result_metric(res, "neighbor_rebuilds", (double)d->nrebuilds, "1");
    if (c->halo)
        decomp_record_write(s->run, c->halo, d->p);
    int rc = dpd_output_end(&c->out, s->run, e);
    if (!run_rc && !rc) {
        rc = final_state_write(s->run, c->halo, d->p, &d->box, d->step, d->time, e);
    }
    return rc;
}

static int dpd_case_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    (void)e;
    struct dpd_case *c = state;
    int rc = ckpt_put_doubles(ck, "pressure_samples", c->plate, c->ns);
    if (!rc) rc = ckpt_put_doubles(ck, "temperature_samples", c->tlate, c->ns);
    if (!rc) rc = dpd_output_checkpoint_write(&c->out, ck);
    return rc;
}

static int dpd_case_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct dpd_case *c = state;
    long ns = ckpt_len(ck, "pressure_samples");
    int rc = ns < 0 ? ERR_INPUT : 0;
    if (!rc && ns > c->nlate)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld pressure samples, at most %ld fit",
                     ck->path, ns, c->nlate);
    if (!rc) rc = ckpt_get_doubles(ck, "pressure_samples", c->plate, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "temperature_samples", c->tlate, ns);
    if (!rc) {
        c->ns = ns;
        rc = dpd_output_checkpoint_read(ck, &c->restored_rows, &c->nrestored, e);
    }
    return rc;
}

static const struct sim_case_ops dpd_case_ops = {
    .begin = dpd_case_begin,
    .after_step = dpd_case_after_step,
    .output = dpd_case_output,
    .report = dpd_case_report,
    .checkpoint_write = dpd_case_checkpoint_write,
    .checkpoint_read = dpd_case_checkpoint_read,
};

static int dpd_case_run(void *state, struct run *run, struct err *e)
{
    struct dpd_case *c = state;
    struct dpd *d = &c->d;
    d->timers = &run->timers;
    c->nlate = c->steps - c->steps / 2;
    c->plate = malloc((size_t)(c->nlate > 0 ? c->nlate : 1) * sizeof *c->plate);
    c->tlate = malloc((size_t)(c->nlate > 0 ? c->nlate : 1) * sizeof *c->tlate);
    if (!c->plate || !c->tlate)
        return err_nomem(e, "samples");
    c->model = (struct dpd_model){.d = d, .snapshots = 1};
    struct sim s;
    sim_init(&s, run, c->steps, d->dt);
    s.case_ops = &dpd_case_ops;
    s.case_state = c;
    int rc = sim_add_model(&s, &sim_model_dpd, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void dpd_case_destroy(void *state)
{
    struct dpd_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    dpd_case_free_halo(c);
    free(c->plate);
    free(c->tlate);
    free(c->restored_rows);
    free(c);
}

static long dpd_case_particles(const void *state)
{
    const struct dpd_case *c = state;
    return c->d.p ? dpd_nparticles(&c->d) : 0;
}

static long dpd_case_steps(const void *state)
{
    const struct dpd_case *c = state;
    return c->steps;
}

const struct case_type dpd_case_type = {
    "dpd", "DPD or DPDE dynamics of one configuration (equilibration, isotherm points)",
    dpd_case_read, dpd_case_run, dpd_case_destroy, dpd_case_particles, dpd_case_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
