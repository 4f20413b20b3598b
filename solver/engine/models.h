/*
 * models: the stage tables of the physics engines, by name.  Adding a model
 * (or a coupling) is one file model_<name>.c and one line in models.c.
 */
#ifndef CASCADE_MODELS_H
#define CASCADE_MODELS_H

#include "engine/sim.h"
#include "dpd/dpd.h"
#include "md/md.h"

/* MD: velocity Verlet with the md's potential and thermostat (md/md.h).
 * The model's self is a struct md_model. */
struct md_model {
    struct md *md;              /* borrowed from the case */
    double max_energy_change;   /* eV/atom; NVE runs only (0: no check) */
};
extern const struct sim_model_ops sim_model_md;

/* DPD/DPDE: the Shardlow-split step of dpd/dpd.h as stages (model_dpd.c).
 * The model's self is a struct dpd_model.  sim_model_dpd_ref is the same
 * model under another checkpoint group, for a second DPD system of the same
 * case (the reference run of an impact). */
struct dpd_model {
    struct dpd *d;              /* borrowed from the case */
    int snapshots;              /* 1: per-particle energies when a snapshot is due */
};
extern const struct sim_model_ops sim_model_dpd;
extern const struct sim_model_ops sim_model_dpd_ref;

/* The model named `name`, or NULL. */
const struct sim_model_ops *sim_model_find(const char *name);

#endif
