/*
 * rdata_ref: the reference rows `cascade import` recorded for a study
 * (db/README.md: imports, import_rows, import_values) -- as the data of a
 * report of their own (the Celik procedure on imported values alone), and
 * as rows to show beside the campaign's values.
 */
#ifndef CASCADE_CAMPAIGN_RDATA_REF_H
#define CASCADE_CAMPAIGN_RDATA_REF_H

#include <jansson.h>
#include <sqlite3.h>

#include "rdata.h"
#include "study_analysis.h"

/* Whether the database has table `name` (an older schema may not). */
int rdata_has_table(sqlite3 *db, const char *name);

/* The sources imported into the study, a JSON list of names (new reference). */
int rdata_sources(sqlite3 *db, long long study_id, json_t **names, struct err *e);

/* Replace the jobs and metrics of d (loaded by rdata_load) with the rows of
 * one imported source: each row a done "job" with its parameters and values. */
int rdata_use_source(sqlite3 *db, struct rdata *d, const char *source, struct err *e);

/* Every imported row of the study, as a list of {source, line, params,
 * metric, unit, value} (new reference; an empty list when there are none). */
int rdata_ref_rows(sqlite3 *db, long long study_id, json_t **rows, struct err *e);

/* Add to each row the campaign's value at the same point of the sweep
 * ("campaign", "diff", "rel"; null when the campaign has none). */
void rdata_ref_compare(json_t *rows, const struct study_analysis *a);

#endif
