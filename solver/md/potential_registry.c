/* potential_registry: the table of potential styles, selected by name. */
#include "md/potential.h"

int lj_create(struct cfg_obj *o, struct potential **out);
int eam_funcfl_create(struct cfg_obj *o, struct potential **out);
int eam_setfl_create(struct cfg_obj *o, struct potential **out);
int eam_fs_create(struct cfg_obj *o, struct potential **out);
int sutton_chen_create(struct cfg_obj *o, struct potential **out);
int sw_create(struct cfg_obj *o, struct potential **out);
int meam_spline_create(struct cfg_obj *o, struct potential **out);

const struct potential_style potential_styles[] = {
    {"eam", "EAM, DYNAMO funcfl file (*.eam)", eam_funcfl_create},
    {"eam/alloy", "EAM, DYNAMO setfl file (*.eam.alloy)", eam_setfl_create},
    {"eam/fs", "Finnis-Sinclair EAM (*.eam.fs)", eam_fs_create},
    {"sutton_chen", "Sutton-Chen many-body, analytic", sutton_chen_create},
    {"lj", "Lennard-Jones 12-6, cut and shifted", lj_create},
    {"sw", "Stillinger-Weber three-body (*.sw)", sw_create},
    {"meam/spline", "spline-based MEAM of Lenosky et al. 2000 (*.meam.spline)", meam_spline_create},
    {NULL, NULL, NULL},
};
