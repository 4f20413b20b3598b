/*
 * study_run: plan a loaded study with the solver, register it and run
 * every job not yet done for this solver -- what `cascade run` does, shared
 * with `cascade regress`.  Nothing is written (no database, no run
 * directory) unless the whole plan builds.
 */
#ifndef CASCADE_CAMPAIGN_STUDY_RUN_H
#define CASCADE_CAMPAIGN_STUDY_RUN_H

#include "plan.h"
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
    /* optional: drop jobs from the plan before it is registered and run
     * (adaptive refinement runs only some levels of each series) */
    int (*plan_filter)(void *ctx, struct plan *p, struct err *e);
    void *filter_ctx;
    double infra_pause;      /* seconds after a first infrastructure failure (doubling);
                              * 0: the default, 0.5 */
};

int study_run(const struct study *s, const struct study_run_opts *o, struct runner_summary *sum,
              struct err *e);

#endif
