/*
 * slurm_state: what Slurm says about a job, as our outcome classes.
 *
 *   PENDING, RUNNING, COMPLETING, ...        still going
 *   COMPLETED                                read result.json (done, or failed)
 *   FAILED                                   the exit code or signal, as locally
 *   OUT_OF_MEMORY                            failed, "out of memory"
 *   TIMEOUT, DEADLINE                        timeout
 *   NODE_FAIL, PREEMPTED, BOOT_FAIL, REVOKED not the job's fault: cancelled,
 *                                            failure_class infrastructure, runs again
 *   CANCELLED                                cancelled (by the runner, cascade
 *                                            cancel or scancel)
 *   PENDING, "launch failed requeued held"   Slurm could not start the batch
 *                                            script on its node and holds the
 *                                            task for an administrator: the
 *                                            runner cancels it; infrastructure,
 *                                            runs again
 */
#ifndef CASCADE_CAMPAIGN_SLURM_STATE_H
#define CASCADE_CAMPAIGN_SLURM_STATE_H

#include "outcome.h"

/* One line of `squeue -O` (slurm_squeue_format). */
struct slurm_task {
    char id[32];          /* "4711_3" */
    char state[24];
    int exit_status;      /* a wait status */
    double elapsed_s;
    char nodes[256];
    double start, end;    /* Unix time, 0: unknown */
    char reason[64];
};

/* The -O argument of squeue that slurm_parse_task reads. */
extern const char slurm_squeue_format[];

/* Parse one line; 0, or -1 when it is not one. */
int slurm_parse_task(const char *line, struct slurm_task *t);

/* Whether a state is final. */
int slurm_state_final(const char *state);

/* What the runner does about a task that is still in the queue. */
enum slurm_queued_action {
    SQ_WAIT,           /* queued or running: look again at the next poll */
    SQ_CANCEL_AGAIN,   /* the runner cancelled it and it is pending again */
    SQ_LAUNCH_FAILED,  /* held by Slurm after its batch launch failed */
};

/* cancel_sent: the runner has sent scancel for this task. */
enum slurm_queued_action slurm_queued_action(const struct slurm_task *t, int cancel_sent);

/* The outcome of an attempt that ended in Slurm: classified from the state
 * and exit status, result.json and the files read from run_dir.
 * by_runner: the runner cancelled it (on request).  limit: its time limit
 * as written, for the message. */
void slurm_outcome(struct outcome *o, const struct slurm_task *t, const char *run_dir,
                   int by_runner, const char *limit);

/* Accounting (when the cluster has it): the --format of sacct -n -P that
 * slurm_parse_sacct reads, one line per job and per step ("4711_3.batch");
 * *step says which, *rss is MaxRSS in MiB (0 when not given). */
extern const char slurm_sacct_format[];
int slurm_parse_sacct(const char *line, struct slurm_task *t, int *step, double *rss);

/* Seconds of "M:SS", "H:MM:SS", "D-HH:MM:SS" (squeue's TimeUsed); -1 when not. */
double slurm_elapsed_seconds(const char *text);

#endif
