/*
 * lammps_data_write: the owned particles as a LAMMPS data file
 * (atom_style atomic) -- header with counts and box bounds, Masses (each
 * line commented with its type name, which input/config_read.c reads
 * back), Atoms (id type x y z ix iy iz) and Velocities.  Positions are
 * written with 17 significant digits so a run restarted from the file
 * continues from the same state.
 *
 * Along non-periodic axes the bounds are widened to contain every particle
 * (a free boundary's box is only shrink-wrapped at neighbour rebuilds).
 * A tilted box (core/box.h) adds the line "xy xz yz" after the bounds;
 * image flags count its edges, as LAMMPS' write_data writes them.
 */
#ifndef CASCADE_LAMMPS_DATA_WRITE_H
#define CASCADE_LAMMPS_DATA_WRITE_H

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

int lammps_data_write(const char *path, const struct particles *p, const struct box *b,
                      const char *title, struct err *e);

#endif
