/*
 * parallel: the one file of cascade-solver that talks MPI.
 *
 * A solver started by mpirun (Open MPI sets OMPI_COMM_WORLD_SIZE, PMIx sets
 * PMIX_RANK) initialises MPI; started any other way it does not, so a plain
 * run never pays for MPI.  With N > 1 ranks the MD engine runs replicated
 * data: every rank holds every particle, computes the forces of its slice of
 * owned particles (neighbour lists are built for the slice only), and the
 * partial forces, densities, energies and virials are summed over ranks.
 * Sums go to rank 0 and are broadcast back, so every rank holds bitwise the
 * same numbers and the replicated trajectories never drift apart.  Rank 0
 * alone writes output files.  (A spatial domain decomposition would replace
 * the sums by halo exchanges in core/ghost.c; the kernels would not change.)
 */
#ifndef CASCADE_PARALLEL_H
#define CASCADE_PARALLEL_H

#include <stddef.h>

#include "util/err.h"

struct parallel {
    int rank, size;
    int mpi;          /* MPI initialised by us */
};

/* Serial defaults (rank 0 of 1) unless launched by mpirun. */
int parallel_init(struct parallel *par, int *argc, char ***argv, struct err *e);
void parallel_finalize(struct parallel *par);

/* buf[k] <- sum over ranks of buf[k]; identical on every rank.  No-op in
 * serial runs (par NULL or size 1). */
void parallel_sum(const struct parallel *par, double *buf, size_t n);

/* This rank's slice [lo, hi) of n items. */
void parallel_range(const struct parallel *par, int n, int *lo, int *hi);

/* 1 on every rank when flag is non-zero on any rank. */
int parallel_any(const struct parallel *par, int flag);

#endif
