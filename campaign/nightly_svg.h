/*
 * nightly_svg: the trend figure of the nightly dashboard as inline SVG --
 * one line per entry of (value - baseline) / tolerance over the nights,
 * the tolerance band, the baseline, the nights on which an entry did not
 * pass shaded red (nightly_page.h).
 */
#ifndef CASCADE_CAMPAIGN_NIGHTLY_SVG_H
#define CASCADE_CAMPAIGN_NIGHTLY_SVG_H

#include <stdio.h>

#include "nightly_history.h"

/* The colour of the q-th line (the tables under a figure use it too). */
const char *np_color(int q);

/* Text with &, <, >, " escaped (HTML and SVG). */
void np_esc(FILE *f, const char *s);

/* The figure of entries ents[0..n) of study s. */
void np_trend_svg(FILE *f, const struct np_study *s, const int *ents, int n);

#endif
