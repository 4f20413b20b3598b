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

#include <stdio.h>

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

int lammps_data_write(const char *path, const struct particles *p, const struct box *b,
                      const char *title, struct err *e);

/* The file in parts, for particles that come a window at a time: the box
 * bounds widened over p's positions (lo and hi come in holding the bounds
 * so far: the box's, or another part's); the header of natoms with those
 * bounds (types and masses from `types`) up to the Atoms heading; the
 * Atoms lines of a part; the Velocities heading; a part's velocity lines.
 * The writes are checked by the caller (ferror). */
void lammps_data_widen(const struct particles *p, const struct box *b, double lo[3],
                       double hi[3]);
void lammps_data_header(FILE *f, const char *title, long natoms, const struct particles *types,
                        const double lo[3], const double hi[3], const struct box *b);
void lammps_data_atoms(FILE *f, const struct particles *p);
void lammps_data_velocities_heading(FILE *f);
void lammps_data_velocities(FILE *f, const struct particles *p);

#endif
