/*
 * import_store: reference rows (import_parse.h) checked against a study in
 * the results database and written in one transaction -- all of them or
 * nothing (db/README.md: imports, import_rows, import_params,
 * import_values).
 *
 * For a study the campaign has run, every parameter must be one of its
 * swept keys and every row must give all of them (the repeats aside); every
 * metric must be one the study records, in the unit the solver wrote.  A
 * study not yet in the database is created holding references only: its
 * axes are the imported parameters, and `resolution` (with `hmap`, `dim`,
 * `volume`) becomes the `report:` section of its settings.  Two rows with
 * the same parameters are an error naming both lines.  Importing a source
 * a study already has replaces that source's rows.
 */
#ifndef CASCADE_CAMPAIGN_IMPORT_STORE_H
#define CASCADE_CAMPAIGN_IMPORT_STORE_H

#include <sqlite3.h>

#include "import_parse.h"

struct import_opts {
    const char *study;        /* study name */
    const char *source;       /* overrides the file's; NULL: the file's */
    const char *resolution;   /* references-only study: report.resolution.axis, or NULL */
    const char *hmap;         /* value | inverse | cells, or NULL */
    long dim;                 /* 0: not given */
    double volume;            /* 0: not given */
};

struct import_result {
    long long study_id;
    int created;              /* the study was created (references only) */
    int replaced;             /* an earlier import of this source was replaced */
    int nrows, nvalues;
    char source[256];
};

int import_store(sqlite3 *db, const struct import_set *s, const struct import_opts *o,
                 struct import_result *res, struct err *e);

#endif
