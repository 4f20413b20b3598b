/*
 * progress: progress of a long run -- on a terminal one self-updating line
 * (step, percentage, ns/day, ETA), otherwise a plain line every 10 %.
 */
#ifndef CASCADE_PROGRESS_H
#define CASCADE_PROGRESS_H

#include <stdio.h>

struct progress {
    FILE *out;
    int tty;
    int enabled;
    long total;
    long first;     /* step the run (re)started from: the rate counts from it */
    double t0, last_print;
    int last_decile;
    double dt_ps;   /* simulated time per step, for ns/day (0: not shown) */
};

void progress_start(struct progress *pr, FILE *out, long total_steps, double dt_ps, int enabled);
/* The same for a run continued from step `first` (a restart). */
void progress_start_at(struct progress *pr, FILE *out, long total_steps, long first, double dt_ps,
                       int enabled);
void progress_update(struct progress *pr, long step);
void progress_finish(struct progress *pr, long step);

#endif
