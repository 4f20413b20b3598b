/*
 * progress_view: what a running campaign shows.  On a terminal: one status
 * line redrawn in place (done / failed / running / total, elapsed, ETA),
 * with a permanent line for each job that did not succeed.  Otherwise
 * (a log file, CI): one plain line per finished job, and a plain status
 * line with the counts, elapsed time and ETA every `plain_every` seconds
 * (60 s; CASCADE_PROGRESS_SECONDS sets it, 0 turns it off), so a log of a
 * long sweep shows where it is even while no job finishes.
 */
#ifndef CASCADE_CAMPAIGN_PROGRESS_VIEW_H
#define CASCADE_CAMPAIGN_PROGRESS_VIEW_H

#include <stdio.h>

struct progress_view {
    FILE *out;
    int tty;
    int quiet;
    double t0;              /* monotonic */
    double last_draw;
    long total;             /* jobs of the study */
    long done_before;       /* done for this solver before this run */
    long done, failed, running, finished_here;
    int drawn;              /* a status line is on screen */
    int finished;           /* the final status line has been drawn */
    double plain_every;     /* not a terminal: seconds between status lines (0: none) */
    double last_plain;      /* when the last one was written */
};

void progress_view_init(struct progress_view *v, FILE *out, int quiet, long total);
/* A job started or finished here ("done", "failed", ...). */
void progress_view_job(struct progress_view *v, const char *status, const char *key,
                       const char *label, double wall_s, const char *message);
/* A plain message (keeps the status line intact). */
void progress_view_note(struct progress_view *v, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Redraw when due (terminal), or write the periodic status line when due
 * (not a terminal). */
void progress_view_tick(struct progress_view *v, int force);
void progress_view_finish(struct progress_view *v);

/* "1h02m", "3m05s", "12.3s" */
void progress_view_duration(double s, char *buf, size_t len);

#endif
