/* thread_accum: private buffers and their ordered reduction. */
#include "core/thread_accum.h"

#include <stdlib.h>
#include <string.h>

int thread_accum_reserve(struct thread_accum *ta, int nthreads, size_t len, struct err *e)
{
    if (nthreads > THREAD_ACCUM_MAX)
        return err_set(e, ERR_INPUT, "at most %d threads are supported", THREAD_ACCUM_MAX);
    if (len > ta->cap || nthreads > ta->nthreads) {
        for (int t = 1; t < THREAD_ACCUM_MAX; t++) {
            free(ta->buf[t]);
            ta->buf[t] = NULL;
        }
        size_t cap = len + len / 4 + 64;
        for (int t = 1; t < nthreads; t++) {
            ta->buf[t] = malloc(cap * sizeof(double));
            if (!ta->buf[t])
                return err_nomem(e, "thread buffers");
        }
        ta->cap = cap;
    }
    ta->nthreads = nthreads;
    return 0;
}

double *thread_accum_target(struct thread_accum *ta, int tid, double *shared, size_t len)
{
    if (tid == 0)
        return shared;
    memset(ta->buf[tid], 0, len * sizeof(double));
    return ta->buf[tid];
}

void thread_accum_reduce(struct thread_accum *ta, double *shared, size_t len)
{
    for (int t = 1; t < ta->nthreads; t++) {
        const double *b = ta->buf[t];
        for (size_t k = 0; k < len; k++)
            shared[k] += b[k];
    }
}

void thread_accum_free(struct thread_accum *ta)
{
    for (int t = 1; t < THREAD_ACCUM_MAX; t++) {
        free(ta->buf[t]);
        ta->buf[t] = NULL;
    }
    ta->cap = 0;
    ta->nthreads = 0;
}
