/*
 * nightly_history: the regression history of one study as the nightly
 * dashboard draws it (nightly_page.h), read from the tables regress_checks
 * and regress_values (regress_history.h): its latest nights, oldest first,
 * and every entry (metric, kind, point) with its baseline, value,
 * tolerance and verdict on each night.
 */
#ifndef CASCADE_CAMPAIGN_NIGHTLY_HISTORY_H
#define CASCADE_CAMPAIGN_NIGHTLY_HISTORY_H

#include <jansson.h>
#include <sqlite3.h>

#include "util/err.h"

struct np_night {
    long long id;
    char checked[40], git[64], version[64], machine[128];
    int passed, compared, regressed;
    int recorded;           /* it has regress_values rows (schema version 8 on) */
    json_t *dirs;           /* owned: distinct run directories of its values */
};

struct np_entry {
    char *metric, *what, *point, *unit;
    double *base, *val, *tol;   /* [nnights], NaN where none */
    int *verdict;               /* [nnights]: enum cmp_verdict, -1 not compared that night */
};

struct np_study {
    char name[128];
    struct np_night *nights;    /* oldest first */
    int nnights;
    struct np_entry *ent;
    int nent, cap;
};

/* The latest `max_nights` checks of study `name` and their entries. */
int np_study_load(sqlite3 *db, const char *name, int max_nights, struct np_study *s,
                  struct err *e);
void np_study_free(struct np_study *s);

/* The names of the studies with regression checks (only `only` when not
 * NULL), appended to the JSON list `names`. */
int np_study_names(sqlite3 *db, const char *only, json_t *names, struct err *e);

/* A verdict that counts as a regression (REGRESSED, MISSING, FAILED). */
int np_bad_verdict(int v);

/* (value - baseline) / tolerance of entry x on night k: NaN without a
 * value, +-inf when the tolerance is 0 and the value moved. */
double np_deviation(const struct np_entry *x, int k);

#endif
