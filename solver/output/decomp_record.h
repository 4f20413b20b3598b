/*
 * decomp_record: the `parallel` record of result.json for a run on bricks
 * (MD through md_output_decomposition, DPD and MPM directly): ranks, grid, owned particles per rank, their
 * max/mean imbalance and the peak resident memory of every rank.
 * Collective: every rank calls it, rank 0's result is written.
 */
#ifndef CASCADE_DECOMP_RECORD_H
#define CASCADE_DECOMP_RECORD_H

#include "core/halo.h"
#include "output/run.h"

void decomp_record_write(struct run *run, const struct halo *h, const struct particles *p);

/* The same for any particle set on a grid of bricks: `owned` this rank's
 * particles (the MPM's material points). */
void decomp_record_write_counts(struct run *run, const struct parallel *par, const int grid[3],
                                long owned);

/* More of a run's own in the `parallel` record (created when not there
 * yet; decomp_record_write keeps what is there): `key` a per-rank count
 * with `<key>_imbalance_max_over_mean` (collective: `mine` is this rank's),
 * or one integer. */
void decomp_record_add_counts(struct result *res, const struct parallel *par, const char *key,
                              long mine);
void decomp_record_add_integer(struct result *res, const char *key, long value);

/* A hierarchical MPM grid held whole on every rank: its cell count
 * (`mpm_cells`) and the node tables each rank made, those of the cells
 * its particles lay in (`mpm_cell_tables_per_rank`; collective). */
void decomp_record_add_cell_tables(struct result *res, const struct parallel *par, long ncell,
                                   long made);

/* A dynamic balance's record (`parallel.balance_every`): the schedule, how
 * often it looked, how often it moved the cuts (checkpoint syncs
 * included) and the worst max/mean it found; nothing when every is 0. */
struct decomp_balance_record {
    long every;
    double threshold;
    long checks, shifts;
    double worst;
};
void decomp_record_add_balance(struct result *res, const struct decomp_balance_record *b);

#endif
