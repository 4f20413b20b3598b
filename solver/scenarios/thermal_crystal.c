/* thermal_crystal: thermalised periodic crystals and their zero-pressure lattice constant. */
#include "scenarios/thermal_crystal.h"

#include <math.h>
#include <string.h>

#include "core/elements.h"
#include "core/velocity.h"
#include "engine/models.h"

int thermal_crystal_md(struct md *md, struct potential *pot, const struct thermal_spec *s, double a,
                       const double *scale, struct err *e)
{
    memset(md, 0, sizeof *md);
    struct lattice l = {s->style, a, {0, 0, 0}, {{0}}};
    struct particles *p = particles_create(1024);
    if (!p)
        return err_nomem(e, "crystal");
    int t = particles_type_index(p, s->element, element_mass(s->element));
    int64_t id = 1;
    if (lattice_fill(&l, s->cells, NULL, p, t, &id, e) < 0) {
        particles_destroy(&p);
        return ERR_RUNTIME;
    }
    double cell[3];
    lattice_cell(&l, cell);
    struct box b = {0};
    for (int d = 0; d < 3; d++) {
        double f = scale ? scale[d] : 1.0;
        b.lo[d] = 0;
        b.hi[d] = s->cells[d] * cell[d] * f;
        b.bc[d] = BOUNDARY_PERIODIC;
        for (int i = 0; i < p->n_owned; i++)
            p->x[3 * i + d] *= f;
    }
    int rc = potential_bind(pot, p, e);
    if (!rc && s->temperature > 0)
        rc = velocity_maxwell(p, 2.0 * s->temperature, s->seed, 1u, e);
    if (rc) {
        particles_destroy(&p);
        return rc;
    }
    rc = md_init(md, p, &b, pot, s->dt, s->skin, s->nthreads, e);
    md->seed = s->seed;
    if (s->temperature > 0) {
        md->thermo.style = THERMOSTAT_LANGEVIN;
        md->thermo.temperature = s->temperature;
        md->thermo.tau = s->tau;
        md->thermo.group_mask = 1u;
    }
    return rc;
}

/* The averages of the last navg steps of a thermal run. */
struct thermal_acc {
    const struct md *md;
    long n, navg;
    double acc[6], tacc;
    long cnt;
};

static int thermal_after_step(void *state, struct sim *s, struct err *e)
{
    struct thermal_acc *a = state;
    if (s->step > a->n - a->navg) {
        double Pi[6];
        md_pressure_tensor(a->md, Pi);
        for (int k = 0; k < 6; k++)
            a->acc[k] += Pi[k];
        a->tacc += md_temperature(a->md);
        a->cnt++;
    }
    return 0;
}

int thermal_average(struct md *md, double t_run, double t_avg, double P[6], double *T,
                    struct err *e)
{
    static const struct sim_case_ops hooks = {.after_step = thermal_after_step};
    struct thermal_acc a = {.md = md};
    a.n = (long)llround(t_run / md->dt);
    a.navg = (long)llround(t_avg / md->dt);
    struct sim s;
    sim_init_subrun(&s, NULL, a.n, md->dt);
    struct md_model model = {.md = md};
    s.case_ops = &hooks;
    s.case_state = &a;
    int rc = sim_add_model(&s, &sim_model_md, &model, e);
    if (!rc)
        rc = sim_run(&s, NULL, e);
    if (rc)
        return rc;
    if (a.cnt == 0)
        return err_set(e, ERR_RUNTIME, "thermal average over no steps");
    for (int k = 0; k < 6; k++)
        P[k] = a.acc[k] / a.cnt;
    *T = a.tacc / a.cnt;
    return 0;
}

static int pressure_at(struct potential *pot, const struct thermal_spec *s, double a, double *p,
                       struct err *e)
{
    struct md md;
    double P[6], T;
    int rc = thermal_crystal_md(&md, pot, s, a, NULL, e);
    if (!rc)
        rc = thermal_average(&md, s->t_eq + s->t_avg, s->t_avg, P, &T, e);
    *p = (P[0] + P[1] + P[2]) / 3.0;
    md.pot = NULL;
    md_free(&md);
    return rc;
}

int thermal_lattice_constant(struct potential *pot, const struct thermal_spec *s, double a_guess,
                             double tol, double *a_T, double *p_left, struct err *e)
{
    double a0 = a_guess, a1 = a_guess * 1.003, p0, p1;
    int rc = pressure_at(pot, s, a0, &p0, e);
    if (!rc)
        rc = pressure_at(pot, s, a1, &p1, e);
    if (rc)
        return rc;
    double slope = (p1 - p0) / (a1 - a0);   /* eV/Å^4, negative for a stable crystal */
    if (!(slope < 0))
        return err_set(e, ERR_RUNTIME,
                       "zero-pressure search at %g K: pressure does not fall with the lattice "
                       "constant (%g and %g eV/Å^3 at %g and %g Å)", s->temperature, p0, p1, a0, a1);
    double a = fabs(p1) < fabs(p0) ? a1 : a0, p = fabs(p1) < fabs(p0) ? p1 : p0;
    for (int it = 0; it < 4 && fabs(p) > tol; it++) {
        a -= p / slope;
        if ((rc = pressure_at(pot, s, a, &p, e)))
            return rc;
    }
    *a_T = a;
    *p_left = p;
    return 0;
}
