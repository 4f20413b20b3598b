/* progress_view: terminal status line or plain log lines. */
#include "progress_view.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sysinfo.h"

void progress_view_duration(double s, char *buf, size_t len)
{
    if (s < 0)
        s = 0;
    long t = (long)(s + 0.5);
    if (s < 60)
        snprintf(buf, len, "%.1fs", s);
    else if (t < 3600)
        snprintf(buf, len, "%ldm%02lds", t / 60, t % 60);
    else
        snprintf(buf, len, "%ldh%02ldm", t / 3600, (t % 3600) / 60);
}

void progress_view_init(struct progress_view *v, FILE *out, int quiet, long total)
{
    memset(v, 0, sizeof *v);
    v->out = out;
    v->tty = isatty(fileno(out));
    v->quiet = quiet;
    v->total = total;
    v->t0 = sys_mono();
    v->last_plain = v->t0;
    v->plain_every = 60;
    const char *every = getenv("CASCADE_PROGRESS_SECONDS");
    if (every && every[0]) {
        char *end;
        double s = strtod(every, &end);
        if (end != every && !*end && s >= 0)
            v->plain_every = s;
    }
}

static void clear_line(struct progress_view *v)
{
    if (v->tty && v->drawn) {
        fputs("\r\033[K", v->out);
        v->drawn = 0;
    }
}

/* Elapsed time and ETA from the throughput so far. */
static void times(const struct progress_view *v, char *elapsed, size_t elen, char *eta,
                  size_t tlen)
{
    double el = sys_mono() - v->t0;
    long left = v->total - v->done - v->failed;
    snprintf(eta, tlen, "?");
    progress_view_duration(el, elapsed, elen);
    if (v->finished_here > 0 && left > 0) {
        double rate = (double)v->finished_here / el;
        if (rate > 0)
            progress_view_duration((double)left / rate, eta, tlen);
    } else if (left <= 0) {
        snprintf(eta, tlen, "0s");
    }
}

static void draw(struct progress_view *v)
{
    char elapsed[32], eta[32];
    times(v, elapsed, sizeof elapsed, eta, sizeof eta);
    fprintf(v->out, "\r\033[K[cascade] done %ld | failed %ld | running %ld | total %ld | %s elapsed, "
                    "ETA %s",
            v->done, v->failed, v->running, v->total, elapsed, eta);
    fflush(v->out);
    v->drawn = 1;
    v->last_draw = sys_mono();
}

/* The status line of a log: no carriage return, no escape sequences. */
static void plain_status(struct progress_view *v)
{
    char elapsed[32], eta[32];
    times(v, elapsed, sizeof elapsed, eta, sizeof eta);
    fprintf(v->out, "[cascade %s] progress: done %ld | failed %ld | running %ld | total %ld | ETA %s\n",
            elapsed, v->done, v->failed, v->running, v->total, eta);
    fflush(v->out);
    v->last_plain = sys_mono();
}

void progress_view_tick(struct progress_view *v, int force)
{
    if (v->quiet || v->finished)
        return;
    if (!v->tty) {
        if (v->plain_every > 0 && sys_mono() - v->last_plain >= v->plain_every)
            plain_status(v);
        return;
    }
    if (force || sys_mono() - v->last_draw >= 0.5)
        draw(v);
}

void progress_view_job(struct progress_view *v, const char *status, const char *key,
                       const char *label, double wall_s, const char *message)
{
    if (v->quiet)
        return;
    int ok = strcmp(status, "done") == 0;
    if (v->tty) {
        if (!ok) {
            clear_line(v);
            fprintf(v->out, "[cascade] %s %s (%s): %s\n", status, key, label, message ? message : "");
        }
        draw(v);
        return;
    }
    char el[32], w[32], eta[32];
    times(v, el, sizeof el, eta, sizeof eta);
    progress_view_duration(wall_s, w, sizeof w);
    fprintf(v->out, "[cascade %s] %ld/%ld %s %s (%s) %s%s%s (ETA %s)\n", el, v->done + v->failed,
            v->total, status, key, label, w, message && message[0] ? ": " : "",
            message ? message : "", eta);
    fflush(v->out);
}

void progress_view_note(struct progress_view *v, const char *fmt, ...)
{
    if (v->quiet)
        return;
    clear_line(v);
    va_list ap;
    va_start(ap, fmt);
    fputs("[cascade] ", v->out);
    vfprintf(v->out, fmt, ap);
    va_end(ap);
    fputc('\n', v->out);
    fflush(v->out);
    if (v->tty && !v->finished)
        draw(v);
}

void progress_view_finish(struct progress_view *v)
{
    if (v->tty && !v->quiet) {
        draw(v);
        fputc('\n', v->out);
        v->drawn = 0;
    }
    v->finished = 1;
}
