/*
 * plot: figures for reports, drawn by gnuplot (SVG).  Data goes to gnuplot
 * inline on its standard input, so no temporary data files are left.
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
};

/* Write the figure as SVG to `path`.  Returns ERR_RUNTIME when gnuplot is
 * missing or fails (its stderr in the message). */
int plot_svg(const struct plot_spec *ps, const char *path, struct err *e);

#endif
