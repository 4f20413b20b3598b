/*
 * outcome: how one attempt at a job ended -- its class, exit code or signal,
 * message, the tail of its stderr, its metrics and the files it left --
 * gathered where the job ran and (under MPI) sent to rank 0 as JSON.
 *
 * Classes (runs.status): done (exit 0 and result.json says ok), failed
 * (non-zero exit, or no usable result.json), crashed (ended by a signal the
 * runner did not send), timeout (the runner killed it at the time limit),
 * diverged (exit 4 or result.json says diverged), cancelled (the runner
 * stopped it on request, or an infrastructure failure called it off).
 *
 * Failure classes (runs.failure_class) say whom a failure is charged to:
 * the job (failed, crashed, timeout, diverged: counts against the study's
 * retries), or the infrastructure (the run directory could not be written,
 * the disk is full, the solver could not be started, the runner went away:
 * recorded as cancelled, never charged, the job runs again).  A crash that
 * repeats an earlier one of the same job (the same signal at the same step,
 * or the same signal when the step is unknown) is deterministic: it is not
 * retried again (store_finish decides, as it needs the earlier runs).
 */
#ifndef CASCADE_CAMPAIGN_OUTCOME_H
#define CASCADE_CAMPAIGN_OUTCOME_H

#include <jansson.h>

#include "util/err.h"

enum run_status { RS_RUNNING, RS_DONE, RS_FAILED, RS_CRASHED, RS_TIMEOUT, RS_DIVERGED, RS_CANCELLED };

const char *run_status_name(enum run_status s);

enum failure_class { FC_NONE, FC_JOB, FC_INFRA, FC_DETERMINISTIC };
/* runs.failure_class: NULL (done, running, cancelled on request), "job",
 * "infrastructure", "deterministic". */
const char *failure_class_name(enum failure_class c);

/* "SIGKILL" for 9, ... ("SIGRTMIN+n", "signal n" beyond). */
const char *outcome_signal_name(int sig, char *buf, size_t len);
/* Whether a status counts against the study's retries (and is retried). */
int run_status_retryable(enum run_status s);

#define OUTCOME_TAIL_MAX 2048
#define OUTCOME_MSG_MAX 1024

struct artifact {
    char path[4096];
    char kind[16];
    long long bytes;
    char sha256[65];
};

struct outcome {
    enum run_status status;
    enum failure_class failure;
    int exit_code;              /* -1 when a signal ended it */
    int signal;                 /* 0 when it exited */
    long last_step;             /* last step in its thermo.csv when it did not finish, -1: unknown */
    long resumed_from_step;     /* the checkpoint step it continued from (result.json), -1: none */
    char message[OUTCOME_MSG_MAX];
    double started, finished;   /* Unix time */
    double wall_s;
    double peak_rss_mib;
    int pid;
    char host[256];
    char stderr_tail[OUTCOME_TAIL_MAX];
    char solver_version[128];   /* from result.json provenance, or "" */
    char solver_git[128];
    json_t *metrics;            /* {name: {"value": x, "unit": u}}, owned, or NULL */
    json_t *series;             /* {name: {"values": [...], "unit": u}}, owned, or NULL */
    struct artifact *artifacts; /* owned */
    int nartifacts;
    double collect_s;           /* time spent reading result.json and hashing files */
    char slurm_state[24];       /* the Slurm state it ended in (runs.slurm_state), or "" */
};

/* How the process ended, as the executor saw it. */
struct exit_info {
    int wait_status;            /* from waitpid */
    int timed_out;              /* the runner killed it at the limit */
    int cancelled;              /* the runner stopped it on request */
    double timeout;             /* the limit, for the message */
    int exec_failed;            /* the program could not be started */
};

/* Classify and read run_dir (result.json, stderr, the files). */
void outcome_collect(struct outcome *o, const char *run_dir, const struct exit_info *x);
/* An attempt that could not be started (an infrastructure failure):
 * o is reset and filled, with "could not start: <why>" as its message. */
void outcome_start_failure(struct outcome *o, const char *why);
void outcome_free(struct outcome *o);

json_t *outcome_to_json(const struct outcome *o);
int outcome_from_json(struct outcome *o, const json_t *j, struct err *e);

/* The last `maxlines` lines (at most `len` bytes) of a file. */
void outcome_file_tail(const char *path, int maxlines, char *out, size_t len);

#endif
