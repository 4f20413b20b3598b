/*
 * final_state: output.final_state for a run on one process, replicated on
 * every rank, or split over bricks.  With bricks the owned particles of
 * every rank pass to rank 0 in id order a window of HALO_GATHER_WINDOW at
 * a time (halo_gather_windows, collective: every rank must call this;
 * twice for a data file, its Atoms then its Velocities) and rank 0 writes
 * them after a header with the totals: the serial run's header and atoms
 * (to round-off) whatever the rank count, in id order (a serial run
 * writes its own order), and no rank holds every particle.  Nothing is
 * gathered when the case asks for no final state.
 */
#ifndef CASCADE_FINAL_STATE_H
#define CASCADE_FINAL_STATE_H

#include "core/halo.h"
#include "output/run.h"

/* `halo` NULL: `p` is the whole state (serial or replicated). */
int final_state_write(struct run *run, struct halo *halo, const struct particles *p,
                      const struct box *b, long step, double time, struct err *e);

#endif
