/*
 * rdata: what a report needs from the results database, read once -- the
 * study, its swept axes, every active job with its latest attempt (state
 * and reason) and the metrics of its latest successful run (the `results`
 * view), one column per metric.
 */
#ifndef CASCADE_CAMPAIGN_RDATA_H
#define CASCADE_CAMPAIGN_RDATA_H

#include <jansson.h>
#include <sqlite3.h>

#include "docpath.h"
#include "util/err.h"

struct rd_axis {
    char name[DOCPATH_MAX];
    int grp;                  /* product factor: zipped axes share it */
    int repeat;               /* the repeats axis (or an axis named 'seed'): averaged over */
    json_t *values;           /* owned: the list of values */
};

struct rd_job {
    long long id;
    char key[17];
    int prep;                 /* a preparation job */
    char *name;               /* preparation job name, or NULL */
    long seq;
    json_t *params;           /* owned: {axis: value} */
    char state[16];           /* latest attempt's status, or 'pending' */
    int attempt;              /* 0: never run */
    char *message;            /* the latest attempt's reason, or NULL */
    int exit_code, signal;    /* -1 when not applicable */
    char *solver;             /* 'version (git)' of the run the metrics come from (NULL: none) */
    double *val;              /* [nmetrics], NaN when the metric is absent or not finite */
};

struct rdata {
    long long study_id;
    char name[128];
    char *description, *spec_path, *spec_text;
    struct rd_axis *axes;
    int naxes;
    struct rd_job *jobs;      /* in expansion order (preparation jobs first) */
    long njobs;
    char **metric, **unit;    /* metric names and units */
    int nmetrics;
};

/* Read study `name`.  ERR_INPUT when there is no such study. */
int rdata_load(sqlite3 *db, const char *name, struct rdata *d, struct err *e);
void rdata_free(struct rdata *d);

/* Index of a metric or an axis, or -1. */
int rdata_metric(const struct rdata *d, const char *name);
int rdata_axis(const struct rdata *d, const char *name);

/* Put the named metrics first, in that order (the rest keep their order). */
void rdata_order_metrics(struct rdata *d, const char *const *names, int n);

#endif
