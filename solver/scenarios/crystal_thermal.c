/* crystal_thermal: pressure time series of a thermostatted crystal. */
#include "scenarios/crystal_thermal.h"

#include <string.h>

#include "core/elements.h"
#include "core/velocity.h"
#include "engine/models.h"
#include "md/md.h"

struct pressure_samples {
    const struct md *md;
    long equilibrate, every;
    double *P;
    long *n;
};

static int sample_after_step(void *state, struct sim *s, struct err *e)
{
    struct pressure_samples *ps = state;
    long k = s->step - ps->equilibrate;   /* steps into the sampling phase */
    if (k > 0 && k % ps->every == 0) {
        md_pressure_tensor(ps->md, ps->P + 6 * *ps->n);
        (*ps->n)++;
    }
    return 0;
}

int crystal_pressure_md(struct potential *pot, const struct crystal_spec *c, double a,
                        const int (*orient)[3], const double eps[3], const struct crystal_md *run,
                        double *P, long *n, struct err *e)
{
    *n = 0;
    struct lattice l = {c->style, a, {0, 0, 0}, {{0}}};
    if (orient)
        memcpy(l.orient, orient, sizeof l.orient);
    struct particles *p = particles_create(256);
    if (!p)
        return err_nomem(e, "crystal");
    double mass = c->mass > 0 ? c->mass : element_mass(c->element);
    int t = particles_type_index(p, c->element, mass);
    int64_t id = 1;
    long nc[3] = {c->cells, c->cells, c->cells};
    if (lattice_fill(&l, nc, NULL, p, t, &id, e) < 0) {
        particles_destroy(&p);
        return ERR_RUNTIME;
    }
    double cell[3];
    lattice_cell(&l, cell);
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    for (int d = 0; d < 3; d++) {
        double s = 1.0 + (eps ? eps[d] : 0.0);
        b.hi[d] = nc[d] * cell[d] * s;
        for (int i = 0; i < p->n_owned; i++)
            p->x[3 * i + d] *= s;
    }
    int rc = 0;
    if (run->temperature > 0)
        rc = velocity_maxwell(p, run->temperature, run->seed, 1u, e);
    if (rc) {
        particles_destroy(&p);
        return rc;
    }
    /* the md takes ownership of p; the potential stays the caller's */
    struct md md;
    rc = md_init(&md, p, &b, pot, run->dt, 1.0, run->nthreads, e);
    md.thermo.style = THERMOSTAT_LANGEVIN;
    md.thermo.temperature = run->temperature;
    md.thermo.tau = run->tau;
    md.thermo.group_mask = 1u;
    md.seed = run->seed;
    /* two declared phases: equilibrate, then sample every sample_every steps */
    struct pressure_samples ps = {&md, run->equilibrate,
                                  run->sample_every > 0 ? run->sample_every : 1, P, n};
    static const struct sim_case_ops hooks = {.after_step = sample_after_step};
    struct sim s;
    struct md_model model = {.md = &md};
    sim_init_subrun(&s, NULL, 0, run->dt);
    s.case_ops = &hooks;
    s.case_state = &ps;
    if (!rc)
        rc = sim_add_phase(&s, "equilibrate", run->equilibrate, e);
    if (!rc)
        rc = sim_add_phase(&s, "sample", run->sample, e);
    if (!rc)
        rc = sim_add_model(&s, &sim_model_md, &model, e);
    if (!rc)
        rc = sim_run(&s, NULL, e);
    md.pot = NULL;
    md_free(&md);
    return rc;
}
