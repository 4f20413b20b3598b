/*
 * xyz_write: extended XYZ frames: a count line, a comment line with
 * Lattice (the three cell vectors a b c, LAMMPS' restricted triclinic
 * cell of core/box.h), Origin, Properties, Time, Step and pbc, then one line per
 * particle.  The columns carry the names the readers of OVITO and ASE map
 * to their own properties without a column mapping:
 *
 *   species:S:1   element symbol        OVITO Particle Type, ASE symbols
 *   pos:R:3       Å                     OVITO Position, ASE positions
 *   velo:R:3      Å/ps                  OVITO Velocity
 *   forces:R:3    eV/Å                  OVITO Force, ASE get_forces()
 *   id:I:1                              OVITO Particle Identifier
 *   masses:R:1    amu                   ASE get_masses()
 *   momenta:R:3   ASE units: amu Å / t_ASE, t_ASE = Å sqrt(amu/eV)
 *                 = 10.1805 fs          ASE get_momenta(), get_velocities()
 *   energies:R:1  eV  (optional)        ASE get_potential_energies()
 *   stress:R:6    GPa, xx yy zz xy xz yz (optional)  OVITO Stress Tensor
 *   NAME:I:1      optional extra integer column (for example a structure class)
 *
 * ASE has no velocity column (its Atoms keep momenta), OVITO none for
 * momenta, hence both.  OVITO shows masses, momenta and energies as user
 * properties, ASE keeps velo and stress as plain arrays.  The reader of
 * input/config_read.h reads velo (also vel, velocities) back.
 */
#ifndef CASCADE_XYZ_WRITE_H
#define CASCADE_XYZ_WRITE_H

#include <stdio.h>

#include "core/box.h"
#include "core/particles.h"

/* Optional columns; any member may be NULL. */
struct xyz_extra {
    const double *pe;        /* per-particle potential energy, eV */
    const double *stress;    /* per-particle stress, 6 per particle (Voigt), GPa */
    const char *int_name;    /* name of an extra integer column */
    const int *int_values;
};

/* x may be NULL (no optional columns). */
int xyz_write_frame(FILE *out, const struct particles *p, const struct box *b, long step,
                    double time, const struct xyz_extra *x);

/* A frame in parts, for particles that come a window at a time: the count
 * and comment lines of n particles with the optional columns (energies,
 * stresses, an integer column int_name unless NULL), then the particle
 * lines of each part with those columns' values. */
void xyz_write_header(FILE *out, long n, const struct box *b, long step, double time, int pe,
                      int stress, const char *int_name);
int xyz_write_particles(FILE *out, const struct particles *p, const struct xyz_extra *x);

#endif
