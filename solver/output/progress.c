/* progress: terminal and log-friendly progress lines. */
#include "output/progress.h"

#include <unistd.h>

#include "core/timers.h"

void progress_start(struct progress *pr, FILE *out, long total_steps, double dt_ps, int enabled)
{
    progress_start_at(pr, out, total_steps, 0, dt_ps, enabled);
}

void progress_start_at(struct progress *pr, FILE *out, long total_steps, long first, double dt_ps,
                       int enabled)
{
    pr->out = out;
    pr->first = first;
    pr->tty = isatty(fileno(out));
    pr->enabled = enabled && total_steps > 0;
    pr->total = total_steps;
    pr->t0 = timers_now();
    pr->last_print = 0;
    pr->last_decile = total_steps > 0 ? (int)(10 * first / total_steps) : 0;
    pr->dt_ps = dt_ps;
}

static void line(struct progress *pr, long step, const char *end)
{
    double el = timers_now() - pr->t0;
    double frac = (double)step / (double)pr->total;
    long done = step - pr->first;   /* steps taken by this process */
    double rate = done > 0 && el > 0 ? done / el : 0;   /* steps per second */
    double eta = rate > 0 ? (pr->total - step) / rate : 0;
    double nsday = rate > 0 && pr->dt_ps > 0 ? rate * pr->dt_ps * 1e-3 * 86400.0 : 0;
    fprintf(pr->out, "%sstep %ld/%ld (%3.0f%%)  %.3g ns/day  elapsed %.1f s  ETA %.1f s%s",
            pr->tty ? "\r" : "", step, pr->total, 100.0 * frac, nsday, el, eta, end);
    fflush(pr->out);
}

void progress_update(struct progress *pr, long step)
{
    if (!pr->enabled)
        return;
    if (pr->tty) {
        double now = timers_now();
        if (now - pr->last_print > 0.5) {
            pr->last_print = now;
            line(pr, step, "   ");
        }
    } else {
        int decile = (int)(10 * step / pr->total);
        if (decile > pr->last_decile) {
            pr->last_decile = decile;
            line(pr, step, "\n");
        }
    }
}

void progress_finish(struct progress *pr, long step)
{
    if (pr->enabled && pr->tty)
        line(pr, step, "\n");
}
