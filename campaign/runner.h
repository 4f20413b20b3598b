/*
 * runner: runs a registered plan to completion on a backend.
 *
 * Jobs are claimed in plan order (preparation jobs first); a job waits while
 * a preparation job it reads is not done, and is given up when that job
 * failed for good.  Failed, crashed and timed-out attempts are retried as
 * the study allows; diverged runs are not (the same case diverges again),
 * nor is a crash that repeats an earlier one (deterministic).
 *
 * Infrastructure failures (the run directory cannot be written, the disk is
 * full, the solver cannot be started) are not the job's: they are recorded
 * (cancelled, failure_class 'infrastructure') without using up its retries,
 * and the runner starts nothing for a while (infra_backoff_s, doubling with
 * each failure in a row), then one job at a time until an attempt runs to
 * an outcome of its own; after infra_limit in a row it stops with the last
 * one's message (which names the path) and returns ERR_RUNTIME, letting
 * running jobs finish.
 * A job leased by another live runner is left to it and looked at again
 * later, so every runner of a study returns when the study is complete.
 * A runner that finds at a heartbeat that it lost a lease (it was frozen
 * past it and another runner took the job over) stops that attempt and
 * records nothing of it; the attempt wrote only its own directory.
 *
 * Signals: the first SIGINT stops claiming and lets running jobs finish; a
 * second SIGINT, or SIGTERM/SIGHUP, cancels them (recorded 'cancelled').
 * With a backend whose jobs outlive the runner (Slurm), SIGHUP (a closed
 * login session) leaves them queued and running instead: the next runner
 * adopts them (store_adopt).
 */
#ifndef CASCADE_CAMPAIGN_RUNNER_H
#define CASCADE_CAMPAIGN_RUNNER_H

#include <sqlite3.h>
#include <stdio.h>

#include "backend.h"
#include "plan.h"
#include "solver.h"
#include "study.h"

struct runner_options {
    const char *runs_root;   /* absolute */
    double lease_s;          /* lease length; heartbeats every third of it */
    double poll_s;           /* how often to look at jobs other runners hold */
    int quiet;
    FILE *log;               /* progress and notes (stderr) */
    double infra_backoff_s;  /* pause after the first infrastructure failure in a row */
    int infra_limit;         /* stop after this many in a row */
};

struct runner_summary {
    long total, done, done_before, failed, cancelled, not_run;
    int interrupted;         /* the signal that stopped the run, or 0 */
    long started;            /* attempts started here */
    double start_s;          /* time spent claiming and starting them */
    long metric_rows;        /* metric rows recorded */
    double record_s;         /* time spent reading results and writing them to the database */
    double gap_s;            /* time slots stood empty between a job's exit (reaped) and the
                                next start in them (the runner's share of the critical path) */
    long gaps;               /* starts that refilled a slot, over which gap_s is summed */
};

int runner_run(const struct study *s, const struct plan *p, const struct solver *sv, sqlite3 *db,
               struct backend *b, const struct runner_options *o, struct runner_summary *sum,
               struct err *e);

#endif
