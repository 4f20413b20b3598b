/*
 * refine_state: how far adaptive refinement (refine_run.h) took each series
 * of a study -- the `refine_groups` table (db/README.md), written by the
 * refining runner after every round, read by `cascade status` and the
 * report.
 */
#ifndef CASCADE_CAMPAIGN_REFINE_STATE_H
#define CASCADE_CAMPAIGN_REFINE_STATE_H

#include <jansson.h>
#include <sqlite3.h>
#include <stdio.h>

#include "util/err.h"

struct refine_row {
    char metric[128];
    char series[512];         /* canonical JSON of the other swept values */
    char axis[256];
    int levels;               /* levels with a value */
    char finest[128];         /* JSON text of the finest level's axis value */
    double value;             /* the metric at the finest level */
    double phi_ext, gci, band, asymptotic;
    const char *state;        /* "refining", "converged", "stopped" */
    char reason[512];
    double spent_core_s, next_core_s;
};

/* Replace the study's rows with these, in one transaction. */
int refine_state_write(sqlite3 *db, long long study_id, const struct refine_row *rows, int n,
                       struct err *e);
/* The study's rows as a JSON list ([] when there are none, or the database
 * predates the table). */
int refine_state_json(sqlite3 *db, long long study_id, json_t **out, struct err *e);
/* The rows as a table for `cascade status`; nothing when there are none. */
int refine_state_print(sqlite3 *db, long long study_id, FILE *out, struct err *e);

#endif
