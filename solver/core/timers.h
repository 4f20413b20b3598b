/*
 * timers: wall-clock timers per phase (CLOCK_MONOTONIC), an enum plus a name
 * table; indentation in the names shows the hierarchy.  The whole run and
 * the time loop also count the process's CPU time (started and stopped
 * once a run, so the extra clock reads cost nothing): on a shared machine
 * the wall time grows with the other processes' load, CPU time much less,
 * which is what the benchmarks compare builds by.
 */
#ifndef CASCADE_TIMERS_H
#define CASCADE_TIMERS_H

enum timer_id {
    TIMER_TOTAL,
    TIMER_SETUP,
    TIMER_LOOP,
    TIMER_NEIGHBOR,
    TIMER_COMM,
    TIMER_FORCE,
    TIMER_INTEGRATE,
    TIMER_MPM_P2G,
    TIMER_MPM_GRID,
    TIMER_MPM_G2P,
    TIMER_DPD_SWEEP,   /* DPD: the pair-by-pair dissipative + random sweep */
    TIMER_COUPLING,    /* couplings: the transfers between the two sides (handshake band) */
    TIMER_ANALYSIS,
    TIMER_OUTPUT,
    TIMER_CHECKPOINT,
    TIMER_COUNT
};

struct timers {
    double total[TIMER_COUNT];   /* seconds */
    double start[TIMER_COUNT];
    long calls[TIMER_COUNT];
    double cpu[TIMER_COUNT];       /* CPU seconds (TIMER_TOTAL and TIMER_LOOP only) */
    double cpu_start[TIMER_COUNT];
};

extern const char *const timer_names[TIMER_COUNT];   /* "  neighbor", ... */
extern const char *const timer_keys[TIMER_COUNT];    /* "neighbor", ... */

double timers_now(void);       /* seconds, monotonic */
double timers_cpu_now(void);   /* CPU seconds of the process (all threads) */
static inline int timer_counts_cpu(enum timer_id id) { return id == TIMER_TOTAL || id == TIMER_LOOP; }
static inline void timer_start(struct timers *t, enum timer_id id)
{
    t->start[id] = timers_now();
    if (timer_counts_cpu(id))
        t->cpu_start[id] = timers_cpu_now();
}
static inline void timer_stop(struct timers *t, enum timer_id id)
{
    t->total[id] += timers_now() - t->start[id];
    t->calls[id]++;
    if (timer_counts_cpu(id))
        t->cpu[id] += timers_cpu_now() - t->cpu_start[id];
}

#endif
