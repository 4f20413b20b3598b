/*
 * crystal_case: zero-temperature crystal properties of a potential
 * (`type: crystal`): equilibrium lattice constant, cohesive energy and, for
 * cubic lattices, the elastic constants C11, C12, C44 and the bulk modulus.
 * The MPM side of the MPM/MD handshake and the DPD/MPM coupling take their
 * elastic constants from here, never from hand-tuned numbers.
 *
 *   crystal:
 *     lattice: fcc          # sc | bcc | fcc | diamond
 *     element: Cu
 *     a_min: 3.3            # Å: search interval for the lattice constant
 *     a_max: 3.9
 *     cells: 2              # periodic repeats of the cubic cell
 *   potential: {...}
 */
#include <math.h>
#include <stdlib.h>

#include "core/units.h"
#include "md/crystal.h"
#include "scenarios/crystal_range.h"
#include "scenarios/case_type.h"

struct crystal_case {
    struct potential *pot;
    struct crystal_spec spec;
    double a_min, a_max;
    char element[16];
};

static int crystal_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    static const char *const cubic[] = {"sc", "bcc", "fcc", "diamond", NULL};
    struct cfg_obj co, po;
    int style, rc;
    const char *element;
    long cells;
    double amin, amax;
    if ((rc = cfg_section_required(root, "crystal", &co)) ||
        (rc = cfg_enum(&co, "lattice", "fcc", cubic, &style)) ||
        (rc = cfg_string(&co, "element", NULL, &element)) ||
        (rc = cfg_real(&co, "a_min", CFG_REQUIRED, CFG_GT(0), &amin)) ||
        (rc = cfg_real(&co, "a_max", CFG_REQUIRED, CFG_GT(0), &amax)) ||
        (rc = cfg_int(&co, "cells", 2, CFG_RANGE(1, 20), &cells)) || (rc = cfg_close(&co)))
        return rc;
    if (!(amax > amin))
        return cfg_error_at(co.cfg, "crystal.a_max", "a_max = %g must exceed a_min = %g", amax,
                            amin);
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot)))
        return rc;
    struct crystal_spec smallest = {(enum lattice_style)style, element, 0, cells};
    /* the skin of the MD the case runs (crystal.c: 0.5 Å) */
    if (!root->cfg->shallow &&
        (rc = crystal_check_range(root, &po, pot, &smallest, amin, 0.5))) {
        potential_destroy(&pot);
        return rc;
    }
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        return 0;
    }
    struct crystal_case *c = calloc(1, sizeof *c);
    if (!c) {
        potential_destroy(&pot);
        return err_nomem(root->cfg->err, "crystal case");
    }
    snprintf(c->element, sizeof c->element, "%s", element);
    c->pot = pot;
    c->spec.style = (enum lattice_style)style;
    c->spec.element = c->element;
    c->spec.cells = cells;
    c->a_min = amin;
    c->a_max = amax;
    (void)common;
    *state = c;
    return 0;
}

static int crystal_run(void *state, struct run *run, struct err *e)
{
    struct crystal_case *c = state;
    double a0, ec;
    int rc = crystal_equilibrium(c->pot, &c->spec, c->a_min, c->a_max, &a0, &ec, e);
    if (rc)
        return rc;
    struct crystal_elastic ce;
    rc = crystal_elastic_constants(c->pot, &c->spec, a0, &ce, e);
    if (rc)
        return rc;
    const double c11 = ce.c11, c12 = ce.c12, c44 = ce.c44;
    const double g = UNITS_EVA3_TO_GPA;
    struct result *r = &run->result;
    result_metric(r, "lattice_constant", a0, "Å");
    result_metric(r, "cohesive_energy", ec, "eV/atom");
    result_metric(r, "c11", c11 * g, "GPa");
    result_metric(r, "c12", c12 * g, "GPa");
    result_metric(r, "c44", c44 * g, "GPa");
    if (c->spec.style == LATTICE_DIAMOND) {   /* internal relaxation (md/crystal.h) */
        result_metric(r, "c44_unrelaxed", ce.c44_unrelaxed * g, "GPa");
        result_metric(r, "kleinman_zeta", ce.zeta, "1");
    }
    result_metric(r, "bulk_modulus", (c11 + 2 * c12) / 3 * g, "GPa");
    run_log(run, "a0 = %.6f Å, Ec = %.6f eV/atom, C11 = %.2f, C12 = %.2f, C44 = %.2f GPa", a0, ec,
            c11 * g, c12 * g, c44 * g);
    return 0;
}

static void crystal_destroy(void *state)
{
    struct crystal_case *c = state;
    if (!c)
        return;
    potential_destroy(&c->pot);
    free(c);
}

static long crystal_particles(const void *state)
{
    (void)state;
    return 0;
}

const struct case_type crystal_case_type = {
    "crystal", "0 K lattice constant, cohesive energy and cubic elastic constants of a potential",
    crystal_read, crystal_run, crystal_destroy, crystal_particles, NULL,
    .checkpoints = 0,
};
