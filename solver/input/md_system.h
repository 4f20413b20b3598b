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
 *     max_particles: 20000000      # more atoms are refused before any is made
 *
 * Exactly one of lattice, read_data, read_xyz.  With a lattice the box is the
 * lattice cells (origin .. origin + cells * cell edge).
 *
 * max_particles (default CONFIG_MAX_ATOMS_DEFAULT, not written into the
 * resolved case when absent) bounds the atoms of the system: a lattice's
 * cells times sites per cell, checked by `resolve` and `check` before
 * anything is allocated; a data or XYZ file's count line, checked when the
 * file is read.  md cases also hold the ghost atoms of the periodic images
 * to it (md_check_range).  The readers' other rules (unique ids,
 * coordinates inside the box, no coincident atoms): input/config_read.h.
 */
#ifndef CASCADE_MD_SYSTEM_H
#define CASCADE_MD_SYSTEM_H

#include <stdint.h>

#include "core/box.h"
#include "core/lattice.h"
#include "core/particles.h"
#include "input/config_read.h"
#include "util/cfg.h"

/* Upper bound of system.max_particles: particle indices are int, ghosts
 * come on top of the owned atoms. */
#define MD_SYSTEM_MAX_PARTICLES_CAP 1000000000L

struct md_system_info {
    int from_lattice;
    struct lattice lattice;
    long cells[3];
    long max_particles;     /* system.max_particles (or its default) */
    long natoms;            /* atoms of the system (of all ranks) */
};

struct halo;
struct parallel;

/* A distributed set-up: once the box is known, plan(ctx, box, &halo) says
 * whether the run is split into bricks (*halo a new decomposition, or NULL
 * for a serial or replicated run; md/md_bricks.h). */
struct md_system_split {
    int (*plan)(void *ctx, const struct box *b, struct halo **out);
    void *ctx;
    int tilt_ok;   /* the caller runs tilted boxes (read from a data or XYZ
                    * file); without it (and with md_system_read) a tilted
                    * file is refused at its tilt line */
    const struct parallel *par;   /* the run's ranks (NULL: serial): with more than
                                   * one, rank 0 alone reads a data or XYZ file */
    int on_extent;  /* plan gets the box with each non-periodic axis cut to the
                     * atoms' extent (of all ranks: a lattice's sites the region
                     * keeps, before `displace`, from a pass that stores none; a
                     * file's atoms, from rank 0), for a body much smaller than
                     * its box; 0: the box */
};

/* The key max_particles of a section that builds atoms (system, and the
 * hugoniot and target sections of their case types): *max is its value or
 * CONFIG_MAX_ATOMS_DEFAULT, which is not written into the case. */
int md_read_max_particles(struct cfg_obj *o, long *max);
/* Refuse `count` atoms (a double: cells multiply past a long) above
 * o's max_particles, with the message at o's key `key`. */
int md_check_count(struct cfg_obj *o, const char *key, double count, long max, const char *what);

/* Reads `system`; unless shallow, builds *p (new) and *b. */
int md_system_read(struct cfg_obj *root, uint64_t seed, struct particles **p, struct box *b,
                   struct md_system_info *info);

/* The same, split over bricks when split->plan returns a halo (*halo, the
 * caller's; NULL otherwise; split NULL: never): a lattice rank builds the
 * sites of its own brick only, with the ids and displacements of the
 * whole build (memory per rank is its brick's); a data or XYZ file is
 * read and checked whole by rank 0 alone when split->par has more than
 * one rank (its errors, file:line and field, become every rank's), which
 * keeps the region's atoms and displaces them as a serial run does and
 * then sends them to their owners in blocks (core/halo_scatter.h): the
 * other ranks hold their brick plus one block, rank 0 the whole file
 * until it drops what is not its own.  Without a halo (replicated data)
 * every rank receives every atom.  Atoms a displacement moved just out
 * of the brick migrate at the first list build.  Collective under
 * split. */
int md_system_read_split(struct cfg_obj *root, uint64_t seed, const struct md_system_split *split,
                         struct particles **p, struct box *b, struct md_system_info *info,
                         struct halo **halo);

#endif
