/*
 * parallel_settings: the case's optional `parallel` section -- how one
 * simulation is spread over the ranks of an mpirun.
 *
 *   parallel:
 *     decomposition: auto     # auto | replicated | bricks
 *     grid: [2, 1, 1]         # bricks per axis (default: chosen from the box)
 *     balance: none           # none | shift (bricks: cuts at the particles'
 *                             # quantiles along each axis, decomp_shift)
 *
 * replicated: every rank holds every particle and computes the forces of
 * a slice (the trajectory is the serial one, bitwise).  bricks: each rank
 * owns the particles of one brick of the box and exchanges ghosts with its
 * neighbours (core/halo.h): memory and work per rank fall with the rank
 * count.  auto: bricks for the case types that are decomposed (`md`) when
 * run on more than one rank, replicated data otherwise.  The section is
 * not written into the resolved case when absent, so job keys of existing
 * cases do not change.  Without mpirun the section is ignored (a serial
 * run).
 */
#ifndef CASCADE_PARALLEL_SETTINGS_H
#define CASCADE_PARALLEL_SETTINGS_H

#include "util/cfg.h"

enum decomposition { DECOMP_AUTO = 0, DECOMP_REPLICATED = 1, DECOMP_BRICKS = 2 };
enum balance { BALANCE_NONE = 0, BALANCE_SHIFT = 1 };

struct parallel_settings {
    enum decomposition decomposition;
    int grid[3];
    int grid_given;
    enum balance balance;     /* absent: none, and not written into the case */
    long balance_every;       /* steps between checks; 0 (absent): set-up only */
    double balance_threshold; /* max/mean owned above which a check shifts */
    int given;                /* the section is in the case */
};

int parallel_settings_read(struct cfg_obj *root, struct parallel_settings *ps);

/* A given `grid` must cut the box into exactly one brick per rank: 0, or
 * the config error at `parallel.grid` (every decomposed model checks this
 * first, before its own brick-width rule). */
int parallel_settings_check_grid_ranks(struct cfg *c, const struct parallel_settings *ps,
                                       int ranks);

#endif
