/*
 * impact_from_potential: a(T) and the MPM's elastic constants at T computed
 * by a cluster-impact case with the handshake boundary itself, from its own
 * potential and crystal -- `target.handshake.thermal.from_potential`, the
 * counterpart of handshake_thermal's `thermal.from_potential`.  The
 * computation is type: elastic's (elastic_thermal.h); this file holds the
 * settings and the 0 K lattice constant the case is first built at.
 *
 *   target:
 *     temperature: 300         K (> 0: the temperature of the computation)
 *     boundary: handshake
 *     handshake:
 *       thermal:
 *         from_potential:
 *           a_min: 3.5, a_max: 3.7   Å: the 0 K minimum is searched here
 *                                    (type: elastic's crystal.a_min, a_max)
 *           cells: 4                 cubic cells of the periodic crystal
 *           strain, timestep, tau, equilibrate, sample,
 *           lattice_iterations, repeats   type: elastic's elastic section
 *
 * target.a and target.handshake.elastic are then left out: the case is
 * read and checked at the 0 K lattice constant, and its run computes a(T)
 * and C11, C12, C44 at T with the case's seed, then builds the case again
 * with target.a = a(T) and target.handshake.elastic = the constants
 * (impact_case.c), so that the run is the run with those numbers given.
 */
#ifndef CASCADE_IMPACT_FROM_POTENTIAL_H
#define CASCADE_IMPACT_FROM_POTENTIAL_H

#include <jansson.h>

#include "core/lattice.h"
#include "output/run.h"
#include "scenarios/elastic_thermal.h"
#include "util/cfg.h"

struct impact_from_potential {
    struct elastic_thermal_settings set;
    long cells;
    double a_min, a_max;          /* Å */
    struct elastic_thermal out;   /* filled by impact_from_potential_compute */
};

/* Whether target.handshake.thermal.from_potential is in the target section
 * `target` (before it is read: the case reads target.a before the boundary). */
int impact_from_potential_given(const json_t *target);

/* Read from_potential from the section `thermal` (target.handshake.thermal)
 * of a target at `temperature` K: *out is NULL when the key is absent, else
 * a new settings block (the caller frees it).  A describe read lists the
 * keys and returns NULL. */
int impact_from_potential_read(struct cfg_obj *thermal, double temperature,
                               struct impact_from_potential **out);

/* The potential's 0 K lattice constant of the target's crystal. */
int impact_from_potential_a0(const struct impact_from_potential *fp, struct potential *pot,
                             enum lattice_style style, const char *element, double *a0,
                             struct err *e);

/* a(T) and the constants at T (fp->out) for the target's crystal with the
 * case's seed and threads; logs to run. */
int impact_from_potential_compute(struct impact_from_potential *fp, struct potential *pot,
                                  enum lattice_style style, const char *element, uint64_t seed,
                                  int nthreads, struct run *run, struct err *e);

#endif
