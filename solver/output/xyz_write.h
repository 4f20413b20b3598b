/*
 * xyz_write: extended XYZ frames (OVITO, ASE): a count line, a comment line
 * with Lattice, Properties, Time and pbc, then one line per particle.
 *   Properties=species:S:1:pos:R:3:vel:R:3:forces:R:3:id:I:1[:extra...]
 */
#ifndef CASCADE_XYZ_WRITE_H
#define CASCADE_XYZ_WRITE_H

#include <stdio.h>

#include "core/box.h"
#include "core/particles.h"

/* Optional extra per-particle integer column (for example a structure
 * class): name and values, or NULL. */
int xyz_write_frame(FILE *out, const struct particles *p, const struct box *b, long step,
                    double time, const char *extra_name, const int *extra);

#endif
