/* mpm_material_registry: the table of constitutive laws, selected by name. */
#include "mpm/mpm_material.h"

int mpm_elastic_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                       struct mpm_material **out);
int mpm_cubic_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                     struct mpm_material **out);
int mpm_j2_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                  struct mpm_material **out);

const struct mpm_material_style mpm_material_styles[] = {
    {"linear_elastic", "isotropic linear elastic (E, nu)", mpm_elastic_create},
    {"cubic_elastic", "cubic linear elastic, crystal axes along x, y, z (C11, C12, C44)",
     mpm_cubic_create},
    {"j2", "von Mises plasticity with linear isotropic hardening (E, nu, yield, hardening)",
     mpm_j2_create},
    {NULL, NULL, NULL},
};
