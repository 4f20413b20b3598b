/*
 * conv_store: the convergence results of a report written to the
 * `convergence` table (db/migrations/0005_convergence.sql), one row per
 * metric, series and source for each set of three finest grids, at full
 * double precision.  A row for the same three grids is replaced (the
 * values may have changed with a rerun); rows for other grids stay, so a
 * study that was refined keeps the GCI of every level it went through.
 */
#ifndef CASCADE_CAMPAIGN_CONV_STORE_H
#define CASCADE_CAMPAIGN_CONV_STORE_H

#include <sqlite3.h>

#include "study_analysis.h"

/* Write every series with three or more grids, in one transaction (all or
 * none).  `source` is "campaign" or an imported source.  *rows receives the
 * number of rows written. */
int conv_store_write(sqlite3 *db, const struct study_analysis *a, const char *source, int *rows,
                     struct err *e);

/* The JSON list of values (17 significant digits) of a series' grids with
 * a value, finest first; `of_h` chooses h instead of the metric's values.
 * Caller frees. */
char *conv_store_list(const struct study_analysis *a, const struct sa_conv *c, int of_h);

#endif
