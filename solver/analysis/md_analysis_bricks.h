/*
 * md_analysis_bricks: the analysis of md_analysis.h on a brick
 * decomposition (core/halo.h), each rank on its own atoms.
 *
 * A class depends only on the atoms within the structure analysis' reach
 * (structure_range: the CNA cutoff, or the adaptive search radius, or the
 * surface radius, whichever is larger; 4.77 Å for Cu), so each rank
 *
 *   1. copies its owned atoms (positions, velocities, types, ids, marks)
 *      and adds the atoms of its neighbours within the reach plus the
 *      farthest an atom strayed from its brick since the last migration,
 *      as ghosts of an exchange of its own (halo_init_like, halo_build:
 *      the MD's ghosts and lists are not touched; the MD's own halo is
 *      the force cutoff plus skin, and only above the brick for a
 *      half-shell engine, so it is not used),
 *   2. classifies them all (structure_classify over owned + ghosts, the
 *      ghosts' positions bitwise their owners', so every owned atom sees
 *      the neighbours a serial run sees) and keeps the owned atoms'
 *      classes; the class counts and the displaced count are sums,
 *   3. finds the sputtered groups across the faces (sputter_bricks.h:
 *      local links, label propagation, the groups' sums merged on rank 0,
 *      the verdict broadcast),
 *   4. measures the crater from the height map of its target atoms,
 *      reduced over the ranks (the highest atom of each column and, at
 *      that height, the smallest id; the rim), which every rank floods
 *      alike (crater.h: crater_map_*, crater_flood),
 *   5. sends the damaged atoms' (id, x, y) to rank 0 (the damage shape's
 *      quantiles need every value; a few per cent of the atoms), which
 *      measures the shape in id order and broadcasts it,
 *
 * and every rank appends the same row and holds the same results (what a
 * checkpoint stores).  The per-atom fields (structure, displaced,
 * sputtered, crater) are written on the owners, so a collective snapshot
 * writes them.  The scratch (the copy, its ghosts, the frame) is freed
 * before the run goes on (md_analysis_release).
 *
 * Equal to the serial analysis of the same positions: the counts, the
 * classes and the groups exactly; the crater bitwise (the same map,
 * flooded in the same order); the damage shape to round-off (its sums
 * run in id order, a serial run's in its atoms' order).  Ties are broken
 * by id where the serial analysis breaks them by index: the atom of a
 * crater column among atoms at the same height (the serial run: the
 * first in its order), the target among two largest groups of one size.
 *
 * Bricks thinner than the reach plus twice that stray distance (along an
 * axis with an exchange) fall back to the former scheme: every atom
 * gathered on rank 0 in id order (halo_gather), the serial analysis
 * there, the results broadcast and the fields scattered back to the
 * owners; rank 0 then holds every atom while it analyses.
 */
#ifndef CASCADE_MD_ANALYSIS_BRICKS_H
#define CASCADE_MD_ANALYSIS_BRICKS_H

#include "analysis/md_analysis.h"
#include "core/halo.h"

/* md_analysis_run over the atoms of every rank of h (p: this rank's);
 * collective: every rank returns the same code and holds the same
 * results and rows.  Timed as TIMER_ANALYSIS when timers is not NULL. */
int md_analysis_run_bricks(struct md_analysis *a, struct halo *h, struct particles *p,
                           const struct box *box, double time, struct timers *timers,
                           struct err *e);

#endif
