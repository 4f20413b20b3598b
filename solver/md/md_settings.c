/* md_settings: the one reader of the `md` section (md_settings.h). */
#include "md/md_settings.h"

const struct md_settings md_settings_defaults = {
    .timestep = 0.001,
    .steps = 1000,
    .temperature = 0.0,
    .skin = 1.0,
    .max_energy_change = 1.0,
    .max_displacement = 0.1,
    .thermostat = {THERMOSTAT_NONE, 0.0, 0.1, 1u},
};

int md_settings_read(struct cfg_obj *root, unsigned keys, const struct md_settings *def,
                     struct md_settings *out)
{
    *out = *def;
    struct cfg_obj mo, to;
    int rc = cfg_section(root, "md", &mo);
    if (!rc && (keys & MD_KEY_TIMESTEP))
        rc = cfg_real(&mo, "timestep", def->timestep, CFG_GT(0), &out->timestep);
    if (!rc && (keys & MD_KEY_STEPS))
        rc = cfg_int(&mo, "steps", def->steps, CFG_GE(0), &out->steps);
    if (!rc && (keys & MD_KEY_TEMPERATURE))
        rc = cfg_real(&mo, "temperature", def->temperature, CFG_GE(0), &out->temperature);
    if (!rc && (keys & MD_KEY_SKIN))
        rc = cfg_real(&mo, "skin", def->skin, CFG_GT(0), &out->skin);
    if (!rc && (keys & MD_KEY_MAX_ENERGY_CHANGE))
        rc = cfg_real(&mo, "max_energy_change", def->max_energy_change, CFG_GT(0),
                      &out->max_energy_change);
    if (!rc && (keys & MD_KEY_MAX_DISPLACEMENT))
        rc = cfg_real(&mo, "max_displacement", def->max_displacement, CFG_RANGE(0.001, 1.0),
                      &out->max_displacement);
    if (!rc && (keys & MD_KEY_THERMOSTAT) && !(rc = cfg_section(&mo, "thermostat", &to)))
        rc = thermostat_read(&to, &out->thermostat);
    if (!rc)
        rc = cfg_close(&mo);
    return rc;
}
