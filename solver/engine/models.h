/*
 * models: the stage tables of the physics engines, by name.  Adding a model
 * (or a coupling) is one file model_<name>.c and one line in models.c.
 */
#ifndef CASCADE_MODELS_H
#define CASCADE_MODELS_H

#include "couple/dpd_mpm.h"
#include "engine/sim.h"
#include "dpd/dpd.h"
#include "md/md.h"
#include "scenarios/impact_boundary.h"

#include "mpm/mpm.h"

/* MD: velocity Verlet with the md's potential and thermostat (md/md.h).
 * The model's self is a struct md_model. */
struct md_model {
    struct md *md;              /* borrowed from the case */
    double max_energy_change;   /* eV/atom; NVE runs only (0: no check) */
    int peratom_always;         /* per-atom energies and virials every step
                                 * (boundaries that read them), not only at
                                 * snapshots */
    long peratom_every;         /* ... and every this many steps (0: never),
                                 * for a case's own sampling */
    long ck_offset, ck_total;   /* bricks: this rank's first row and all rows of a
                                 * checkpoint's atoms (checkpoint_collect) */
    int read_all;               /* bricks: a checkpoint read put every atom on every rank */
};
extern const struct sim_model_ops sim_model_md;

/* Bricks: the rows of a checkpoint's particle set this rank writes -- its
 * first (the owned particles of the lower ranks) and all of them.
 * Collective. */
int model_checkpoint_rows(struct halo *h, const struct particles *p, long *offset, long *total,
                          struct err *e);

/* Bricks: the stored particles of `group` whose positions (or values of
 * p's 3-component field `field`, e.g. the positions of the last list
 * build; NULL: the positions) lie in this rank's brick, with the bricks
 * cut over the stored box b first
 * (decomp_set_box), read in blocks (ckpt_get_particles_where: the memory
 * is the brick and one block, never the whole set) and in stored order,
 * so the rank holds what reading every particle and keeping its brick's
 * (halo_distribute) gave; ids checked unique over the ranks (one id in
 * two bricks is refused naming the file and dataset), and positions (and
 * the selecting field) more than a box length outside b refused too.  rc: the result of
 * the reads before.  Collective. */
int model_particles_read_brick(struct halo *h, const struct box *b, struct ckpt *ck,
                               const char *group, const char *field, struct particles *p, int rc,
                               struct err *e);
/* Each rank checked the ids of group it kept; one id on two ranks is
 * refused too.  Collective. */
int model_ids_unique_over_ranks(struct halo *h, const struct particles *p, struct ckpt *ck,
                                const char *group, struct err *e);

/* A checkpoint's atoms (group, e.g. "model/md/atoms") into md after its
 * box was read: serially all of them; on bricks each rank its brick's
 * (or, from a collective file, an even share that the sync migrates:
 * *read_all then tells md_decomposed_sync), ids checked unique over the
 * ranks.  rc: the result of the reads before (collective on bricks). */
int model_md_atoms_read(struct md *md, struct ckpt *ck, const char *group, int rc,
                        int *read_all, struct err *e);

/* An impact target's boundary treatment (scenarios/impact_boundary.h):
 * its pre_step before the md's drift, its step after the md's kick.  The
 * stateful variant (the handshake layers) cannot be checkpointed yet. */
struct impact_boundary_model {
    struct impact_boundary *bnd;   /* borrowed from the case */
    struct md *md;
};
extern const struct sim_model_ops sim_model_impact_boundary;
extern const struct sim_model_ops sim_model_impact_boundary_stateful;

/* The MPM/MD handshake (couple/handshake.h): one coupled step of the MPM
 * and the MD with a common dt (model_handshake.c).  The self is a struct
 * handshake_model; the MD is hs->md. */
struct handshake;
struct handshake_model {
    struct handshake *hs;       /* borrowed from the case */
    long ck_offset, ck_total;   /* bricks: this rank's first row and all rows of a
                                 * checkpoint's atoms (checkpoint_collect) */
    int read_all;               /* bricks: a checkpoint read put every atom on every rank */
};
extern const struct sim_model_ops sim_model_handshake;

/* MPM: MUSL/USL steps of an mpm (mpm/mpm.h) -- force: s9 and s1-s3,
 * integrate: s4-s14 -- on the case's time step rule, which the model owns
 * (it sets s->dt).  The model's self is a struct mpm_model. */
struct mpm_model {
    struct mpm *m;              /* borrowed from the case */
    double dt_fixed;            /* ps; 0: cfl x the explicit limit (mpm_stable_dt) */
    double cfl;
    int adaptive;               /* recompute the CFL step before every step */
    double load_ramp;           /* ps: loads reach full value after this (0: at once) */
    double max_energy_change;   /* relative; closed systems only (0: no check) */
    /* bricks (mpm/mpm_bricks.h; borrowed from the case), or NULL: the
     * stages exchange halo nodes and migrate points; a checkpoint's rows
     * are every rank's points in rank order, each rank writing its own */
    struct mpm_bricks *bricks;
    long ck_offset, ck_total;      /* bricks: this rank's first row and all rows of a
                                    * checkpoint's points (checkpoint_collect) */
    struct err sync_err;           /* bricks: what stopped checkpoint_sync (re-cut or
                                    * reorder), reported by the next step (code 0: none) */
};
extern const struct sim_model_ops sim_model_mpm;
/* The time step the model takes from its current state (ps). */
double mpm_model_timestep(const struct mpm_model *mm);

/* DPD/DPDE: the Shardlow-split step of dpd/dpd.h as stages (model_dpd.c).
 * The model's self is a struct dpd_model.  sim_model_dpd_ref is the same
 * model under another checkpoint group, for a second DPD system of the same
 * case (the reference run of an impact). */
struct dpd_model {
    struct dpd *d;              /* borrowed from the case */
    int snapshots;              /* 1: per-particle energies when a snapshot is due */
    long ck_offset, ck_total;   /* bricks: this rank's first row and all rows of a
                                 * checkpoint's particles (checkpoint_collect) */
    int sync_rc;                /* bricks: the redistribution after a checkpoint failed */
};
extern const struct sim_model_ops sim_model_dpd;
extern const struct sim_model_ops sim_model_dpd_ref;

/* DPD particles carried by the MPM grid, with or without material points:
 * the DPD/MPM-grid and the concurrent DPD/MPM models of Chen 2014
 * (couple/dpd_mpm.h).  The model's self is a struct dpd_mpm_model; several
 * instances (a run and its reference run) go in with sim_add_model_named. */
struct dpd_mpm_model {
    struct dpd_mpm *c;          /* borrowed from the case */
    int snapshots;              /* 1: per-particle energies when a snapshot is due (the
                                 * run whose particles are written) */
    long ck_offset, ck_total;   /* bricks: this rank's first row and all rows of a
                                 * checkpoint's particles (checkpoint_collect) */
    long ck_carried, ck_partners;   /* bricks: the classes' counts over the ranks */
    int read_all;               /* bricks: a checkpoint read put every particle on every
                                 * rank (1) or its brick's (2) */
    int sync_rc;                /* bricks: the redistribution after a checkpoint failed */
};
extern const struct sim_model_ops sim_model_dpd_mpm;

/* The model named `name`, or NULL. */
const struct sim_model_ops *sim_model_find(const char *name);

#endif
