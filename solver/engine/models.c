/* models: the registry of model stage tables (models.h). */
#include "engine/models.h"

#include <string.h>

static const struct sim_model_ops *const registry[] = {
    &sim_model_md,
    &sim_model_impact_boundary,
    &sim_model_handshake,
    &sim_model_mpm,
    &sim_model_dpd,
    &sim_model_dpd_ref,
    &sim_model_dpd_mpm,
    NULL,
};

const struct sim_model_ops *sim_model_find(const char *name)
{
    for (int k = 0; registry[k]; k++)
        if (strcmp(registry[k]->name, name) == 0)
            return registry[k];
    return NULL;
}
