/* thermostat: Berendsen rescaling and Langevin forces. */
#include "core/thermostat.h"

#include <math.h>

#include "core/rng.h"
#include "core/units.h"

int thermostat_read(struct cfg_obj *o, struct thermostat *t)
{
    static const char *const styles[] = {"none", "berendsen", "langevin", NULL};
    int style, rc;
    if ((rc = cfg_enum(o, "style", "none", styles, &style)))
        return rc;
    t->style = (enum thermostat_style)style;
    t->group_mask = 1u;
    if (t->style == THERMOSTAT_NONE)
        return cfg_close(o);
    if ((rc = cfg_real(o, "temperature", CFG_REQUIRED, CFG_GE(0), &t->temperature)) ||
        (rc = cfg_real(o, "tau", 0.1, CFG_GT(0), &t->tau)))
        return rc;
    return cfg_close(o);
}

void thermostat_langevin_forces(const struct thermostat *t, struct particles *p, double dt,
                                uint64_t seed, long step)
{
    for (int i = 0; i < p->n_owned; i++) {
        if (!(p->mask[i] & t->group_mask))
            continue;
        double m = p->mass[p->type[i]];
        double gamma = m / t->tau * UNITS_MVV2E;   /* amu/ps -> eV ps/Å^2 */
        double sigma = sqrt(2.0 * m * UNITS_MVV2E * UNITS_KB * t->temperature / (t->tau * dt));
        uint64_t key = rng_key(seed, RNG_SITE_LANGEVIN, (uint64_t)step, (uint64_t)p->id[i], 0);
        for (int d = 0; d < 3; d++)
            p->f[3 * i + d] += -gamma * p->v[3 * i + d] + sigma * rng_gaussian(key, (uint64_t)d);
    }
}

void thermostat_berendsen_rescale(const struct thermostat *t, struct particles *p, double dt,
                                  double T)
{
    if (!(T > 0))
        return;
    double lambda2 = 1.0 + dt / t->tau * (t->temperature / T - 1.0);
    double lambda = sqrt(lambda2 > 0 ? lambda2 : 0);
    for (int i = 0; i < p->n_owned; i++)
        if (p->mask[i] & t->group_mask)
            for (int d = 0; d < 3; d++)
                p->v[3 * i + d] *= lambda;
}
