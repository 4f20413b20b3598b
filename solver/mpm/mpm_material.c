/* mpm_material: the common material keys and the law registry lookup. */
#include "mpm/mpm_material.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int mpm_key_error(struct cfg_obj *o, const char *key, const char *fmt, ...)
{
    char path[CFG_PATH_MAX], msg[ERR_MSG_MAX / 2];
    snprintf(path, sizeof path, "%s%s%s", o->path, o->path[0] ? "." : "", key);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return cfg_error_at(o->cfg, path, "%s", msg);
}

int mpm_iso_read(struct cfg_obj *o, const struct mpm_units *u, struct mpm_iso *iso, double *E,
                 double *nu)
{
    int rc;
    if ((rc = cfg_real(o, "E", CFG_REQUIRED, CFG_ANY, E)) ||
        (rc = cfg_real(o, "nu", CFG_REQUIRED, CFG_ANY, nu)))
        return rc;
    if (!(*E > 0))
        return mpm_key_error(o, "E", "Young's modulus E = %g must be positive", *E);
    if (!(*nu > -1.0 && *nu < 0.5))
        return mpm_key_error(o, "nu",
                             "Poisson's ratio nu = %g must lie in (-1, 0.5) for a stable solid",
                             *nu);
    double Ei = *E * u->stress;
    iso->mu = Ei / (2 * (1 + *nu));
    iso->lambda = Ei * *nu / ((1 + *nu) * (1 - 2 * *nu));
    return 0;
}

int mpm_material_create(struct cfg_obj *o, const struct mpm_units *u, struct mpm_material **out)
{
    static const char *const rates[] = {"jaumann", "none", NULL};
    const char *name_list[16];
    int n = 0;
    for (; mpm_material_styles[n].law && n < 15; n++)
        name_list[n] = mpm_material_styles[n].law;
    name_list[n] = NULL;
    *out = NULL;
    const char *name;
    int law, rate, rc;
    double density;
    if ((rc = cfg_string(o, "name", NULL, &name)) || (rc = cfg_enum(o, "law", NULL, name_list, &law)) ||
        (rc = cfg_real(o, "density", CFG_REQUIRED, CFG_ANY, &density)) ||
        (rc = cfg_enum(o, "rate", "jaumann", rates, &rate)))
        return rc;
    if (!(density > 0))
        return mpm_key_error(o, "density", "density = %g must be positive", density);
    if (strlen(name) == 0 || strlen(name) >= sizeof((struct mpm_material *)0)->name)
        return mpm_key_error(o, "name", "material name must have 1 to 31 characters");
    struct mpm_material *m = NULL;
    rc = mpm_material_styles[law].create(o, u, density * u->density, &m);
    if (!rc)
        rc = cfg_close(o);
    if (rc || o->cfg->shallow) {
        free(m);
        return rc;
    }
    snprintf(m->name, sizeof m->name, "%s", name);
    m->density = density * u->density;
    m->jaumann = rate == 0;
    *out = m;
    return 0;
}

void mpm_material_base_init(struct mpm_material *m, const char *name, double density)
{
    snprintf(m->name, sizeof m->name, "%s", name);
    m->density = density;
    m->jaumann = 1;
}

void mpm_material_destroy(struct mpm_material **m)
{
    if (!m || !*m)
        return;
    free(*m);
    *m = NULL;
}
