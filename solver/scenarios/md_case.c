/*
 * md_case: the generic molecular-dynamics case (`type: md`).
 *
 *   system:    see md_system.h
 *   potential: style + the style's keys (md/potential.h)
 *   md:        timestep, steps, temperature, skin, max_energy_change,
 *              thermostat (md/md_settings.h; the shared defaults)
 *
 * A run of 0 steps evaluates energies, forces and the pressure tensor.
 *
 * Besides the final values, result.json has the mean pressure over the
 * second half of the run (the first half is taken as equilibration) with
 * its block-averaged standard error, and the mass density: one point of an
 * isotherm per run (the MD->DPD bridge, Chen 2014 Sec. 2.2).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/block_average.h"
#include "engine/models.h"
#include "core/units.h"
#include "core/halo.h"
#include "md/md.h"
#include "md/md_bricks.h"
#include "md/md_settings.h"
#include "core/velocity.h"
#include "scenarios/case_type.h"
#include "input/md_system.h"
#include "output/final_state.h"
#include "output/md_output.h"
#include "md/md_timestep.h"

struct md_case {
    struct md md;
    struct md_model model;
    long steps;
    double temperature;
    double max_de;
    /* the run's accumulators (checkpointed) */
    struct md_output out;
    double tsum;                 /* temperature summed over the steps */
    long tcount;
    double *plate;               /* pressure samples of the second half (GPa) */
    long nlate, np;
    double *restored_rows;       /* thermo rows read from a checkpoint */
    long nrestored;
    /* least-squares line through the total energy per atom against time
     * (Welford-style running moments: no cancellation over long runs) */
    struct energy_fit {
        double n, mean_t, mean_e, c_te, m2_t, m2_e;
    } fit;
};

static void energy_fit_add(struct energy_fit *f, double t, double e)
{
    f->n += 1.0;
    double dt = t - f->mean_t, de = e - f->mean_e;
    f->mean_t += dt / f->n;
    f->mean_e += de / f->n;
    f->c_te += dt * (e - f->mean_e);
    f->m2_t += dt * (t - f->mean_t);
    f->m2_e += de * (e - f->mean_e);
}

static double md_case_energy_per_atom(const struct md *md)
{
    long n = md_natoms(md) > 0 ? md_natoms(md) : 1;
    return (md->last.energy + md_kinetic_energy(md)) / (double)n;
}

/* The decomposition of the box the system builder has just sized
 * (md_system_split): bricks under mpirun (md/md_bricks.h). */
struct md_case_plan {
    const struct case_common *common;
    double range;
    struct cfg *cfg;
};

static int md_case_plan_bricks(void *ctx, const struct box *b, struct halo **out)
{
    const struct md_case_plan *pl = ctx;
    return md_bricks_plan(pl->common->par, &pl->common->parallel, b, pl->range, pl->cfg, out);
}

static int md_case_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    /* the potential and the skin first: the interaction range sizes the
     * bricks, and under mpirun each rank builds only its brick's atoms */
    struct cfg_obj po;
    struct potential *pot = NULL;
    int rc;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot)))
        return rc;
    struct md_settings ms;
    if ((rc = md_settings_read(root,
                               MD_KEY_TIMESTEP | MD_KEY_STEPS | MD_KEY_TEMPERATURE | MD_KEY_SKIN |
                                   MD_KEY_MAX_ENERGY_CHANGE | MD_KEY_THERMOSTAT,
                               &md_settings_defaults, &ms))) {
        potential_destroy(&pot);
        return rc;
    }
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    struct halo *halo = NULL;
    struct md_case_plan plan = {common, pot ? pot->cutoff + ms.skin : 0.0, root->cfg};
    struct md_system_split split = {md_case_plan_bricks, &plan, 1, common->par, 0};
    rc = md_system_read_split(root, common->seed, &split, &p, &box, &info, &halo);
    if (rc || root->cfg->shallow) {
        potential_destroy(&pot);
        return rc;
    }
    struct md_case *c = calloc(1, sizeof *c);
    struct err *e = root->cfg->err;
    if (!c)
        rc = err_nomem(e, "md case");
    /* bricks: from here on p holds this rank's atoms (md_adopt), and every
     * step below is collective */
    if (c && halo)
        md_adopt(&c->md, p, halo);
    /* the impact geometry puts the atoms unevenly: move the cuts */
    if (c && halo && common->parallel.balance == BALANCE_SHIFT)
        rc = halo_balance(halo, &box, p, plan.range, e);
    if (c) {
        c->steps = ms.steps;
        c->temperature = ms.temperature;
        c->max_de = ms.max_energy_change;
    }
    if (!rc && ms.temperature > 0) {
        /* masses are needed first: bind the potential's masses */
        if (!(rc = potential_bind(pot, p, e)))
            rc = velocity_maxwell_split(p, ms.temperature, common->seed, 1u, halo, e);
    }
    if (!rc && !halo)
        p->par = common->par;
    /* the key to blame: the skin when it is most of the range, else the
     * potential's file or cutoff */
    const char *rkey = ms.skin > pot->cutoff                  ? "md.skin"
                       : pot->source_path[0]               ? "potential.file"
                       : json_object_get(po.node, "cutoff") ? "potential.cutoff"
                                                            : "potential";
    if (!rc)
        rc = md_check_range(pot, &box, info.natoms, ms.skin, info.max_particles, root->cfg,
                            rkey);
    if (rc) {
        particles_destroy(&p);
        if (c && halo) {
            md_free(&c->md);   /* adopted the halo */
        } else if (halo) {
            halo_free(halo);
            free(halo);
        }
        potential_destroy(&pot);
        free(c);
        return rc;
    }
    rc = md_init(&c->md, p, &box, pot, ms.timestep, ms.skin, common->nthreads, e);
    c->md.thermo = ms.thermostat;
    c->md.seed = common->seed;
    if (!rc && c->md.halo && common->parallel.balance_every > 0)
        halo_balance_schedule(c->md.halo, common->parallel.balance_every,
                              common->parallel.balance_threshold, 0);
    if (!rc)
        rc = md_check_timestep(&c->md, root->cfg, "md.timestep");
    if (rc) {
        md_free(&c->md);
        free(c);
        return rc;
    }
    *state = c;
    return 0;
}

/* --- the run on the engine (engine/sim.h) --------------------------------- */

static int md_case_begin(void *state, struct sim *s, struct err *e)
{
    struct md_case *c = state;
    if (s->restarted_from < 0)
        energy_fit_add(&c->fit, c->md.time, md_case_energy_per_atom(&c->md));
    int rc = md_output_begin(&c->out, s->run, &c->md, e);
    if (!rc && s->restarted_from >= 0)
        rc = md_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    return rc;
}

static int md_case_after_step(void *state, struct sim *s, struct err *e)
{
    struct md_case *c = state;
    struct md *md = &c->md;
    /* one pass over the atoms for the kinetic energy of both accumulators */
    double ke = md_kinetic_energy(md);
    long n = md_natoms(md) > 0 ? md_natoms(md) : 1;
    c->tsum += md_temperature_of(md, ke);
    c->tcount++;
    energy_fit_add(&c->fit, md->time, (md->last.energy + ke) / (double)n);
    /* pressure samples of the second half of the run */
    if (s->step > c->steps / 2 && c->np < c->nlate) {
        double Ps[6];
        md_pressure_tensor(md, Ps);
        c->plate[c->np++] = (Ps[0] + Ps[1] + Ps[2]) / 3.0 * UNITS_EVA3_TO_GPA;
    }
    return 0;
}

static int md_case_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct md_case *c = state;
    (void)due;   /* md_output_step reads the same schedule */
    int rc = md_output_step(&c->out, s->run, &c->md, c->steps);
    return rc ? err_set(e, ERR_RUNTIME, "step %ld: %s", s->step, c->out.err.msg) : 0;
}

static int md_case_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct md_case *c = state;
    struct md *md = &c->md;
    struct result *res = &s->run->result;
    long natoms = md_natoms(md);
    double e0 = s->e0[0].total;
    double pe = md->last.energy, ke = md_kinetic_energy(md), P[6], mom[3];
    md_pressure_tensor(md, P);
    md_momentum(md, mom);
    double fmax = 0;
    for (int i = 0; i < md->p->n_owned; i++) {
        const double *f = md->p->f + 3 * i;
        double fm = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        if (fm > fmax)
            fmax = fm;
    }
    if (md->halo)
        halo_max(md->halo, &fmax, 1);
    result_metric(res, "atoms", (double)natoms, "1");
    result_metric(res, "pe", pe, "eV");
    result_metric(res, "pe_per_atom", pe / natoms, "eV/atom");
    result_metric(res, "ke", ke, "eV");
    result_metric(res, "etotal", pe + ke, "eV");
    result_metric(res, "temperature", md_temperature(md), "K");
    result_metric(res, "temperature_mean", c->tcount ? c->tsum / c->tcount : md_temperature(md),
                  "K");
    result_metric(res, "energy_drift", (pe + ke - e0) / fabs(e0 != 0 ? e0 : 1.0), "1");
    /* the drift as a rate: slope of the fitted line, and the fluctuation
     * about it (RMS), both per atom; the end-point difference above mixes
     * the two */
    const struct energy_fit *f = &c->fit;
    double slope = f->n > 1 && f->m2_t > 0 ? f->c_te / f->m2_t : 0.0;
    double resid = f->n > 1 ? (f->m2_e - slope * f->c_te) / f->n : 0.0;
    result_metric(res, "energy_drift_rate", slope, "eV/atom/ps");
    result_metric(res, "energy_fluctuation", sqrt(resid > 0 ? resid : 0.0), "eV/atom");
    result_metric(res, "pressure", (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA, "GPa");
    const char *pn[6] = {"pxx", "pyy", "pzz", "pxy", "pxz", "pyz"};
    for (int k = 0; k < 6; k++)
        result_metric(res, pn[k], P[k] * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(res, "max_force", fmax, "eV/Å");
    result_metric(res, "momentum", sqrt(mom[0] * mom[0] + mom[1] * mom[1] + mom[2] * mom[2]),
                  "amu Å/ps");
    result_metric(res, "volume", box_volume(&md->box), "Å^3");
    double mass = 0;
    for (int i = 0; i < md->p->n_owned; i++)
        mass += md->p->mass[md->p->type[i]];
    if (md->halo)
        halo_sum(md->halo, &mass, 1);
    result_metric(res, "density", mass / box_volume(&md->box) * UNITS_AMU_A3_TO_KG_M3 / 1000.0,
                  "g/cm^3");
    double psem;
    double pmean = c->np ? block_average(c->plate, c->np, 10, &psem)
                         : (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA;
    result_metric(res, "pressure_mean", pmean, "GPa");
    result_metric(res, "pressure_sem", c->np ? psem : NAN, "GPa");
    result_metric(res, "neighbor_rebuilds", (double)md->nrebuilds, "1");
    if (md->halo)
        md_output_decomposition(s->run, md);
    int rc = md_output_end(&c->out, s->run, e);
    if (md->halo)   /* rank 0 wrote: all ranks or none go on to the final state */
        rc = halo_agree(md->halo, rc, e);
    if (!run_rc && !rc)
        rc = final_state_write(s->run, md->halo, md->p, &md->box, md->step, md->time, e);
    return rc;
}

static int md_case_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct md_case *c = state;
    int rc = ckpt_put_double(ck, "temperature_sum", c->tsum);
    if (!rc) rc = ckpt_put_long(ck, "temperature_count", c->tcount);
    if (!rc) rc = ckpt_put_doubles(ck, "pressure_samples", c->plate, c->np);
    if (!rc) rc = ckpt_put_doubles(ck, "energy_fit", &c->fit.n, 6);
    if (!rc) rc = ckpt_put_doubles(ck, "thermo_rows", c->out.series, c->out.nrows * MD_THERMO_COLS);
    return rc;
}

static int md_case_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct md_case *c = state;
    int rc = ckpt_get_double(ck, "temperature_sum", &c->tsum);
    if (!rc) rc = ckpt_get_long(ck, "temperature_count", &c->tcount);
    if (!rc) rc = ckpt_get_doubles(ck, "energy_fit", &c->fit.n, 6);
    long np = rc ? -1 : ckpt_len(ck, "pressure_samples");
    if (!rc && (np < 0 || np > c->nlate))
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld pressure samples, at most %ld fit",
                     ck->path, np, c->nlate);
    if (!rc) {
        c->np = np;
        rc = ckpt_get_doubles(ck, "pressure_samples", c->plate, np);
    }
    if (!rc)
        rc = ckpt_get_rows(ck, "thermo_rows", MD_THERMO_COLS, &c->restored_rows, &c->nrestored);
    return rc;
}

static const struct sim_case_ops md_case_ops = {
    .begin = md_case_begin,
    .after_step = md_case_after_step,
    .output = md_case_output,
    .report = md_case_report,
    .checkpoint_write = md_case_checkpoint_write,
    .checkpoint_read = md_case_checkpoint_read,
};

static int md_case_run(void *state, struct run *run, struct err *e)
{
    struct md_case *c = state;
    c->md.timers = &run->timers;
    c->nlate = c->steps - c->steps / 2;
    c->plate = malloc((size_t)(c->nlate > 0 ? c->nlate : 1) * sizeof *c->plate);
    if (!c->plate)
        return err_nomem(e, "pressure samples");
    c->model = (struct md_model){.md = &c->md, .max_energy_change = c->max_de};
    struct sim s;
    sim_init(&s, run, c->steps, c->md.dt);
    s.case_ops = &md_case_ops;
    s.case_state = c;
    int rc = sim_add_model(&s, &sim_model_md, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void md_case_destroy(void *state)
{
    struct md_case *c = state;
    if (!c)
        return;
    md_free(&c->md);
    free(c->plate);
    free(c->restored_rows);
    free(c);
}

static long md_case_particles(const void *state)
{
    const struct md_case *c = state;
    return c->md.p ? md_natoms(&c->md) : 0;
}

static long md_case_steps(const void *state)
{
    const struct md_case *c = state;
    return c->steps;
}

const struct case_type md_case_type = {
    "md", "molecular dynamics of one crystal or configuration (NVE or thermostatted)",
    md_case_read, md_case_run, md_case_destroy, md_case_particles, md_case_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
