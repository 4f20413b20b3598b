/* registry: the case types cascade-solver knows, selected by `type:`. */
#include <string.h>

#include "scenarios/case_type.h"

extern const struct case_type md_case_type;
extern const struct case_type crystal_case_type;
extern const struct case_type elastic_case_type;
extern const struct case_type dpd_case_type;
extern const struct case_type dpd_impact_case_type;
extern const struct case_type dpd_tensile_case_type;
extern const struct case_type dpd_fit_case_type;
extern const struct case_type mpm_case_type;
extern const struct case_type handshake_wave_case_type;
extern const struct case_type handshake_static_case_type;
extern const struct case_type handshake_packet_case_type;
extern const struct case_type handshake_thermal_case_type;
extern const struct case_type dpd_grid_impact_case_type;
extern const struct case_type dpd_grid_tensile_case_type;
extern const struct case_type dpd_mpm_impact_case_type;
extern const struct case_type impact_case_type;
extern const struct case_type hugoniot_case_type;
extern const struct case_type isotherm_case_type;
extern const struct case_type structure_case_type;

const struct case_type *const case_types[] = {
    &md_case_type,
    &crystal_case_type,
    &elastic_case_type,
    &dpd_case_type,
    &dpd_impact_case_type,
    &dpd_tensile_case_type,
    &dpd_fit_case_type,
    &mpm_case_type,
    &handshake_wave_case_type,
    &handshake_static_case_type,
    &handshake_packet_case_type,
    &handshake_thermal_case_type,
    &dpd_grid_impact_case_type,
    &dpd_grid_tensile_case_type,
    &dpd_mpm_impact_case_type,
    &impact_case_type,
    &hugoniot_case_type,
    &isotherm_case_type,
    &structure_case_type,
    NULL,
};

const struct case_type *case_type_find(const char *name)
{
    for (int i = 0; case_types[i]; i++)
        if (strcmp(case_types[i]->name, name) == 0)
            return case_types[i];
    return NULL;
}
