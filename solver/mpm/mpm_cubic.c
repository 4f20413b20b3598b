/*
 * mpm_cubic: cubic linear elasticity with the crystal axes along the box
 * axes (Guo & Yang 2005: C11, C12, C44 computed from the same potential as
 * the MD region, e.g. by the `crystal` case type).
 *
 *   law: cubic_elastic
 *   C11, C12, C44: elastic constants (GPa | Pa)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/units.h"
#include "mpm/mpm_material.h"

struct cubic {
    struct mpm_material base;
    double c11, c12, c44;   /* eV/Å^3 */
};

static void cubic_update(const struct mpm_material *m, double s[6], const double de[6],
                         double *state)
{
    (void)state;
    const struct cubic *c = (const struct cubic *)m;
    s[0] += c->c11 * de[0] + c->c12 * (de[1] + de[2]);
    s[1] += c->c11 * de[1] + c->c12 * (de[0] + de[2]);
    s[2] += c->c11 * de[2] + c->c12 * (de[0] + de[1]);
    /* Voigt: sigma_xy = C44 * gamma_xy = C44 * 2 eps_xy */
    s[3] += 2 * c->c44 * de[3];
    s[4] += 2 * c->c44 * de[4];
    s[5] += 2 * c->c44 * de[5];
}

static double cubic_wave_speed(const struct mpm_material *m)
{
    const struct cubic *c = (const struct cubic *)m;
    /* longitudinal moduli along <100>, <110>, <111>; the largest bounds all */
    double m100 = c->c11;
    double m110 = (c->c11 + c->c12 + 2 * c->c44) / 2;
    double m111 = (c->c11 + 2 * c->c12 + 4 * c->c44) / 3;
    double mx = fmax(m100, fmax(m110, m111));
    return sqrt(mx / m->density * UNITS_FTM2V);
}

static const struct mpm_material_ops cubic_ops = {
    "cubic_elastic", 0, cubic_update, cubic_wave_speed, NULL,
};

struct mpm_material *mpm_material_cubic_elastic(const char *name, double density, double c11,
                                                double c12, double c44)
{
    struct cubic *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->base.ops = &cubic_ops;
    c->c11 = c11;
    c->c12 = c12;
    c->c44 = c44;
    mpm_material_base_init(&c->base, name, density);
    snprintf(c->base.description, sizeof c->base.description,
             "cubic elastic C11 = %g, C12 = %g, C44 = %g eV/Å^3", c11, c12, c44);
    return &c->base;
}

int mpm_cubic_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                     struct mpm_material **out)
{
    double c11, c12, c44;
    int rc;
    if ((rc = cfg_real(o, "C11", CFG_REQUIRED, CFG_ANY, &c11)) ||
        (rc = cfg_real(o, "C12", CFG_REQUIRED, CFG_ANY, &c12)) ||
        (rc = cfg_real(o, "C44", CFG_REQUIRED, CFG_ANY, &c44)))
        return rc;
    /* Born stability of a cubic crystal */
    if (!(c44 > 0))
        return mpm_key_error(o, "C44", "C44 = %g must be positive", c44);
    if (!(c11 > fabs(c12)))
        return mpm_key_error(o, "C11", "C11 = %g must exceed |C12| = %g (Born stability)", c11,
                             fabs(c12));
    if (!(c11 + 2 * c12 > 0))
        return mpm_key_error(o, "C12",
                             "C11 + 2 C12 = %g must be positive (bulk modulus, Born stability)",
                             c11 + 2 * c12);
    if (o->cfg->shallow)
        return 0;
    struct cubic *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(o->cfg->err, "material");
    c->base.ops = &cubic_ops;
    c->c11 = c11 * u->stress;
    c->c12 = c12 * u->stress;
    c->c44 = c44 * u->stress;
    snprintf(c->base.description, sizeof c->base.description,
             "cubic elastic C11 = %g, C12 = %g, C44 = %g %s", c11, c12, c44, u->stress_name);
    (void)density;
    *out = &c->base;
    return 0;
}
