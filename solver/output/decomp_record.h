/*
 * decomp_record: the `parallel` record of result.json for a run on bricks
 * (MD through md_output_decomposition, DPD directly): ranks, grid, owned particles per rank, their
 * max/mean imbalance and the peak resident memory of every rank.
 * Collective: every rank calls it, rank 0's result is written.
 */
#ifndef CASCADE_DECOMP_RECORD_H
#define CASCADE_DECOMP_RECORD_H

#include "core/halo.h"
#include "output/run.h"

void decomp_record_write(struct run *run, const struct halo *h, const struct particles *p);

#endif
