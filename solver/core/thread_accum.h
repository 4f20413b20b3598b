/*
 * thread_accum: per-thread accumulation buffers for half-list kernels.
 *
 * With a half list both particles of a pair receive a contribution, so
 * threads would race on j.  Thread 0 writes the real array; threads 1..T-1
 * write private copies that are added afterwards in thread order, so a given
 * thread count always gives the same sums.
 */
#ifndef CASCADE_THREAD_ACCUM_H
#define CASCADE_THREAD_ACCUM_H

#include <stddef.h>

#include "util/err.h"

#define THREAD_ACCUM_MAX 64

struct thread_accum {
    int nthreads;
    size_t cap;                    /* doubles per private buffer */
    double *buf[THREAD_ACCUM_MAX]; /* buf[0] unused */
};

/* Ensure T-1 private buffers of `len` doubles. */
int thread_accum_reserve(struct thread_accum *ta, int nthreads, size_t len, struct err *e);
/* The array thread `tid` accumulates into (zeroed for tid > 0). */
double *thread_accum_target(struct thread_accum *ta, int tid, double *shared, size_t len);
/* shared[k] += buf[t][k] for t = 1..T-1. */
void thread_accum_reduce(struct thread_accum *ta, double *shared, size_t len);
void thread_accum_free(struct thread_accum *ta);

#endif
