/*
 * cg_material_state: one thermodynamic state of the coarse-grained crystal
 * for the material points of the concurrent DPD/MPM model -- the density
 * and the cubic elastic constants taken at the same lattice constant, so
 * that sqrt(C11/rho) is the longitudinal speed of one material and not of
 * two (before 2026-11-25 the points had the surface-contracted bar's
 * density, 9.005 g/cm^3, beside constants at the parameter file's lattice
 * constant, 8.76 g/cm^3: 1.4 % on the speed).
 *
 *   lattice    (default) the equilibrated crystal at the run's temperature:
 *              the lattice constant where the model pressure of the
 *              coarse-grained potential, static plus the quasi-harmonic
 *              Einstein thermal pressure (cg_lattice.h), vanishes at the
 *              temperature of the target's velocities
 *   bar        the state of the bar as read: its volume per particle
 *              (extents over particle count), lattice constant (4 V)^(1/3)
 *   parameter  the parameter file's lattice constant
 *   given      concurrent.lattice_constant
 *
 * In every case rho = 4 m / a^3, the point volume is a^3 / 4 and C11, C12,
 * C44 are the static constants at a (cg_lattice_elastic).
 */
#ifndef CASCADE_CG_MATERIAL_STATE_H
#define CASCADE_CG_MATERIAL_STATE_H

#include "dpd/cg_params.h"
#include "util/err.h"

enum cg_state_source { CG_STATE_LATTICE, CG_STATE_BAR, CG_STATE_PARAMETER, CG_STATE_GIVEN };

struct cg_material_state {
    int source;                  /* enum cg_state_source */
    double T;                    /* K: temperature the state is for */
    double a;                    /* Å */
    double rho;                  /* amu/Å^3 */
    double volume;               /* Å^3 per particle */
    double c11, c12, c44;        /* eV/Å^3 */
    char note[200];              /* where it came from, for result.json */
};

/* The state of `source` (a_given for CG_STATE_GIVEN, bar_volume: the bar's
 * volume per particle, T: the run's temperature).  Returns 0, or ERR_INPUT
 * when the zero-pressure lattice cannot be found near the parameter
 * file's. */
int cg_material_state_get(const struct cg_params *prm, int source, double a_given, double T,
                          double bar_volume, struct cg_material_state *s, struct err *e);

/* The names of the sources, for cfg_enum (NULL-terminated). */
extern const char *const cg_state_source_names[];

#endif
