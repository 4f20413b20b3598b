/*
 * result: the run's result.json -- the scalar metrics the campaign records,
 * with units, plus status, timing and provenance:
 *
 *   {"status": "ok" | "diverged" | "failed",
 *    "message": "...",                       (when not ok)
 *    "metrics": {NAME: {"value": X, "unit": "U"}, ...},
 *    "series":  {NAME: {"unit": "U", "values": [...]}, ...},   (optional)
 *    "artifacts": {NAME: "file name in the output directory", ...},   (optional)
 *    "timing":  {...}, "provenance": {...}, "case_key": "...", "case": {...}}
 *
 * Written atomically (temporary file + rename) so a reader never sees half
 * of it.
 */
#ifndef CASCADE_RESULT_H
#define CASCADE_RESULT_H

#include <jansson.h>

#include "util/err.h"

struct result {
    json_t *root;      /* owned */
    json_t *metrics;   /* borrowed from root */
    json_t *series;    /* borrowed from root */
};

int result_init(struct result *r);
void result_free(struct result *r);
void result_metric(struct result *r, const char *name, double value, const char *unit);
/* Attach a "source" text to an existing metric (where its value came
 * from); nothing when there is no such metric. */
void result_metric_source(struct result *r, const char *name, const char *source);
/* A series of values (for example counts over time), copied. */
void result_series(struct result *r, const char *name, const double *values, int n,
                   const char *unit);
/* A file the run wrote that later jobs may read (for example the final
 * state of a preparation run), by name relative to the output directory. */
void result_artifact(struct result *r, const char *name, const char *file);
void result_set_status(struct result *r, const char *status, const char *message);
int result_write(const struct result *r, const char *path, struct err *e);

#endif
