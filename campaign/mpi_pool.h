/*
 * mpi_pool: the one file of cascade that talks MPI (mpi.h is included
 * nowhere else).  Under `mpirun -np N cascade run ...`, rank 0 owns the
 * database and sends jobs to ranks 1..N-1, which run them and send back
 * their outcomes.  Messages are JSON text with a tag.
 *
 * MPI is initialised only when the environment shows that mpirun started
 * this process (OMPI_COMM_WORLD_SIZE or PMIX_RANK); a plain `cascade run`
 * never initialises it, even when its jobs use an mpirun launcher.
 */
#ifndef CASCADE_CAMPAIGN_MPI_POOL_H
#define CASCADE_CAMPAIGN_MPI_POOL_H

#include "util/err.h"

enum mpi_pool_tag { MPI_TAG_JOB = 1, MPI_TAG_RESULT = 2, MPI_TAG_CANCEL = 3, MPI_TAG_STOP = 4 };

/* Whether mpirun started this process (environment only; no MPI call). */
int mpi_pool_wanted(void);

int mpi_pool_init(int *argc, char ***argv, int *rank, int *size, struct err *e);
void mpi_pool_finalize(void);
void mpi_pool_abort(int code);

int mpi_pool_send(int dest, int tag, const char *text, struct err *e);
/* A waiting message, if any: returns 1 and sets src, tag and text (malloc'ed,
 * NUL-ended); 0 when none; -1 on error. */
int mpi_pool_poll(int *src, int *tag, char **text, struct err *e);

#endif
