/*
 * study_run: plan a loaded study with the solver, register it and run
 * every job not yet done for this solver -- what `cascade run` does, shared
 * with `cascade regress`.  Nothing is written (no database, no run
 * directory) unless the whole plan builds.
 */
#ifndef CASCADE_CAMPAIGN_STUDY_RUN_H
#define CASCADE_CAMPAIGN_STUDY_RUN_H

#include "runner.h"
#include "study.h"

struct study_run_opts {
    const char *db_path;
    const char *runs;        /* run directories root (created) */
    const char *solver;      /* --solver, or NULL */
    long jobs;               /* 0: cores / (threads x mpirun ranks) */
    double lease;            /* seconds */
    int quiet;
    int mpi_size;            /* > 1: rank 0 of an MPI runner with mpi_size - 1 workers */
    double infra_pause;      /* seconds after a first infrastructure failure (doubling);
                              * 0: the default, 0.5 */
};

int study_run(const struct study *s, const struct study_run_opts *o, struct runner_summary *sum,
              struct err *e);

#endif
