/*
 * childenv: the environment of every process cascade starts.
 *
 * Under mpirun, Open MPI puts OMPI_* and PMIX_* variables into each rank's
 * environment; a solver started with them believes it is a rank of the
 * runner's MPI job (and its own MPI_Init hangs or joins the wrong job).  So
 * children get the environment without them -- except OMPI_ALLOW_RUN_AS_ROOT
 * and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM, which the user sets and a job's own
 * mpirun needs when run as root.  Nor do they get the CASCADE_FAULT_*
 * variables (util/fault.h, campaign/db_fault.h): a fault injected into the
 * runner is meant for the runner, not for every solver it starts.
 */
#ifndef CASCADE_CAMPAIGN_CHILDENV_H
#define CASCADE_CAMPAIGN_CHILDENV_H

/* Whether a "NAME=value" entry is one the children must not see. */
int childenv_is_mpi(const char *entry);

/* Whether it is a CASCADE_FAULT_* entry. */
int childenv_is_fault(const char *entry);

/* A NULL-ended copy of environ without those entries (the strings are
 * borrowed from environ; free only the array). */
char **childenv_create(void);

#endif
