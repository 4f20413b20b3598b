/*
 * mpm_j2: J2 (von Mises) elastic-plastic law with linear isotropic
 * hardening, for the far field: elastic predictor, radial return.
 *
 *   law: j2
 *   E, nu:      elastic moduli (GPa | Pa)
 *   yield:      initial yield stress sigma_y > 0 (GPa | Pa)
 *   hardening:  H >= 0, yield stress = sigma_y + H * eps_p (GPa | Pa)
 *
 * State: eps_p, the equivalent plastic strain.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/units.h"
#include "mpm/mpm_material.h"

struct j2 {
    struct mpm_material base;
    struct mpm_iso c;
    double sy, H;   /* eV/Å^3 */
};

static void j2_update(const struct mpm_material *m, double s[6], const double de[6],
                      double *state)
{
    const struct j2 *p = (const struct j2 *)m;
    mpm_iso_increment(&p->c, s, de);   /* elastic trial */
    double mean = (s[0] + s[1] + s[2]) / 3.0;
    double d[6] = {s[0] - mean, s[1] - mean, s[2] - mean, s[3], s[4], s[5]};
    double j2 = 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) +
                d[3] * d[3] + d[4] * d[4] + d[5] * d[5];
    double q = sqrt(3.0 * j2);   /* von Mises stress */
    double fy = q - (p->sy + p->H * state[0]);
    if (fy <= 0)
        return;
    /* radial return: deps_p = f / (3 mu + H); scale the deviator */
    double dep = fy / (3.0 * p->c.mu + p->H);
    double scale = 1.0 - 3.0 * p->c.mu * dep / q;
    s[0] = mean + scale * d[0];
    s[1] = mean + scale * d[1];
    s[2] = mean + scale * d[2];
    s[3] = scale * d[3];
    s[4] = scale * d[4];
    s[5] = scale * d[5];
    state[0] += dep;
}

static double j2_wave_speed(const struct mpm_material *m)
{
    const struct j2 *p = (const struct j2 *)m;
    return sqrt((p->c.lambda + 2 * p->c.mu) / m->density * UNITS_FTM2V);
}

static const char *const j2_state_names[] = {"plastic_strain", NULL};

static const struct mpm_material_ops j2_ops = {
    "j2", 1, j2_update, j2_wave_speed, j2_state_names,
};

struct mpm_material *mpm_material_j2(const char *name, double density, double E, double nu,
                                     double yield, double hardening)
{
    struct j2 *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->base.ops = &j2_ops;
    p->c.mu = E / (2 * (1 + nu));
    p->c.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    p->sy = yield;
    p->H = hardening;
    mpm_material_base_init(&p->base, name, density);
    snprintf(p->base.description, sizeof p->base.description,
             "J2 plasticity E = %g, nu = %g, yield = %g, hardening = %g (eV/Å^3)", E, nu, yield,
             hardening);
    return &p->base;
}

int mpm_j2_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                  struct mpm_material **out)
{
    struct mpm_iso c;
    double E, nu, sy, H;
    int rc = mpm_iso_read(o, u, &c, &E, &nu);
    if (rc || (rc = cfg_real(o, "yield", CFG_REQUIRED, CFG_ANY, &sy)) ||
        (rc = cfg_real(o, "hardening", 0.0, CFG_ANY, &H)))
        return rc;
    if (!(sy > 0))
        return mpm_key_error(o, "yield", "yield stress = %g must be positive", sy);
    if (!(H >= 0))
        return mpm_key_error(o, "hardening", "hardening modulus = %g must not be negative", H);
    if (o->cfg->shallow)
        return 0;
    struct j2 *p = calloc(1, sizeof *p);
    if (!p)
        return err_nomem(o->cfg->err, "material");
    p->base.ops = &j2_ops;
    p->c = c;
    p->sy = sy * u->stress;
    p->H = H * u->stress;
    snprintf(p->base.description, sizeof p->base.description,
             "J2 plasticity E = %g %s, nu = %g, yield = %g, hardening = %g", E, u->stress_name,
             nu, sy, H);
    (void)density;
    *out = &p->base;
    return 0;
}
