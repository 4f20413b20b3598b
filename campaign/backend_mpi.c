/*
 * backend_mpi: slots are the worker ranks 1..N-1 of the runner's MPI job;
 * rank 0 (the runner, which alone opens the database) sends each a launch
 * spec and receives the outcome.  Time limits are enforced on the worker.
 */
#include "backend_mpi.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mpi_pool.h"
#include "sysinfo.h"
#include "util/mem.h"

struct mpi_backend {
    int *busy;
};

static int mpi_start(struct backend *b, int slot, const struct launch_spec *L, struct err *e)
{
    struct mpi_backend *m = b->impl;
    json_t *j = launch_to_json(L);
    char *text = j ? json_dumps(j, JSON_COMPACT) : NULL;
    json_decref(j);
    if (!text)
        return err_nomem(e, "job message");
    int rc = mpi_pool_send(slot + 1, MPI_TAG_JOB, text, e);
    free(text);
    if (!rc)
        m->busy[slot] = 1;
    return rc;
}

static int mpi_wait(struct backend *b, double max_wait, backend_done_fn done, void *ctx)
{
    struct mpi_backend *m = b->impl;
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGCHLD);
    double until = sys_mono() + max_wait;
    int got = 0;
    for (;;) {
        int src, tag;
        char *text = NULL;
        struct err e = {0};
        int r = mpi_pool_poll(&src, &tag, &text, &e);
        if (r == 1) {
            if (tag == MPI_TAG_RESULT && src >= 1 && src <= b->nslots && m->busy[src - 1]) {
                json_error_t je;
                json_t *j = json_loads(text, 0, &je);
                struct outcome o;
                if (!j || outcome_from_json(&o, j, &e) != 0) {
                    char why[64];
                    snprintf(why, sizeof why, "bad result message from rank %d", src);
                    outcome_start_failure(&o, why);
                }
                json_decref(j);
                m->busy[src - 1] = 0;
                done(ctx, src - 1, &o);
                got++;
            }
            free(text);
            continue;   /* drain every waiting message */
        }
        if (got)
            return 0;
        double left = until - sys_mono();
        struct timespec ts = {0, left > 0.002 ? 2000000L : (left > 0 ? (long)(left * 1e9) : 0)};
        int sig = sigtimedwait(&set, NULL, &ts);
        if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP)
            return sig;
        if (sys_mono() >= until)
            return 0;
    }
}

static void mpi_cancel(struct backend *b, int slot)
{
    struct err e = {0};
    (void)b;
    mpi_pool_send(slot + 1, MPI_TAG_CANCEL, "{}", &e);
}

static void mpi_destroy(struct backend *b)
{
    struct mpi_backend *m = b->impl;
    if (m)
        free(m->busy);
    free(m);
    b->impl = NULL;
}

int backend_mpi_create(struct backend *b, int nworkers, struct err *e)
{
    memset(b, 0, sizeof *b);
    struct mpi_backend *m = mem_calloc(1, sizeof *m);
    if (m)
        m->busy = mem_calloc((size_t)nworkers, sizeof *m->busy);
    if (!m || !m->busy) {
        free(m);
        return err_nomem(e, "MPI backend");
    }
    b->impl = m;
    b->nslots = nworkers;
    b->start = mpi_start;
    b->wait = mpi_wait;
    b->cancel = mpi_cancel;
    b->destroy = mpi_destroy;
    return 0;
}

void backend_mpi_stop_workers(int size)
{
    struct err e = {0};
    for (int r = 1; r < size; r++)
        mpi_pool_send(r, MPI_TAG_STOP, "{}", &e);
}

/* --- worker ranks ------------------------------------------------------------ */

struct worker_ctx {
    int sent;
    struct err e;
};

static void worker_done(void *ctx, int slot, struct outcome *o)
{
    struct worker_ctx *w = ctx;
    (void)slot;
    json_t *j = outcome_to_json(o);
    char *text = j ? json_dumps(j, JSON_COMPACT) : NULL;
    json_decref(j);
    mpi_pool_send(0, MPI_TAG_RESULT, text ? text : "{}", &w->e);
    free(text);
    outcome_free(o);
    w->sent = 1;
}

int backend_mpi_worker(void)
{
    backend_block_signals();
    struct exec_local *x = exec_local_create(1);
    if (!x)
        return 1;
    struct worker_ctx w = {0, {0}};
    int stop = 0, rc = 0;
    while (!stop) {
        int src, tag;
        char *text = NULL;
        int r = mpi_pool_poll(&src, &tag, &text, &w.e);
        if (r < 0) {
            rc = 1;
            break;
        }
        if (r == 1) {
            if (tag == MPI_TAG_STOP) {
                stop = 1;
            } else if (tag == MPI_TAG_CANCEL) {
                if (exec_local_busy(x))
                    exec_local_cancel(x, 0);
            } else if (tag == MPI_TAG_JOB) {
                json_error_t je;
                json_t *j = json_loads(text, 0, &je);
                struct launch_spec L;
                struct err e = {0};
                if (j && launch_from_json(&L, j, &e) == 0) {
                    if (exec_local_start(x, 0, &L, &e) != 0) {
                        struct outcome o;
                        outcome_start_failure(&o, e.msg);
                        worker_done(&w, 0, &o);
                    }
                    launch_free(&L);
                } else {
                    struct outcome o;
                    outcome_start_failure(&o, "malformed job message");
                    worker_done(&w, 0, &o);
                }
                json_decref(j);
            }
            free(text);
            continue;
        }
        /* nothing from rank 0: look after the job (time limit, exit) */
        int sig = exec_local_wait(x, exec_local_busy(x) ? 0.005 : 0.002, worker_done, &w);
        if ((sig == SIGTERM || sig == SIGINT || sig == SIGHUP) && exec_local_busy(x))
            exec_local_cancel(x, 0);
    }
    exec_local_destroy(&x);
    return rc;
}
