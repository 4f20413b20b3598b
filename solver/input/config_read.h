/*
 * config_read: initial configurations made elsewhere.
 *
 *   LAMMPS data file, atom_style atomic: header counts and box bounds,
 *   "Masses", "Atoms" (id type x y z [ix iy iz]) and optional "Velocities"
 *   sections.  Type names come from `elements` (type 1, 2, ...) or else from
 *   the comments of the Masses section ("1 63.546 # Cu").
 *
 *   Extended XYZ: count line, comment line with Lattice="..." (orthogonal),
 *   Properties=species:S:1:pos:R:3[:vel:R:3][:id:I:1 ...] and pbc="T T T".
 *
 * Errors name the file and line.  Distances Å, velocities Å/ps (metal units).
 */
#ifndef CASCADE_CONFIG_READ_H
#define CASCADE_CONFIG_READ_H

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

/* Default of system.max_particles: particle and neighbour-list indices
 * are int, and a full neighbour list of ~100 entries per atom passes 2^31
 * entries near 20 million atoms. */
#define CONFIG_MAX_ATOMS_DEFAULT 20000000L

int config_read_lammps_data(const char *path, const char *const *elements, int nelements,
                            struct particles *p, struct box *b, struct err *e);

/* pbc[d] is set from the file's pbc attribute (1 periodic), default all 1. */
int config_read_extxyz(const char *path, struct particles *p, struct box *b, int pbc[3],
                       struct err *e);

#endif
