/* crystal_range: the interaction range against a case's periodic crystal. */
#include "scenarios/crystal_range.h"

#include <jansson.h>
#include <stdio.h>

#include "core/box.h"
#include "core/lattice.h"
#include "input/config_read.h"
#include "md/md.h"

int crystal_check_range(struct cfg_obj *root, struct cfg_obj *potential_section,
                        const struct potential *pot, const struct crystal_spec *spec,
                        double a_min, double skin)
{
    struct lattice l = {spec->style, a_min, {0, 0, 0}, {{0}}};
    double cell[3];
    lattice_cell(&l, cell);
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    for (int d = 0; d < 3; d++)
        b.hi[d] = (double)spec->cells * cell[d];
    long n = spec->cells * spec->cells * spec->cells * (long)lattice_cell_sites(&l);
    char why[1024];
    if (md_range_ok(pot, &b, n, skin, (double)CONFIG_MAX_ATOMS_DEFAULT,
                    "the solver's particle limit", why, sizeof why) == 0)
        return 0;
    const char *key = pot->source_path[0]                               ? "potential.file"
                      : json_object_get(potential_section->node, "cutoff") ? "potential.cutoff"
                                                                         : "potential";
    char msg[1200];
    snprintf(msg, sizeof msg, "%s (the %ld x %ld x %ld crystal at a = %g Å)", why, spec->cells,
             spec->cells, spec->cells, a_min);
    return cfg_error_at(root->cfg, key, "%s", msg);
}
