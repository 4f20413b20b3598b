/* progress_view: terminal status line or plain log lines. */
#include "progress_view.h"

#include <stdarg.h>
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
}

static void clear_line(struct progress_view *v)
{
    if (v->tty && v->drawn) {
        fputs("\r\033[K", v->out);
        v->drawn = 0;
    }
}

static void draw(struct progress_view *v)
{
    double el = sys_mono() - v->t0;
    long left = v->total - v->done - v->failed;
    char elapsed[32], eta[32] = "?";
    progress_view_duration(el, elapsed, sizeof elapsed);
    if (v->finished_here > 0 && left > 0) {
        /* throughput so far */
        double rate = (double)v->finished_here / el;
        if (rate > 0)
            progress_view_duration((double)left / rate, eta, sizeof eta);
    } else if (left <= 0) {
        snprintf(eta, sizeof eta, "0s");
    }
    fprintf(v->out, "\r\033[K[cascade] done %ld | failed %ld | running %ld | total %ld | %s elapsed, "
                    "ETA %s",
            v->done, v->failed, v->running, v->total, elapsed, eta);
    fflush(v->out);
    v->drawn = 1;
    v->last_draw = sys_mono();
}

void progress_view_tick(struct progress_view *v, int force)
{
    if (!v->tty || v->quiet || v->finished)
        return;
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
    char el[32], w[32];
    progress_view_duration(sys_mono() - v->t0, el, sizeof el);
    progress_view_duration(wall_s, w, sizeof w);
    fprintf(v->out, "[cascade %s] %ld/%ld %s %s (%s) %s%s%s\n", el, v->done + v->failed, v->total,
            status, key, label, w, message && message[0] ? ": " : "", message ? message : "");
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
