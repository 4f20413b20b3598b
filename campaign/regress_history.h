/*
 * regress_history: the night-by-night record of `cascade regress` (tables
 * regress_values and the view regress_history of schema version 8;
 * db/README.md): every compared entry of every check with that night's
 * value, the baseline, the tolerance, the verdict and the run directories
 * the value came from, and the machine the check ran on.  The nightly
 * dashboard (nightly_page.h) is drawn from it.
 */
#ifndef CASCADE_CAMPAIGN_REGRESS_HISTORY_H
#define CASCADE_CAMPAIGN_REGRESS_HISTORY_H

#include <sqlite3.h>

#include "baseline.h"
#include "study_analysis.h"

/* Record one comparison against baseline `baseline_id`: the regress_checks
 * row (baseline_db_check) with this machine's name, and one regress_values
 * row per entry of `r`, in one transaction (nothing is left half-written).
 * `a` is the analysis the comparison was made from (units, run
 * directories). */
int regress_history_record(sqlite3 *db, long long baseline_id, const char *solver,
                           const struct cmp_report *r, const struct study_analysis *a,
                           struct err *e);

#endif
