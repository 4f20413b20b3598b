/*
 * md_system: the `system` section of MD-based cases -- where the atoms come
 * from and the box they live in.
 *
 *   system:
 *     lattice: {style: fcc, a: 3.615, cells: [10, 10, 10], origin: [0, 0, 0]}
 *     element: Cu                  # element of the lattice sites
 *     read_data: file.data         # or: a LAMMPS data file (atomic style)
 *     read_xyz: file.xyz           # or: an extended XYZ file
 *     elements: [Cu]               # type names for read_data (type 1, 2, ...)
 *     boundary: [periodic, periodic, periodic]   # periodic | free | fixed
 *     region: {shape: sphere, ...} # keep only lattice sites inside
 *     displace: 0.0                # random uniform displacement amplitude (Å)
 *     mass: 0                      # amu for the lattice element (0: standard)
 *
 * Exactly one of lattice, read_data, read_xyz.  With a lattice the box is the
 * lattice cells (origin .. origin + cells * cell edge).
 */
#ifndef CASCADE_MD_SYSTEM_H
#define CASCADE_MD_SYSTEM_H

#include <stdint.h>

#include "core/box.h"
#include "core/lattice.h"
#include "core/particles.h"
#include "util/cfg.h"

struct md_system_info {
    int from_lattice;
    struct lattice lattice;
    long cells[3];
};

/* Reads `system`; unless shallow, builds *p (new) and *b. */
int md_system_read(struct cfg_obj *root, uint64_t seed, struct particles **p, struct box *b,
                   struct md_system_info *info);

#endif
