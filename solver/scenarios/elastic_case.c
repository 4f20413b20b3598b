/*
 * elastic_case: cubic elastic constants at a temperature from MD
 * (`type: elastic`), by finite-strain averages -- the constants the MPM
 * side of the MPM/MD handshake needs when the MD region is not at 0 K
 * (Guo & Yang 2005, section 2.2: the constants "can be derived from the
 * atomic potential and then are used in the MPM region").
 *
 *   crystal:  {lattice: fcc, element: Cu, a_min: 3.5, a_max: 3.7, cells: 4}
 *   potential: {...}
 *   elastic:
 *     temperature: 300     K
 *     strain: 0.01         amplitude of the +- strains
 *     timestep: 0.002      ps
 *     tau: 0.5             ps, Langevin damping time
 *     equilibrate: 2000    steps before each average
 *     sample: 6000         steps averaged (a pressure sample every 5)
 *     lattice_iterations: 3
 *     repeats: 1           independent runs (other velocities) per strain
 *
 * The computation (a0, a(T) by pressure iterations, C11/C12 from +-strains
 * along [100], C44 from +-strains along [110], the errors) is
 * elastic_thermal.h's, shared with handshake_thermal's `from_potential`.
 */
#include <math.h>
#include <stdlib.h>

#include "core/units.h"
#include "scenarios/case_type.h"
#include "scenarios/crystal_range.h"
#include "scenarios/elastic_thermal.h"

struct elastic_case {
    struct potential *pot;
    struct crystal_spec spec;
    char element[16];
    double a_min, a_max;
    struct elastic_thermal_settings set;
};

static int elastic_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    static const char *const cubic[] = {"sc", "bcc", "fcc", "diamond", NULL};
    struct cfg_obj co, po, eo;
    int style, rc;
    const char *element;
    long cells;
    double amin, amax;
    struct elastic_thermal_settings set = {0};
    if ((rc = cfg_section_required(root, "crystal", &co)) ||
        (rc = cfg_enum(&co, "lattice", "fcc", cubic, &style)) ||
        (rc = cfg_string(&co, "element", NULL, &element)) ||
        (rc = cfg_real(&co, "a_min", CFG_REQUIRED, CFG_GT(0), &amin)) ||
        (rc = cfg_real(&co, "a_max", CFG_REQUIRED, CFG_GT(0), &amax)) ||
        (rc = cfg_int(&co, "cells", 4, CFG_RANGE(2, 20), &cells)) || (rc = cfg_close(&co)))
        return rc;
    if (!(amax > amin))
        return cfg_error_at(co.cfg, "crystal.a_max", "a_max = %g must exceed a_min = %g", amax,
                            amin);
    if ((rc = cfg_section(root, "elastic", &eo)) || (rc = elastic_thermal_read(&eo, 1, &set)) ||
        (rc = cfg_close(&eo)))
        return rc;
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot)))
        return rc;
    struct crystal_spec smallest = {(enum lattice_style)style, element, 0, cells};
    /* the skin of the MD the case runs (crystal_thermal.c: 1.0 Å) */
    if (!root->cfg->shallow &&
        (rc = crystal_check_range(root, &po, pot, &smallest, amin, 1.0))) {
        potential_destroy(&pot);
        return rc;
    }
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        return 0;
    }
    struct elastic_case *c = calloc(1, sizeof *c);
    if (!c) {
        potential_destroy(&pot);
        return err_nomem(root->cfg->err, "elastic case");
    }
    snprintf(c->element, sizeof c->element, "%s", element);
    c->pot = pot;
    c->spec.style = (enum lattice_style)style;
    c->spec.element = c->element;
    c->spec.cells = cells;
    c->a_min = amin;
    c->a_max = amax;
    c->set = set;
    c->set.md.seed = common->seed;
    c->set.md.nthreads = common->nthreads;
    *state = c;
    return 0;
}

static int elastic_run(void *state, struct run *run, struct err *e)
{
    struct elastic_case *c = state;
    const double G = UNITS_EVA3_TO_GPA;
    struct elastic_thermal r0;
    timer_start(&run->timers, TIMER_LOOP);
    int rc = elastic_thermal_compute(c->pot, &c->spec, c->a_min, c->a_max, &c->set, run, &r0, e);
    timer_stop(&run->timers, TIMER_LOOP);
    if (rc)
        return rc;
    const double *C = r0.c, *Ce = r0.c_err, *c0 = r0.c0;
    struct result *r = &run->result;
    result_metric(r, "temperature", c->set.md.temperature, "K");
    result_metric(r, "lattice_constant", r0.a, "Å");
    result_metric(r, "lattice_constant_0K", r0.a0, "Å");
    result_metric(r, "thermal_expansion", r0.a / r0.a0 - 1, "1");
    result_metric(r, "pressure_last_iteration", r0.p_mean * G, "GPa");
    result_metric(r, "pressure_last_iteration_err", r0.p_err * G, "GPa");
    result_metric(r, "c11", C[0] * G, "GPa");
    result_metric(r, "c12", C[1] * G, "GPa");
    result_metric(r, "c44", C[2] * G, "GPa");
    result_metric(r, "c11_err", Ce[0] * G, "GPa");
    result_metric(r, "c12_err", Ce[1] * G, "GPa");
    result_metric(r, "c44_err", Ce[2] * G, "GPa");
    result_metric(r, "bulk_modulus", (C[0] + 2 * C[1]) / 3 * G, "GPa");
    result_metric(r, "c11_0K", c0[0] * G, "GPa");
    result_metric(r, "c12_0K", c0[1] * G, "GPa");
    result_metric(r, "c44_0K", c0[2] * G, "GPa");
    run_log(run,
            "elastic at %g K: a = %.5f Å, C11 = %.1f +- %.1f, C12 = %.1f +- %.1f, C44 = %.1f +- "
            "%.1f GPa (0 K: %.1f, %.1f, %.1f)",
            c->set.md.temperature, r0.a, C[0] * G, Ce[0] * G, C[1] * G, Ce[1] * G, C[2] * G,
            Ce[2] * G, c0[0] * G, c0[1] * G, c0[2] * G);
    return 0;
}

static void elastic_destroy(void *state)
{
    struct elastic_case *c = state;
    if (!c)
        return;
    potential_destroy(&c->pot);
    free(c);
}

static long elastic_particles(const void *state)
{
    const struct elastic_case *c = state;
    if (!c)
        return 0;
    struct lattice l = {c->spec.style, 1.0, {0, 0, 0}, {{0}}};
    double basis[8][3];
    long n = c->spec.cells;
    return lattice_basis(&l, basis) * n * n * n;
}

static long elastic_steps(const void *state)
{
    const struct elastic_case *c = state;
    if (!c)
        return 0;
    return elastic_thermal_steps(&c->set);
}

const struct case_type elastic_case_type = {
    "elastic",
    "cubic elastic constants at a temperature from MD finite-strain averages (for the MPM side "
    "of the handshake)",
    elastic_read, elastic_run, elastic_destroy, elastic_particles, elastic_steps,
    .checkpoints = 0,
};
