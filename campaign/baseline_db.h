/*
 * baseline_db: baselines and regression checks in the results database
 * (tables baselines, baseline_values, regress_checks of schema version 2;
 * db/README.md).  A baseline is recorded once per distinct file content,
 * with the solver version its values came from; every check adds a row.
 */
#ifndef CASCADE_CAMPAIGN_BASELINE_DB_H
#define CASCADE_CAMPAIGN_BASELINE_DB_H

#include <jansson.h>
#include <sqlite3.h>

#include "baseline.h"

/* Record baseline `b` (the file's text `text`, at `path`) of study
 * `study_id`; *id receives its row (the existing one when the same content
 * was recorded before). */
int baseline_db_record(sqlite3 *db, long long study_id, const char *path, const char *text,
                       const json_t *b, long long *id, struct err *e);

/* Record one comparison against baseline `baseline_id`. */
int baseline_db_check(sqlite3 *db, long long baseline_id, const char *solver,
                      const struct cmp_report *r, struct err *e);

#endif
