/* nightly_svg: the trend figure (see nightly_svg.h). */
#include "nightly_svg.h"

#include <math.h>
#include <string.h>

#include "baseline.h"

static const char *const palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd",
                                      "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
#define NPAL 8

const char *np_color(int q)
{
    return palette[q % NPAL];
}

void np_esc(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

#define FIG_W 760
#define FIG_H 250
#define M_L 64
#define M_R 16
#define M_T 16
#define M_B 52

/* One trend figure: entries [ents] of one metric and kind. */
void np_trend_svg(FILE *f, const struct np_study *s, const int *ents, int n)
{
    int nn = s->nnights;
    double ymax = 1.5;
    for (int q = 0; q < n; q++)
        for (int k = 0; k < nn; k++) {
            double d = fabs(np_deviation(&s->ent[ents[q]], k));
            if (isfinite(d) && d * 1.15 > ymax)
                ymax = d * 1.15;
        }
    if (ymax > 5)
        ymax = 5;   /* beyond: drawn at the edge, with the value in the tooltip */
    double pw = FIG_W - M_L - M_R, ph = FIG_H - M_T - M_B, step = pw / (nn > 0 ? nn : 1);
#define XN(k) (M_L + ((k) + 0.5) * step)
#define YV(v) (M_T + ph * (1 - ((v) + ymax) / (2 * ymax)))
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 "
               "%d %d\" role=\"img\">\n",
            FIG_W, FIG_H, FIG_W, FIG_H);
    fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%g\" height=\"%g\" fill=\"#fff\" stroke=\"#999\"/>\n",
            M_L, M_T, pw, ph);
    /* the nights on which an entry of this metric did not pass */
    for (int k = 0; k < nn; k++) {
        int bad = 0;
        for (int q = 0; q < n; q++)
            bad |= np_bad_verdict(s->ent[ents[q]].verdict[k]);
        if (bad)
            fprintf(f, "<rect class=\"regressed-night\" x=\"%.1f\" y=\"%d\" width=\"%.1f\" "
                       "height=\"%g\" fill=\"#f8d0d0\"><title>%s: regressed</title></rect>\n",
                    XN(k) - step / 2, M_T, step, ph, s->nights[k].checked);
    }
    /* the tolerance band and the baseline */
    fprintf(f, "<rect class=\"band\" x=\"%d\" y=\"%.1f\" width=\"%g\" height=\"%.1f\" "
               "fill=\"#cfe3f7\" fill-opacity=\"0.8\"><title>tolerance band: |value - baseline| "
               "&lt;= tolerance</title></rect>\n",
            M_L, YV(1.0), pw, YV(-1.0) - YV(1.0));
    fprintf(f, "<line class=\"baseline\" x1=\"%d\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#222\" "
               "stroke-dasharray=\"6 3\"/>\n",
            M_L, YV(0.0), M_L + pw, YV(0.0));
    /* y axis */
    const double ticks[] = {-1, 0, 1};
    for (int t = 0; t < 3; t++)
        fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+g</text>\n",
                M_L - 6, YV(ticks[t]) + 4, ticks[t]);
    fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+.2g</text>\n",
            M_L - 6, YV(ymax) + 10, ymax);
    fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%+.2g</text>\n",
            M_L - 6, YV(-ymax), -ymax);
    fprintf(f, "<text transform=\"translate(14 %.1f) rotate(-90)\" font-size=\"11\" "
               "text-anchor=\"middle\">(value &#8722; baseline) / tolerance</text>\n",
            M_T + ph / 2);
    /* x axis: the nights (at most about 12 labels) */
    int every = nn > 12 ? (nn + 11) / 12 : 1;
    for (int k = 0; k < nn; k++) {
        if ((nn - 1 - k) % every)
            continue;
        /* "11-25 02:30": month, day and time (several checks a day stay apart) */
        const char *c = s->nights[k].checked;
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"10\" text-anchor=\"middle\">%.5s "
                   "%.5s</text>\n",
                XN(k), FIG_H - M_B + 16, strlen(c) >= 16 ? c + 5 : c, strlen(c) >= 16 ? c + 11 : "");
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"9\" fill=\"#555\" "
                   "text-anchor=\"middle\">%.8s</text>\n",
                XN(k), FIG_H - M_B + 29, s->nights[k].git);
    }
    fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"11\" text-anchor=\"middle\">night (date, "
               "commit)</text>\n",
            M_L + pw / 2, FIG_H - 6);
    /* one line per point of the sweep */
    for (int q = 0; q < n; q++) {
        const struct np_entry *x = &s->ent[ents[q]];
        const char *color = np_color(q);
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", color);
        for (int k = 0; k < nn; k++) {
            double d = np_deviation(x, k);
            if (isnan(d))
                continue;
            d = d > ymax ? ymax : d < -ymax ? -ymax : d;
            fprintf(f, "%.1f,%.1f ", XN(k), YV(d));
        }
        fputs("\"/>\n", f);
        for (int k = 0; k < nn; k++) {
            if (x->verdict[k] < 0 || x->verdict[k] == CMP_NEW)
                continue;
            double d = np_deviation(x, k);
            int bad = np_bad_verdict(x->verdict[k]);
            if (isnan(d)) {   /* no value that night: a cross at the top */
                fprintf(f, "<path class=\"novalue\" d=\"M%.1f %.1f l8 8 m0 -8 l-8 8\" "
                           "stroke=\"#c00\" stroke-width=\"2\"><title>",
                        XN(k) - 4, YV(ymax) + 2);
            } else {
                double y = d > ymax ? ymax : d < -ymax ? -ymax : d;
                fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%d\" fill=\"%s\" stroke=\"%s\" "
                           "stroke-width=\"%d\"%s><title>",
                        XN(k), YV(y), bad ? 5 : 3, color, bad ? "#c00" : color, bad ? 2 : 1,
                        bad ? " class=\"regressed\"" : "");
            }
            np_esc(f, s->nights[k].checked);
            fputs(" ", f);
            np_esc(f, x->point);
            fprintf(f, ": value %.10g, baseline %.10g, tolerance %.3g (%s)</title>%s\n", x->val[k],
                    x->base[k], x->tol[k], cmp_verdict_names[x->verdict[k]],
                    isnan(d) ? "</path>" : "</circle>");
        }
    }
    fputs("</svg>\n", f);
#undef XN
#undef YV
}

