/*
 * nightly_page: the nightly dashboard (`cascade report --nightly`), one
 * self-contained static HTML page drawn from the regression history of the
 * database (regress_history.h): no server, no scripts, no external files.
 *
 * Per study: a table of the nights, newest first (date, commit, solver,
 * machine, verdict, entries compared and regressed, links to the run
 * directories the values came from); per metric (and per observed order)
 * an inline SVG figure of the trend over the nights -- each point of the
 * sweep a line of (value - baseline) / tolerance, the tolerance band
 * |value - baseline| <= tolerance shaded, the baseline the line at 0, the
 * nights on which an entry of the metric regressed or had no value shaded
 * red and their markers red -- with a table of the numbers of the latest
 * night under it.
 */
#ifndef CASCADE_CAMPAIGN_NIGHTLY_PAGE_H
#define CASCADE_CAMPAIGN_NIGHTLY_PAGE_H

#include <sqlite3.h>

#include "util/err.h"

struct nightly_page_opts {
    const char *out;        /* the page (its directory is created) */
    const char *study;      /* one study, or NULL: every study with checks */
    int nights;             /* the latest N checks per study (> 0) */
    const char *db_label;   /* the database as the page names it */
};

/* Write the page.  *nfigures receives the number of figures drawn (each one
 * inline <svg> in a <figure class="trend">).  ERR_INPUT when the database
 * holds no regression check (of that study). */
int nightly_page_write(sqlite3 *db, const struct nightly_page_opts *o, int *nfigures,
                       struct err *e);

#endif
