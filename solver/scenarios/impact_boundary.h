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
 *                 Fig. 12).  Not available yet: it needs the MPM solver
 *                 (solver/mpm) and the handshake (solver/couple).  The case
 *                 accepts the name and refuses it with a clear message.
 *
 * Extension point.  A treatment is a row of impact_boundaries[] with
 *   read(target, b)        its keys in the `target` section;
 *   setup(b, md, lo, hi)   after md_init: mark groups in p->mask, set
 *                          md->frozen_mask and the thermostat, and build
 *                          whatever it owns (the handshake: the MPM layers
 *                          around [lo, hi], regions I-III of Fig. 3, their
 *                          material points on lattice sites);
 *   step(b, md)            after every md_step (the handshake: move the
 *                          region II/III atoms with their material points
 *                          and advance the MPM layers by the same dt);
 *   exclude_mask(b)        the groups the damage counts leave out;
 *   destroy(b).
 * `handshake` then replaces its read() by a real one and fills in the
 * rest; the case type does not change.
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
    long nfixed, ndamped;
    void *data;               /* the treatment's own state */
};

struct impact_boundary_ops {
    const char *name;
    int (*read)(struct cfg_obj *target, struct impact_boundary *b);
    int (*setup)(struct impact_boundary *b, struct md *md, const double lo[3], const double hi[3],
                 struct err *e);
    int (*step)(struct impact_boundary *b, struct md *md, struct err *e);
    uint32_t (*exclude_mask)(const struct impact_boundary *b);
    void (*destroy)(struct impact_boundary *b);
};

extern const struct impact_boundary_ops impact_boundaries[];   /* NULL-name terminated */

/* Read `boundary` and the chosen treatment's keys from `target`. */
int impact_boundary_read(struct cfg_obj *target, struct impact_boundary *b);

#endif
