/* crystal_range: check at read time that a case's periodic crystal can hold
 * its potential's interaction range (the crystal and elastic case types
 * build their crystals only when they run; without this, a huge cutoff
 * passed `check` and failed in `run` without naming the key). */
#ifndef CASCADE_SCENARIOS_CRYSTAL_RANGE_H
#define CASCADE_SCENARIOS_CRYSTAL_RANGE_H

#include "md/crystal.h"
#include "util/cfg.h"

/* The smallest crystal the case builds: spec->cells cubic cells of edge
 * a_min, skin as the case's MD uses.  ERR_INPUT at the potential key that
 * sets the range (file, cutoff) when md_range_ok refuses it with the
 * solver's default particle limit. */
int crystal_check_range(struct cfg_obj *root, struct cfg_obj *potential_section,
                        const struct potential *pot, const struct crystal_spec *spec,
                        double a_min, double skin);

#endif
