/*
 * store: what the runner writes to the results database.
 *
 * Registering a study writes the study, its axes and its jobs in one
 * transaction.  Claiming a job takes a lease inside BEGIN IMMEDIATE: the
 * check that it is not done for this solver, not leased by a live runner and
 * has its preparation jobs done, the new 'running' run row and the lease are
 * one atomic step, so two runners never run a job twice.  Heartbeats extend
 * the leases; a lease that expired, or whose runner process is gone from
 * this host, is reaped: its run becomes 'cancelled' and the job runs again.
 */
#ifndef CASCADE_CAMPAIGN_STORE_H
#define CASCADE_CAMPAIGN_STORE_H

#include <sqlite3.h>

#include "outcome.h"
#include "plan.h"
#include "solver.h"
#include "study.h"

struct store {
    sqlite3 *db;                  /* borrowed */
    char runner[320];
    char host[256];
    int pid;
    char solver_version[128];
    char solver_git[128];
    char launcher[512];
    double lease_s;
    long retries;
    const char *const *metrics;   /* record only these (NULL: all) */
    int nmetrics;
    const char *const *series;    /* series to record (NULL: none) */
    int nseries;
    sqlite3_stmt *st[16];
    long last_metric_rows;        /* metric rows the last store_finish wrote */
    char note[1024];              /* what the last store_finish could not do besides
                                     recording (the `current` link), or "" */
    int pending;                  /* an outcome store_finish recorded with defer set
                                     waits for its commit (the transaction is open) */
    int pending_lost;             /* that commit failed: the outcome is not recorded
                                     (set until the caller clears it) */
};

int store_init(struct store *st, sqlite3 *db, const struct study *s, const struct solver *sv,
               double lease_s, struct err *e);
void store_fini(struct store *st);

/* Write the study and its jobs; job_ids[j] receives the id of plan job j. */
int store_register(struct store *st, const struct study *s, const struct plan *p,
                   long long *study_id, long long *job_ids, struct err *e);

enum claim_result {
    CLAIM_OK,         /* leased: run it */
    CLAIM_DONE,       /* done for this solver already */
    CLAIM_LEASED,     /* a live runner has it */
    CLAIM_WAIT,       /* a preparation job it needs is not done yet */
    CLAIM_BLOCKED,    /* a preparation job it needs failed for good */
    CLAIM_EXHAUSTED,  /* failed as often as the study allows, diverged, or crashed
                         deterministically (infrastructure failures never count) */
};

/* On CLAIM_OK: the new run's id, attempt number and directory (job_dir is
 * runs/<study>/<key>; the attempt's is job_dir/attempt-N).  With an outcome
 * pending (store_finish with defer), the claim runs in its transaction (a
 * savepoint, so a claim that fails undoes only itself) and its commit
 * records both; pending_lost says when that commit failed. */
int store_claim(struct store *st, long long job_id, const char *job_dir, enum claim_result *res,
                long long *run_id, int *attempt, char *run_dir, size_t run_dir_len,
                struct err *e);

/* Record an outcome and point the job's `current` link at run_dir, in the
 * transaction (so the link follows the order in which attempts were
 * recorded).  *lost is set when the lease was no longer ours (the job was
 * taken over after our lease expired): nothing is recorded or linked then.
 * A crash that repeats an earlier one of the job is reclassified
 * deterministic here (o->failure, o->message), as only the database knows
 * the earlier runs. */
int store_finish(struct store *st, long long job_id, long long run_id, const char *run_dir,
                 struct outcome *o, int *lost, int defer, struct err *e);

/* defer: the transaction is left open (st->pending) for the next claim to
 * commit with its own, one commit per job instead of two.  Until then
 * nothing of the outcome is in the database: a runner killed meanwhile
 * leaves the run 'running' under its lease, reaped and run again like any
 * run whose recording failed.  store_flush commits it (0 when nothing is
 * pending; on failure pending_lost is set and the outcome is rolled back).
 * Every other function of this file that writes flushes first, so the
 * caller need only flush before it waits for anything. */
int store_flush(struct store *st, struct err *e);

/* Undo a claim whose attempt was never started (a runner that stops with a
 * job claimed ahead, runner.c): its lease and its 'running' run are
 * deleted and the job's state is what it was before, as if never claimed.
 * Does nothing when the lease is no longer this runner's. */
int store_unclaim(struct store *st, long long job_id, long long run_id, struct err *e);

/* Extend this runner's leases. */
int store_heartbeat(struct store *st, struct err *e);
/* Whether this runner still holds the lease of run_id of a job (a runner
 * that was frozen past its lease may find that another runner took it). */
int store_lease_held(struct store *st, long long job_id, long long run_id, int *held,
                     struct err *e);
/* The run directory of a job's latest done run for this solver (after any
 * `cascade retry`), into dir; ERR_RUNTIME when it has none. */
int store_done_dir(struct store *st, long long job_id, char *dir, size_t len, struct err *e);
/* Reap expired and orphaned leases; *n the number reaped. */
int store_reap(struct store *st, int *n, struct err *e);

/* Slurm: record the Slurm ids of submitted attempts and the state Slurm
 * shows (PENDING when submitted, RUNNING once seen running), in one
 * transaction; ids are recorded before their array is released to run. */
int store_record_slurm_ids(struct store *st, int n, const long long *run_ids,
                           const char *const *slurm_ids, const char *state, struct err *e);

/* Slurm: the attempts of a study submitted to Slurm ('running' with a
 * Slurm id) whose runner is gone (or that are this runner's): their leases
 * become this runner's, and the runner follows them in Slurm instead of
 * submitting the jobs again.  *out is malloc'ed (the caller frees). */
struct store_adopted {
    long long job_id, run_id;
    int attempt;
    char run_dir[4096];
    char slurm_id[32];
};
int store_adopt(struct store *st, long long study_id, struct store_adopted **out, int *n,
                struct err *e);

/* Slurm: how many attempts of a study are in Slurm with no live runner
 * following them (a runner without Slurm must not run those jobs again). */
int store_slurm_orphans(struct store *st, long long study_id, int *n, struct err *e);

/* The verdict on a job for this solver, without changing anything. */
int store_job_verdict(struct store *st, long long job_id, enum claim_result *res, struct err *e);

#endif
