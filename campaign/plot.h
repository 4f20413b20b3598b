/*
 * plot: figures for reports, drawn by gnuplot (SVG).  gnuplot is started
 * without a shell; the data goes through a temporary file (removed after)
 * and every text reaches the script as a quoted string with control
 * characters blanked, so no title, label or file name can become a command.
 */
#ifndef CASCADE_PLOT_H
#define CASCADE_PLOT_H

#include "util/err.h"

#define PLOT_MAX_SERIES 8

enum plot_style { PLOT_POINTS, PLOT_LINESPOINTS, PLOT_LINES };

struct plot_series {
    const char *label;
    const double *x, *y;
    int n;
    enum plot_style style;
};

struct plot_spec {
    const char *title;
    const char *xlabel, *ylabel;
    int logx, logy;
    int nseries;
    struct plot_series series[PLOT_MAX_SERIES];
    /* optional analytic overlay, a gnuplot expression in x (e.g. a fitted
     * line "3.94 + 1.49*x" or a slope "0.02*x**1.53") */
    const char *overlay;
    const char *overlay_label;
    /* more overlays (one per series, say: each series' fitted line) */
    int noverlays;
    struct plot_overlay {
        const char *expr, *label;
        int color;     /* draw in the colour of series `color` (1 = the first); 0: its own */
    } overlays[PLOT_MAX_SERIES];
    int key_inside;    /* the key in the top left corner, not below the plot */
};

/* Write the figure as SVG to `path`.  Returns ERR_RUNTIME when gnuplot is
 * missing or fails (its stderr in the message). */
int plot_svg(const struct plot_spec *ps, const char *path, struct err *e);

/* Copy text for a title, label or key entry with the characters that
 * gnuplot's enhanced text mode would interpret (_ ^ { } @ & ~ \) escaped,
 * so names like pe_per_atom print as written. */
void plot_text(const char *in, char *out, size_t len);

#endif
