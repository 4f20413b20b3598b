/*
 * export_ref: the reference rows `cascade import` recorded for a study, as
 * rows of `cascade export --csv` beside the jobs: kind `reference`, name
 * the source, attempt the line of the imported file, the imported
 * parameters and metric values in the same columns.
 */
#ifndef CASCADE_CAMPAIGN_EXPORT_REF_H
#define CASCADE_CAMPAIGN_EXPORT_REF_H

#include <sqlite3.h>
#include <stdio.h>

#include "util/err.h"

/* The imported metrics (name, unit) of a study that are not yet among
 * names[0..*n): appended to the two growing arrays (strdup'ed). */
int export_ref_metrics(sqlite3 *db, long long study_id, char ***names, char ***units, int *n,
                       struct err *e);

/* One CSV row per imported row, with the given parameter and metric columns. */
int export_ref_rows(sqlite3 *db, long long study_id, char *const *axes, int naxes,
                    char *const *metrics, int nm, FILE *out, struct err *e);

#endif
