/*
 * config_read: initial configurations made elsewhere.
 *
 *   LAMMPS data file, atom_style atomic: header counts and box bounds,
 *   "Masses", "Atoms" (id type x y z [ix iy iz]) and optional "Velocities"
 *   sections.  A triclinic box ("xy xz yz" line) gives b->tilt (core/box.h:
 *   LAMMPS' restricted triclinic cell); the tilt is refused at its line,
 *   naming the factor, beyond LAMMPS' limit (|xy|, |xz| <= lx / 2, |yz| <=
 *   ly / 2), along a non-periodic axis (rules->bc), or when the caller does
 *   not simulate tilted boxes (rules->allow_tilt).  Atom positions are
 *   Cartesian, image flags count cell edges (x + ix a + iy b + iz c
 *   unwrapped), as LAMMPS writes them.  Type names come from `elements` (type 1, 2, ...) or else from
 *   the comments of the Masses section ("1 63.546 # Cu").
 *
 *   Extended XYZ: count line, comment line with Lattice="ax ay az bx by bz
 *   cx cy cz" (a restricted triclinic cell, ay = az = bz = 0: tilt xy = bx,
 *   xz = cx, yz = cy, held to the rules of the data file's tilt),
 *   Properties=species:S:1:pos:R:3[:velo:R:3][:id:I:1 ...] and pbc="T T T".
 *   Velocities (Å/ps) come from a column velo, vel or velocities, or else
 *   from ASE's momenta:R:3 (amu Å / t_ASE, t_ASE = Å sqrt(amu/eV)) divided
 *   by the masses:R:1 column or the element's mass, so files ASE writes
 *   keep their velocities.  The species are chemical element symbols.
 *   After the atoms there may be further frames (only the first is read),
 *   nothing else.
 *
 * Both readers refuse, naming file:line and the field, as LAMMPS's
 * read_data does:
 *   - numbers that are not whole finite decimal tokens ("1.5x", "nan",
 *     "0x10", "1e999"); ids, types, image flags and counts not integers;
 *   - more atoms than rules->max_atoms (from the header, before reading on);
 *   - an atom id given twice (both lines named), a velocity given twice;
 *   - a coordinate outside the box, by this rule per axis (rules->bc;
 *     a tilted box: the fractional coordinate s, -1 <= s < 2):
 *       periodic  within one box length of the box: lo - L <= x < hi + L;
 *                 the run wraps it into [lo, hi) at its first neighbour
 *                 list build, the image flag counting the wrap
 *       free      within one box length of the box as well (the run
 *                 shrink-wraps the box around the atoms)
 *       fixed     inside [lo, hi], as the run requires
 *     Positions are stored as the file gives them.
 *   - two atoms closer than rules->min_distance (periodic images included;
 *     both lines named), found with a cell sort in O(N).
 *
 * Distances Å, velocities Å/ps (metal units).
 */
#ifndef CASCADE_CONFIG_READ_H
#define CASCADE_CONFIG_READ_H

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

/* Default of rules.max_atoms (and of system.max_particles): particle and
 * neighbour-list indices are int, and a full neighbour list of ~100
 * entries per atom passes 2^31 entries near 20 million atoms. */
#define CONFIG_MAX_ATOMS_DEFAULT 20000000L
/* Default of rules.min_distance, Å: well below any bond (H2: 0.74 Å). */
#define CONFIG_MIN_DISTANCE_DEFAULT 0.1

struct config_rules {
    enum boundary bc[3];   /* how coordinates outside the file's box are treated */
    long max_atoms;        /* a larger file is refused before it is read on */
    double min_distance;   /* Å: atoms closer than this are refused (0: not checked) */
    int allow_tilt;        /* 0: a tilted box is refused at its line (the caller's
                            * engine has orthogonal boxes only) */
    const char *who;       /* the caller, for that message ("case type dpd"); may be NULL */
};

/* All periodic, the default limits, tilt allowed. */
struct config_rules config_rules_default(void);

/* rules may be NULL (config_rules_default()).  b->lo, b->hi and b->tilt
 * come from the file; b->bc is left as it is. */
int config_read_lammps_data(const char *path, const char *const *elements, int nelements,
                            const struct config_rules *rules, struct particles *p, struct box *b,
                            struct err *e);

/* pbc[d] is set from the file's pbc attribute (1 periodic), default all 1;
 * the coordinates are checked against rules->bc, not against pbc. */
int config_read_extxyz(const char *path, const struct config_rules *rules, struct particles *p,
                       struct box *b, int pbc[3], struct err *e);

#endif
