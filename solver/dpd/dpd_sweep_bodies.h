/*
 * dpd_sweep_bodies: the pairs of the cell-coloured Shardlow sweep
 * (dpd_sweep_cells.c) that touch a free rigid body.  Internal to solver/dpd.
 *
 * A free body (the flyer) has one velocity, which every pair between one
 * of its particles and the rest changes: such pairs anchored in two cells
 * of one colour do not commute, so they cannot be swept colour by colour
 * on different ranks.  They are swept apart, before the colours, in one
 * global order -- (cell, lower id, higher id, periodic image), the order
 * of the colour sweep's keys -- by every rank alike: each rank sends the
 * body pairs of the cells it owns (geometry, random number, and both
 * particles' velocities and DPDE internal energies, current on every
 * copy), every rank receives all of them, sweeps them in that order
 * with the body's velocity (the same on every rank), and writes the new
 * velocities and energies into each of its copies by id.  No further
 * exchange is needed, the body's velocity and the impulse on it come out
 * bitwise the same on every rank, and a serial run with `sweep: cells`
 * makes the same updates in the same order.  (Prescribed bodies -- grips,
 * pistons -- keep their velocity: their pairs commute within a colour and
 * stay in the colour sweep.)
 */
#ifndef CASCADE_DPD_SWEEP_BODIES_H
#define CASCADE_DPD_SWEEP_BODIES_H

#include <stdint.h>

#include "dpd/dpd.h"
#include "dpd/dpd_ou.h"

/* One pair as the rank owning its anchor cell sees it. */
struct dpd_body_pair {
    double cell;              /* the anchor's cell key (dpd_sweep_cells.c) */
    int64_t id[2];            /* anchor (lower id), partner */
    uint32_t image;           /* the partner's periodic copy, as in the pair key */
    int32_t body[2];          /* body index of each side, -1 for none */
    double e[3], wr, xi;      /* unit vector anchor - partner, w^R, the pair's normal number */
    double winv[2];           /* inverse masses in the pair (a body's, 0 when prescribed) */
    double v[2][3], u[2];     /* both sides' velocities and internal energies */
};

/* Sweep the n body pairs this rank found, together with every other
 * rank's (collective on bricks), update this rank's copies (owned and
 * ghost) and the bodies' velocities, and add the impulses on the bodies
 * to imp (amu Å/ps, the same on every rank).  ERR_DIVERGED when an
 * internal energy falls to zero or below (on every rank alike). */
int dpd_sweep_bodies(struct dpd *d, const struct dpd_ou *ou, const struct dpd_body_pair *mine,
                     long n, double imp[DPD_MAX_BODIES][3], struct err *e);

#endif
