/*
 * outcome: how one attempt at a job ended -- its class, exit code or signal,
 * message, the tail of its stderr, its metrics and the files it left --
 * gathered where the job ran and (under MPI) sent to rank 0 as JSON.
 *
 * Classes (runs.status): done (exit 0 and result.json says ok), failed
 * (non-zero exit, or no usable result.json), crashed (ended by a signal the
 * runner did not send), timeout (the runner killed it at the time limit),
 * diverged (exit 4 or result.json says diverged), cancelled (the runner
 * stopped it on request).
 */
#ifndef CASCADE_CAMPAIGN_OUTCOME_H
#define CASCADE_CAMPAIGN_OUTCOME_H

#include <jansson.h>

#include "util/err.h"

enum run_status { RS_RUNNING, RS_DONE, RS_FAILED, RS_CRASHED, RS_TIMEOUT, RS_DIVERGED, RS_CANCELLED };

const char *run_status_name(enum run_status s);
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
    int exit_code;              /* -1 when a signal ended it */
    int signal;                 /* 0 when it exited */
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
    struct artifact *artifacts; /* owned */
    int nartifacts;
    double collect_s;           /* time spent reading result.json and hashing files */
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
void outcome_free(struct outcome *o);

json_t *outcome_to_json(const struct outcome *o);
int outcome_from_json(struct outcome *o, const json_t *j, struct err *e);

/* The last `maxlines` lines (at most `len` bytes) of a file. */
void outcome_file_tail(const char *path, int maxlines, char *out, size_t len);

#endif
