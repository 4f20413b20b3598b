/* crystal_thermal: pressure time series of a thermostatted crystal. */
#include "scenarios/crystal_thermal.h"

#include <string.h>

#include "core/elements.h"
#include "core/velocity.h"
#include "md/md.h"

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
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}};
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
    for (long s = 0; s < run->equilibrate && !rc; s++)
        rc = md_step(&md, e);
    long every = run->sample_every > 0 ? run->sample_every : 1;
    for (long s = 1; s <= run->sample && !rc; s++) {
        rc = md_step(&md, e);
        if (!rc && s % every == 0) {
            md_pressure_tensor(&md, P + 6 * *n);
            (*n)++;
        }
    }
    md.pot = NULL;
    md_free(&md);
    return rc;
}
