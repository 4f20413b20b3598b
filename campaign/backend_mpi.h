/*
 * backend_mpi: job slots on the worker ranks of the runner's own MPI job
 * (`mpirun -np N cascade run ...`: N-1 slots), and the worker ranks' loop.
 */
#ifndef CASCADE_CAMPAIGN_BACKEND_MPI_H
#define CASCADE_CAMPAIGN_BACKEND_MPI_H

#include "backend.h"

int backend_mpi_create(struct backend *b, int nworkers, struct err *e);
/* Tell ranks 1..size-1 to leave their loop. */
void backend_mpi_stop_workers(int size);
/* The loop of ranks 1..N-1: run what rank 0 sends until told to stop. */
int backend_mpi_worker(void);

#endif
