/*
 * final_state: output.final_state for a run on one process, replicated on
 * every rank, or split over bricks.  With bricks every rank's owned
 * particles are gathered on rank 0 in id order (halo_gather, collective:
 * every rank must call this) and rank 0 writes them, so the file is the
 * serial run's whatever the rank count.  Nothing is gathered when the case
 * asks for no final state.
 */
#ifndef CASCADE_FINAL_STATE_H
#define CASCADE_FINAL_STATE_H

#include "core/halo.h"
#include "output/run.h"

/* `halo` NULL: `p` is the whole state (serial or replicated). */
int final_state_write(struct run *run, struct halo *halo, const struct particles *p,
                      const struct box *b, long step, double time, struct err *e);

#endif
