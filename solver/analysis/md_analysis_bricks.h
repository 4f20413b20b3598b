/*
 * md_analysis_bricks: the analysis of md_analysis.h on a brick
 * decomposition (core/halo.h).
 *
 * What the analyses need is not local to a brick: the sputtered groups
 * are connected components over the whole target (a group may span
 * bricks), the crater is a height map over the whole top face, and the
 * damage shape takes quantiles of all displaced atoms.  The analysis runs
 * every `analysis.every` steps (100 by default, against a step of about
 * 1e-5 of its cost per atom), so the simplest correct scheme is used:
 *
 *   1. every rank's atoms are gathered on rank 0 in id order (halo_gather),
 *   2. rank 0 runs the serial analysis (md_analysis_run) on them,
 *   3. the results (counts, sputter, crater, damage shape and the new row
 *      of the series) are broadcast, so every rank holds the serial
 *      analysis state (what a checkpoint stores, the displaced peak),
 *   4. the per-atom fields (structure, displaced, sputtered, crater) go
 *      back to the atoms' owners (a scatter in each rank's own order), so
 *      a collective snapshot writes them with the atoms.
 *
 * Rank 0 holds every atom (about 150 bytes each with the fields) and the
 * analysis' frame while it analyses; both are freed before the run goes
 * on (md_analysis_release), so between analyses its memory is its brick's.
 * The result is the serial analysis of the same positions: the atoms come
 * in id order instead of the serial run's spatial order, which changes
 * only the order of the damage shape's floating-point sums (round-off).
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
