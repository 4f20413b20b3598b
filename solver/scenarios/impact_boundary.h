/*
 * impact_boundary: how an impact target's faces other than its free top
 * are treated -- the `target.boundary` choice of a cluster_impact case.
 *
 *   fixed_damped  pure MD.  Atoms within fixed_thickness of the bottom and
 *                 of the four sides are held in place (Guo & Yang 2005,
 *                 section 3.2: "the rest five surfaces are fixed"); the
 *                 next damped_thickness carry a Langevin bath at the target
 *                 temperature with friction time damping_time, which
 *                 absorbs outgoing waves before they reflect from the fixed
 *                 atoms back into the crater region.
 *   handshake     the MD target embedded in hierarchical MPM layers through
 *                 the MPM/MD handshake (Guo & Yang 2005, section 2.2 and
 *                 Fig. 12): solver/scenarios/handshake_impact.h.
 *
 * Extension point.  A treatment is a row of impact_boundaries[] with
 *   read(target, b)        its keys in the `target` section (state it
 *                          allocates goes to b->data: destroy frees it,
 *                          also when reading or building fails);
 *   prepare(b, lo, hi, p, type, box, pot, nthreads, cfg)
 *                          once the target's extent [lo, hi] (atom
 *                          positions) and atom type are known, before the
 *                          atoms are built and the box is cut into bricks:
 *                          builds what the treatment owns (the handshake:
 *                          the whole MPM side) and widens the box for the
 *                          particles it will add (optional);
 *   add_particles(b, &p, halo)
 *                          with the target and cluster built (on bricks:
 *                          the rank's atoms): appends the treatment's own
 *                          particles (the handshake: the MD copies of the
 *                          material points of regions II and III; on
 *                          bricks those in the rank's brick) (optional,
 *                          with prepare);
 *   setup(b, md, lo, hi)   after md_init: mark groups in p->mask, set
 *                          md->frozen_mask and the thermostat, and tie
 *                          whatever it owns to the md;
 *   pre_step(b, md)        before every md_step (the handshake: region I to
 *                          the MPM, the MPM layers one dt on, the region
 *                          II/III atoms to their material points) (optional);
 *   step(b, md)            after every md_step (optional);
 *   exclude_mask(b)        the groups the damage counts leave out;
 *   report(b, result)      the treatment's own metrics (optional);
 *   destroy(b);
 *   stateless              checkpoints may be written (nothing of its own
 *                          changes during the run), or
 *   checkpoint_write/read/sync  its own state in a checkpoint (the
 *                          handshake: its material points and counters).
 * In the engine (engine/sim.h) the treatment is a model that runs pre_step
 * as its pre_force stage (before the md's) and step as its post_step
 * stage (after the md's integrate): engine/model_impact_boundary.c.
 * b->peratom asks for per-atom energies and virials at every step.
 */
#ifndef CASCADE_IMPACT_BOUNDARY_H
#define CASCADE_IMPACT_BOUNDARY_H

#include <stdint.h>

#include "md/md.h"
#include "util/cfg.h"

/* Group bits of impact cases (bit 0 is "all"). */
enum {
    IMPACT_GROUP_FIXED = 1u << 1,
    IMPACT_GROUP_DAMPED = 1u << 2,
    IMPACT_GROUP_CLUSTER = 1u << 3,
};

struct impact_boundary {
    const struct impact_boundary_ops *ops;
    double fixed_thickness;   /* Å */
    double damped_thickness;  /* Å */
    double damping_time;      /* ps */
    double temperature;       /* K */
    double a;                 /* Å: target.a (the case sets it before prepare) */
    long nfixed, ndamped;
    int peratom;              /* per-atom virials every step (not just at snapshots) */
    void *data;               /* the treatment's own state */
    /* target.handshake.thermal.from_potential (impact_from_potential.h),
     * which the treatment reads and impact_boundary_free frees; the case
     * hands it to the boundary of its second read at a(T), for the
     * metrics.  NULL when a(T) is an input. */
    struct impact_from_potential *from_potential;
};

struct result;
struct ckpt;
struct halo;

struct impact_boundary_ops {
    const char *name;
    int (*read)(struct cfg_obj *target, struct impact_boundary *b);
    int (*setup)(struct impact_boundary *b, struct md *md, const double lo[3], const double hi[3],
                 struct err *e);
    int (*step)(struct impact_boundary *b, struct md *md, struct err *e);
    uint32_t (*exclude_mask)(const struct impact_boundary *b);
    void (*destroy)(struct impact_boundary *b);
    int (*prepare)(struct impact_boundary *b, const double lo[3], const double hi[3],
                   const struct particles *p, int type, struct box *box, struct potential *pot,
                   int nthreads, struct cfg *cfg);
    int (*pre_step)(struct impact_boundary *b, struct md *md, struct err *e);
    void (*report)(const struct impact_boundary *b, struct result *r);
    /* 1: all the treatment's state is rebuilt from the case (a checkpoint
     * of the md restores the run); 0: it has state of its own, which the
     * three functions below store, read back and resynchronise (without
     * them the treatment cannot be checkpointed) */
    int stateless;
    int (*checkpoint_write)(const struct impact_boundary *b, struct ckpt *ck, const char *group);
    int (*checkpoint_read)(struct impact_boundary *b, struct ckpt *ck, const char *group);
    void (*checkpoint_sync)(struct impact_boundary *b);
    int (*add_particles)(struct impact_boundary *b, struct particles **p, const struct halo *halo,
                         struct err *e);
    /* before rank 0 writes a checkpoint, on every rank (collective on
     * bricks: the handshake gathers its material points); NULL: nothing */
    int (*checkpoint_collect)(struct impact_boundary *b, struct err *e);
    /* on bricks, after rank 0 wrote the checkpoint, on every rank with the
     * file open through MPI-IO: this rank's part of the state (the
     * handshake's material points) into `group`; NULL: nothing */
    int (*checkpoint_write_part)(const struct impact_boundary *b, struct ckpt *ck,
                                 const char *group);
};

extern const struct impact_boundary_ops impact_boundaries[];   /* NULL-name terminated */

/* Read `boundary` and the chosen treatment's keys from `target`. */
int impact_boundary_read(struct cfg_obj *target, struct impact_boundary *b);

/* The treatment's destroy, when it has one and was read. */
void impact_boundary_free(struct impact_boundary *b);

#endif
