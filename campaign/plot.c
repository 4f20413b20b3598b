/* plot: gnuplot driver for report figures. */
#include "plot.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "util/fault.h"
#include "util/wfile.h"

/* gnuplot strings are single-quoted: inside them gnuplot substitutes
 * nothing (no backquoted commands, no @macros) and a quote is doubled.  A
 * newline would end the command and start a new one, which could be a
 * shell escape ('!cmd', 'system "cmd"'), so every control character is
 * written as a space: text from a study can never become a command. */
static void put_quoted(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '\'')
            fputc('\'', f);
        fputc(c < 0x20 || c == 0x7f ? ' ' : c, f);
    }
    fputc('\'', f);
}

/* An overlay is a gnuplot expression in x that the report builds from
 * numbers; anything beyond a number, x and arithmetic is refused, so a
 * caller cannot pass a command through it. */
static int overlay_expr_ok(const char *s)
{
    for (; *s; s++)
        if (!strchr("0123456789.eE+-*/() x", *s))
            return 0;
    return 1;
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

/* Start gnuplot without a shell: its stdin is the returned stream, its
 * stderr goes to errfd. */
static FILE *gnuplot_start(int errfd, pid_t *pid, struct err *e)
{
    int fds[2];
    if (pipe(fds) != 0) {
        err_set(e, ERR_RUNTIME, "cannot start gnuplot: pipe: %s", strerror(errno));
        return NULL;
    }
    pid_t child = fork();
    if (child < 0) {
        err_set(e, ERR_RUNTIME, "cannot start gnuplot: fork: %s", strerror(errno));
        close(fds[0]);
        close(fds[1]);
        return NULL;
    }
    if (child == 0) {
        dup2(fds[0], STDIN_FILENO);
        dup2(errfd, STDOUT_FILENO);
        dup2(errfd, STDERR_FILENO);
        close(fds[0]);
        close(fds[1]);
        close(errfd);
        execlp("gnuplot", "gnuplot", (char *)NULL);
        dprintf(STDERR_FILENO, "cannot run gnuplot: %s", strerror(errno));
        _exit(127);
    }
    close(fds[0]);
    FILE *g = fdopen(fds[1], "w");
    if (!g) {
        err_set(e, ERR_RUNTIME, "cannot start gnuplot: %s", strerror(errno));
        close(fds[1]);
        waitpid(child, NULL, 0);
        return NULL;
    }
    *pid = child;
    return g;
}

/* The series as gnuplot data blocks (two blank lines apart, addressed with
 * `index k`) in a temporary file: the script itself carries no data. */
static int write_data_file(const struct plot_spec *ps, int fd, const char *path, struct err *e)
{
    FILE *f = fdopen(dup(fd), "w");
    if (!f)
        return err_set(e, ERR_RUNTIME, "cannot write the gnuplot data %s: %s", path,
                       strerror(errno));
    for (int k = 0; k < ps->nseries; k++) {
        fprintf(f, "# series %d\n", k);
        int rows = 0;
        for (int i = 0; i < ps->series[k].n; i++) {
            double x = ps->series[k].x[i], y = ps->series[k].y[i];
            if (isfinite(x) && isfinite(y) && (!ps->logx || x > 0) && (!ps->logy || y > 0)) {
                fprintf(f, "%.12g %.12g\n", x, y);
                rows++;
            }
        }
        if (!rows)   /* an empty block would shift the index of the next */
            fprintf(f, "NaN NaN\n");
        fprintf(f, "\n\n");
    }
    int bad = fault_write(ENOSPC) != 0 || fflush(f) != 0 || ferror(f);
    int err = errno;
    if (fclose(f) != 0 || bad)
        return err_set(e, ERR_RUNTIME, "cannot write the gnuplot data %s: %s", path,
                       strerror(bad ? err : errno));
    return 0;
}

int plot_svg(const struct plot_spec *ps, const char *path, struct err *e)
{
    if (ps->overlay && !overlay_expr_ok(ps->overlay))
        return err_set(e, ERR_RUNTIME, "plot overlay '%.40s' is not an expression in x",
                       ps->overlay);
    for (int k = 0; k < ps->noverlays && k < PLOT_MAX_SERIES; k++)
        if (!overlay_expr_ok(ps->overlays[k].expr))
            return err_set(e, ERR_RUNTIME, "plot overlay '%.40s' is not an expression in x",
                           ps->overlays[k].expr);
    const char *tmp = getenv("TMPDIR");
    char errpath[512], datapath[512];
    snprintf(errpath, sizeof errpath, "%s/cascade-gnuplot-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    snprintf(datapath, sizeof datapath, "%s/cascade-plotdata-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    int errfd = fault_write(ENOSPC) != 0 ? -1 : mkstemp(errpath);
    if (errfd < 0)
        return err_set(e, ERR_RUNTIME, "cannot create a temporary file %s: %s", errpath,
                       strerror(errno));
    int datafd = fault_write(ENOSPC) != 0 ? -1 : mkstemp(datapath);
    if (datafd < 0) {
        int rc = err_set(e, ERR_RUNTIME, "cannot create a temporary file %s: %s", datapath,
                         strerror(errno));
        close(errfd);
        unlink(errpath);
        return rc;
    }
    int rc = write_data_file(ps, datafd, datapath, e);
    close(datafd);
    /* gnuplot writes PATH.tmp, renamed over PATH when it succeeded: a
     * failure leaves the previous figure or none, never a truncated one */
    char svgtmp[4096 + 8] = "";
    if (!rc && snprintf(svgtmp, sizeof svgtmp, "%s.tmp", path) >= (int)sizeof svgtmp)
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: the name is too long", path);
    pid_t pid = -1;
    FILE *g = rc ? NULL : gnuplot_start(errfd, &pid, e);
    if (!g) {
        close(errfd);
        unlink(errpath);
        unlink(datapath);
        return rc ? rc : ERR_RUNTIME;
    }
    /* the key below the plot: it never hides data and long entries have the
     * full width (key_inside puts it back in the top left corner) */
    int entries = ps->nseries + (ps->overlay != NULL) + ps->noverlays, below = !ps->key_inside;
    fprintf(g, "set terminal svg size 640,%d dynamic enhanced font 'sans,11' background rgb 'white'\n",
            below ? 400 + 18 * entries : 420);
    fprintf(g, "set output ");
    put_quoted(g, svgtmp);
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
        fprintf(g, "%s", first ? "" : ", ");
        put_quoted(g, datapath);
        fprintf(g, " index %d using 1:2 with %s pointtype 7 pointsize 0.8 linewidth 1.5 title ",
                k, style_name(ps->series[k].style));
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
    fprintf(g, "\nquit\n");
    fclose(g);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    char msg[512] = "";
    ssize_t got = pread(errfd, msg, sizeof msg - 1, 0);
    if (got > 0)
        msg[got] = '\0';
    close(errfd);
    unlink(errpath);
    unlink(datapath);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        unlink(svgtmp);
        return err_set(e, ERR_RUNTIME, "gnuplot failed for %s%s%s", path, msg[0] ? ": " : "",
                       msg);
    }
    if (wfile_rename(svgtmp, path) != 0) {
        int rc2 = err_set(e, ERR_RUNTIME, "cannot write %s: rename from %s: %s", path, svgtmp,
                          strerror(errno));
        unlink(svgtmp);
        return rc2;
    }
    return 0;
}
