/*
 * md_case: the generic molecular-dynamics case (`type: md`).
 *
 *   system:    see md_system.h
 *   potential: style + the style's keys (md/potential.h)
 *   md:
 *     timestep: 0.001        ps
 *     steps: 1000
 *     temperature: 0         K, Maxwell-Boltzmann initial velocities (0: at rest)
 *     skin: 1.0              Å, neighbour-list skin
 *     thermostat: {style: none | berendsen | langevin, temperature, tau}
 *     max_energy_change: 1.0 eV/atom: an NVE run whose total energy moves more
 *                            than this has diverged
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
#include "core/units.h"
#include "md/md.h"
#include "core/velocity.h"
#include "scenarios/case_type.h"
#include "scenarios/md_system.h"
#include "scenarios/md_output.h"
#include "scenarios/md_timestep.h"

struct md_case {
    struct md md;
    long steps;
    double temperature;
    double max_de;
};

static int md_case_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box;
    struct md_system_info info;
    int rc = md_system_read(root, common->seed, &p, &box, &info);
    if (rc)
        return rc;
    struct cfg_obj po, mo, to;
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot))) {
        particles_destroy(&p);
        return rc;
    }
    double dt, temperature, skin, max_de;
    long steps;
    struct thermostat th;
    if ((rc = cfg_section(root, "md", &mo)) ||
        (rc = cfg_real(&mo, "timestep", 0.001, CFG_GT(0), &dt)) ||
        (rc = cfg_int(&mo, "steps", 1000, CFG_GE(0), &steps)) ||
        (rc = cfg_real(&mo, "temperature", 0.0, CFG_GE(0), &temperature)) ||
        (rc = cfg_real(&mo, "skin", 1.0, CFG_GT(0), &skin)) ||
        (rc = cfg_real(&mo, "max_energy_change", 1.0, CFG_GT(0), &max_de)) ||
        (rc = cfg_section(&mo, "thermostat", &to)) || (rc = thermostat_read(&to, &th)) ||
        (rc = cfg_close(&mo))) {
        particles_destroy(&p);
        potential_destroy(&pot);
        return rc;
    }
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        return 0;
    }
    struct md_case *c = calloc(1, sizeof *c);
    if (!c) {
        particles_destroy(&p);
        potential_destroy(&pot);
        return err_nomem(root->cfg->err, "md case");
    }
    c->steps = steps;
    c->temperature = temperature;
    c->max_de = max_de;
    struct err *e = root->cfg->err;
    if (temperature > 0) {
        /* masses are needed first: bind the potential's masses */
        if ((rc = potential_bind(pot, p, e)) ||
            (rc = velocity_maxwell(p, temperature, common->seed, 1u, e))) {
            particles_destroy(&p);
            potential_destroy(&pot);
            free(c);
            return rc;
        }
    }
    p->par = common->par;
    /* the key to blame: the skin when it is most of the range, else the
     * potential's file or cutoff */
    const char *rkey = skin > pot->cutoff                ? "md.skin"
                       : pot->source_path[0]             ? "potential.file"
                       : json_object_get(po.node, "cutoff") ? "potential.cutoff"
                                                          : "potential";
    if ((rc = md_check_range(pot, &box, p->n_owned, skin, info.max_particles, root->cfg, rkey))) {
        particles_destroy(&p);
        potential_destroy(&pot);
        free(c);
        return rc;
    }
    rc = md_init(&c->md, p, &box, pot, dt, skin, common->nthreads, e);
    c->md.thermo = th;
    c->md.seed = common->seed;
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

static int md_case_run(void *state, struct run *run, struct err *e)
{
    struct md_case *c = state;
    struct md *md = &c->md;
    md->timers = &run->timers;
    struct md_output mo;
    int rc = md_output_begin(&mo, run, md, e);
    if (rc)
        return rc;
    long natoms = md->p->n_owned;
    double e0 = md->last.energy + md_kinetic_energy(md);
    double tsum = 0;
    long tcount = 0;
    int diverged = 0;
    char why[256] = "";
    /* pressure samples of the second half of the run */
    long nlate = c->steps - c->steps / 2;
    double *plate = malloc((size_t)(nlate > 0 ? nlate : 1) * sizeof *plate);
    long np = 0;
    if (!plate)
        return err_nomem(e, "pressure samples");
    md->peratom = run_due(0, c->steps, run->out.snapshot_every);
    rc = md_compute_forces(md, e);
    if (!rc)
        rc = md_output_step(&mo, run, md, c->steps);
    progress_start(&run->progress, stderr, c->steps, md->dt, run->opt.progress && !run->opt.quiet);
    timer_start(&run->timers, TIMER_LOOP);
    for (long s = 1; s <= c->steps && !rc; s++) {
        md->peratom = run_due(s, c->steps, run->out.snapshot_every);
        rc = md_step(md, e);
        if (rc)
            break;
        double pe = md->last.energy, ke = md_kinetic_energy(md);
        tsum += md_temperature(md);
        tcount++;
        if (!isfinite(pe) || !isfinite(ke)) {
            diverged = 1;
            snprintf(why, sizeof why, "non-finite energy at step %ld", s);
        } else if (md->thermo.style == THERMOSTAT_NONE && fabs(pe + ke - e0) > c->max_de * natoms) {
            diverged = 1;
            snprintf(why, sizeof why,
                     "total energy changed by %.3g eV/atom at step %ld (limit md.max_energy_change "
                     "= %g eV/atom): time step too large?",
                     (pe + ke - e0) / natoms, s, c->max_de);
        }
        if (diverged) {
            rc = err_set(e, ERR_DIVERGED, "diverged: %s", why);
            break;
        }
        if (s > c->steps / 2 && np < nlate) {
            double Ps[6];
            md_pressure_tensor(md, Ps);
            plate[np++] = (Ps[0] + Ps[1] + Ps[2]) / 3.0 * UNITS_EVA3_TO_GPA;
        }
        rc = md_output_step(&mo, run, md, c->steps);
        progress_update(&run->progress, s);
    }
    timer_stop(&run->timers, TIMER_LOOP);
    progress_finish(&run->progress, md->step);
    /* metrics */
    struct result *res = &run->result;
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
    result_metric(res, "atoms", (double)natoms, "1");
    result_metric(res, "pe", pe, "eV");
    result_metric(res, "pe_per_atom", pe / natoms, "eV/atom");
    result_metric(res, "ke", ke, "eV");
    result_metric(res, "etotal", pe + ke, "eV");
    result_metric(res, "temperature", md_temperature(md), "K");
    result_metric(res, "temperature_mean", tcount ? tsum / tcount : md_temperature(md), "K");
    result_metric(res, "energy_drift", (pe + ke - e0) / fabs(e0 != 0 ? e0 : 1.0), "1");
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
    result_metric(res, "density", mass / box_volume(&md->box) * UNITS_AMU_A3_TO_KG_M3 / 1000.0,
                  "g/cm^3");
    double psem;
    double pmean = np ? block_average(plate, np, 10, &psem) : (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA;
    result_metric(res, "pressure_mean", pmean, "GPa");
    result_metric(res, "pressure_sem", np ? psem : NAN, "GPa");
    free(plate);
    result_metric(res, "neighbor_rebuilds", (double)md->nrebuilds, "1");
    int rc2 = md_output_end(&mo, run, e);
    if (!rc && !rc2)
        rc2 = run_write_final_state(run, md->p, &md->box, md->step, md->time, e);
    return rc ? rc : rc2;
}

static void md_case_destroy(void *state)
{
    struct md_case *c = state;
    if (!c)
        return;
    md_free(&c->md);
    free(c);
}

static long md_case_particles(const void *state)
{
    const struct md_case *c = state;
    return c->md.p ? c->md.p->n_owned : 0;
}

static long md_case_steps(const void *state)
{
    const struct md_case *c = state;
    return c->steps;
}

const struct case_type md_case_type = {
    "md", "molecular dynamics of one crystal or configuration (NVE or thermostatted)",
    md_case_read, md_case_run, md_case_destroy, md_case_particles, md_case_steps,
};
