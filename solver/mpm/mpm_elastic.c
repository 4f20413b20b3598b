/*
 * mpm_elastic: isotropic linear elasticity in rate form,
 * dsigma = lambda tr(de) I + 2 mu de (Guo & Yang 2005, Eq. (8)).
 *
 *   law: linear_elastic
 *   E:   Young's modulus (GPa | Pa)
 *   nu:  Poisson's ratio
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/units.h"
#include "mpm/mpm_material.h"

struct elastic {
    struct mpm_material base;
    struct mpm_iso c;
};

static void elastic_update(const struct mpm_material *m, double s[6], const double de[6],
                           double *state)
{
    (void)state;
    mpm_iso_increment(&((const struct elastic *)m)->c, s, de);
}

static double elastic_wave_speed(const struct mpm_material *m)
{
    const struct elastic *el = (const struct elastic *)m;
    /* P wave: sqrt((lambda + 2 mu) / rho), Å/ps */
    return sqrt((el->c.lambda + 2 * el->c.mu) / m->density * UNITS_FTM2V);
}

static const struct mpm_material_ops elastic_ops = {
    "linear_elastic", 0, elastic_update, elastic_wave_speed, NULL,
};

struct mpm_material *mpm_material_linear_elastic(const char *name, double density, double E,
                                                 double nu)
{
    struct elastic *el = calloc(1, sizeof *el);
    if (!el)
        return NULL;
    el->base.ops = &elastic_ops;
    el->c.mu = E / (2 * (1 + nu));
    el->c.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    mpm_material_base_init(&el->base, name, density);
    el->base.iso = &el->c;
    snprintf(el->base.description, sizeof el->base.description,
             "linear elastic E = %g eV/Å^3, nu = %g", E, nu);
    return &el->base;
}

int mpm_elastic_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                       struct mpm_material **out)
{
    struct mpm_iso c;
    double E, nu;
    int rc = mpm_iso_read(o, u, &c, &E, &nu);
    if (rc || o->cfg->shallow)
        return rc;
    struct elastic *el = calloc(1, sizeof *el);
    if (!el)
        return err_nomem(o->cfg->err, "material");
    el->base.ops = &elastic_ops;
    el->c = c;
    el->base.iso = &el->c;
    snprintf(el->base.description, sizeof el->base.description,
             "linear elastic E = %g %s, nu = %g", E, u->stress_name, nu);
    (void)density;
    *out = &el->base;
    return 0;
}
