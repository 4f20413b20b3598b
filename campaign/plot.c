/* plot: gnuplot driver for report figures. */
#include "plot.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* gnuplot strings are single-quoted; a quote inside is doubled */
static void put_quoted(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; s && *s; s++) {
        if (*s == '\'')
            fputc('\'', f);
        fputc(*s, f);
    }
    fputc('\'', f);
}

void plot_text(const char *in, char *out, size_t len)
{
    size_t n = 0;
    for (; in && *in && n + 2 < len; in++) {
        if (strchr("_^{}@&~\\", *in))
            out[n++] = '\\';
        out[n++] = *in;
    }
    if (len)
        out[n < len ? n : len - 1] = '\0';
}

static const char *style_name(enum plot_style s)
{
    return s == PLOT_LINES ? "lines" : s == PLOT_LINESPOINTS ? "linespoints" : "points";
}

int plot_svg(const struct plot_spec *ps, const char *path, struct err *e)
{
    char errpath[] = "/tmp/cascade-gnuplot-XXXXXX";
    int errfd = mkstemp(errpath);
    if (errfd < 0)
        return err_set(e, ERR_RUNTIME, "cannot create a temporary file: %s", strerror(errno));
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "gnuplot 2>%s", errpath);
    FILE *g = popen(cmd, "w");
    if (!g) {
        close(errfd);
        unlink(errpath);
        return err_set(e, ERR_RUNTIME, "cannot start gnuplot: %s", strerror(errno));
    }
    /* the key below the plot: it never hides data and long entries have the
     * full width (key_inside puts it back in the top left corner) */
    int entries = ps->nseries + (ps->overlay != NULL) + ps->noverlays, below = !ps->key_inside;
    fprintf(g, "set terminal svg size 640,%d dynamic enhanced font 'sans,11' background rgb 'white'\n",
            below ? 400 + 18 * entries : 420);
    fprintf(g, "set output ");
    put_quoted(g, path);
    fprintf(g, "\nset encoding utf8\nset grid\n%s\n",
            below ? "set key below left Left reverse box vertical maxcols 1 spacing 1.1 height 0.6" : "set key top left box opaque");
    if (ps->title) {
        fprintf(g, "set title ");
        put_quoted(g, ps->title);
        fputc('\n', g);
    }
    fprintf(g, "set xlabel ");
    put_quoted(g, ps->xlabel ? ps->xlabel : "");
    if (below)
        fprintf(g, " offset 0,0.6");   /* clear of the key's frame */
    fprintf(g, "\nset ylabel ");
    put_quoted(g, ps->ylabel ? ps->ylabel : "");
    fputc('\n', g);
    if (ps->logx)
        fprintf(g, "set logscale x\nset format x '%%g'\n");
    if (ps->logy)
        fprintf(g, "set logscale y\nset format y '%%g'\n");
    /* pad the ranges a little so end points are not on the frame */
    fprintf(g, "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n");
    fprintf(g, "plot ");
    int first = 1;
    for (int k = 0; k < ps->nseries; k++) {
        fprintf(g, "%s'-' using 1:2 with %s pointtype 7 pointsize 0.8 linewidth 1.5 title ",
                first ? "" : ", ", style_name(ps->series[k].style));
        put_quoted(g, ps->series[k].label ? ps->series[k].label : "");
        first = 0;
    }
    if (ps->overlay) {
        fprintf(g, "%s%s with lines dashtype 2 linewidth 1.5 title ", first ? "" : ", ", ps->overlay);
        put_quoted(g, ps->overlay_label ? ps->overlay_label : ps->overlay);
        first = 0;
    }
    for (int k = 0; k < ps->noverlays && k < PLOT_MAX_SERIES; k++) {
        fprintf(g, "%s%s with lines dashtype 2 linewidth 1.2 ", first ? "" : ", ",
                ps->overlays[k].expr);
        if (ps->overlays[k].color > 0)
            fprintf(g, "linecolor %d ", ps->overlays[k].color);
        fprintf(g, "title ");
        put_quoted(g, ps->overlays[k].label ? ps->overlays[k].label : ps->overlays[k].expr);
        first = 0;
    }
    fputc('\n', g);
    for (int k = 0; k < ps->nseries; k++) {
        for (int i = 0; i < ps->series[k].n; i++) {
            double x = ps->series[k].x[i], y = ps->series[k].y[i];
            if (isfinite(x) && isfinite(y) && (!ps->logx || x > 0) && (!ps->logy || y > 0))
                fprintf(g, "%.12g %.12g\n", x, y);
        }
        fprintf(g, "e\n");
    }
    int status = pclose(g);
    char msg[512] = "";
    ssize_t got = pread(errfd, msg, sizeof msg - 1, 0);
    if (got > 0)
        msg[got] = '\0';
    close(errfd);
    unlink(errpath);
    if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return err_set(e, ERR_RUNTIME, "gnuplot failed for %s%s%s", path, msg[0] ? ": " : "",
                       msg);
    return 0;
}
