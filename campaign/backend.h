/*
 * backend: where job attempts run.  The runner hands a backend launch specs
 * for its slots and receives outcomes; it never learns whether the job ran
 * as a child process here (backend_local) or on an MPI worker rank
 * (backend_mpi).
 */
#ifndef CASCADE_CAMPAIGN_BACKEND_H
#define CASCADE_CAMPAIGN_BACKEND_H

#include <sys/types.h>

#include "launch.h"
#include "outcome.h"

/* Called for each finished slot; the outcome is the callee's to keep or
 * free (outcome_free). */
typedef void (*backend_done_fn)(void *ctx, int slot, struct outcome *o);

struct backend {
    int nslots;
    void *impl;
    /* Starting a job costs the runner little beyond the claim (local child
     * processes): while every slot is busy, the runner claims the next job
     * and writes its directory, and starts it as soon as a slot is freed,
     * before recording the job that freed it (runner.c). */
    int claim_ahead;
    int (*start)(struct backend *b, int slot, const struct launch_spec *L, struct err *e);
    /* Wait up to max_wait seconds for finished slots (calling done for each)
     * or a signal; returns the signal caught (SIGINT, SIGTERM, SIGHUP) or 0. */
    int (*wait)(struct backend *b, double max_wait, backend_done_fn done, void *ctx);
    /* Stop the job in a slot; its outcome (cancelled) arrives through wait. */
    void (*cancel)(struct backend *b, int slot);
    void (*destroy)(struct backend *b);

    /* Backends whose jobs outlive the runner (Slurm); NULL elsewhere. */
    /* Follow an attempt submitted by an earlier runner (job plan index,
     * run directory, the id it had there) in a free slot. */
    int (*adopt)(struct backend *b, int slot, long plan_index, const char *run_dir,
                 const char *external_id, struct err *e);
    /* Stop following a slot without touching the job (its lease went to
     * another runner); its outcome (not recorded) arrives through wait. */
    void (*release)(struct backend *b, int slot);
    /* Set by the runner: called with the ids of attempts just submitted
     * (state "PENDING"), before they may start -- a non-zero return calls
     * the submission off -- and again when they are seen running. */
    int (*submitted)(void *ctx, int n, const int *slots, const char *const *ids,
                     const char *state, struct err *e);
    void *submitted_ctx;
};

/* The signals the runner handles are blocked from here on and taken with
 * sigtimedwait; children get them unblocked. */
void backend_block_signals(void);

/* Child processes on this host; nslots at least 1. */
int backend_local_create(struct backend *b, int nslots, struct err *e);

/* The executor underneath backend_local, also used by MPI worker ranks. */
struct exec_local;
struct exec_local *exec_local_create(int nslots);
void exec_local_destroy(struct exec_local **x);
int exec_local_start(struct exec_local *x, int slot, const struct launch_spec *L, struct err *e);
int exec_local_wait(struct exec_local *x, double max_wait, backend_done_fn done, void *ctx);
void exec_local_cancel(struct exec_local *x, int slot);
int exec_local_busy(const struct exec_local *x);
/* The process (group leader) of the job in a slot; 0 when the slot is free. */
pid_t exec_local_pid(const struct exec_local *x, int slot);

#endif
