/*
 * handshake_impact: the MPM/MD handshake as the boundary of a cluster-impact
 * target, `target.boundary: handshake` of type cluster_impact (Guo & Yang
 * 2005, section 3.2 and Fig. 12: the MD target embedded in hierarchical MPM
 * layers).  The functions fill the `handshake` row of impact_boundaries[]
 * (solver/scenarios/impact_boundary.h).
 *
 *   target:
 *     boundary: handshake
 *     handshake:
 *       mpm: 16              lattice constants of MPM beyond the MD target on
 *                            its four sides and below it (its top stays free)
 *       regions: [2, 2, 2]   widths of regions I, II, III (lattice constants)
 *       cell: 1              finest cell (1 or 0.5 lattice constants)
 *       fine: 6              the coarse grid starts this far from the MD
 *       levels: 2            coarsening levels (0: uniform grid)
 *       coarsen: xyz         directions halved per level
 *       layer: 4             width of each coarse level before the next
 *
 * The outer faces of the MPM are fixed ("the rest five surfaces are fixed")
 * and its top is free, flush with the target's surface.  The MPM is cubic
 * elastic with the potential's 0 K constants; the target must be fcc at the
 * potential's lattice constant and at 0 K, unless
 *       elastic: {c11, c12, c44}          GPa, the MPM's constants (at T)
 *       thermal: {damping_time: 0.1, seed: 1}
 * are given: then the target may be at a temperature (target.a = a(T)) and
 * region II is under a Langevin bath (couple/handshake_thermal.h).  With
 *       thermal: {from_potential: {a_min, a_max, ...}}
 * the case computes a(T) and the constants at T itself instead
 * (impact_from_potential.h): target.a and elastic then stay out.  The
 * boundary's target.a is b->a, which the case sets before prepare.
 */
#ifndef CASCADE_HANDSHAKE_IMPACT_H
#define CASCADE_HANDSHAKE_IMPACT_H

#include "scenarios/impact_boundary.h"

int handshake_impact_read(struct cfg_obj *target, struct impact_boundary *b);
int handshake_impact_prepare(struct impact_boundary *b, const double lo[3], const double hi[3],
                             const struct particles *p, int type, struct box *box,
                             struct potential *pot, int nthreads, struct cfg *cfg);
int handshake_impact_add_particles(struct impact_boundary *b, struct particles **p,
                                   const struct halo *halo, struct err *e);
int handshake_impact_setup(struct impact_boundary *b, struct md *md, const double lo[3],
                           const double hi[3], struct err *e);
int handshake_impact_pre_step(struct impact_boundary *b, struct md *md, struct err *e);
uint32_t handshake_impact_exclude(const struct impact_boundary *b);
void handshake_impact_report(const struct impact_boundary *b, struct result *r);
void handshake_impact_destroy(struct impact_boundary *b);
/* The MPM layers and the handshake's counters in a checkpoint (the atoms
 * are the MD model's): couple/handshake.h. */
int handshake_impact_checkpoint_write(const struct impact_boundary *b, struct ckpt *ck,
                                      const char *group);
int handshake_impact_checkpoint_read(struct impact_boundary *b, struct ckpt *ck, const char *group);
void handshake_impact_checkpoint_sync(struct impact_boundary *b);
int handshake_impact_checkpoint_write_part(const struct impact_boundary *b, struct ckpt *ck,
                                           const char *group);
int handshake_impact_checkpoint_collect(struct impact_boundary *b, struct err *e);

#endif
