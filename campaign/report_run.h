/*
 * report_run: the steps `cascade report` and `cascade regress` share --
 * read a study's results from the database, analyse them with the study's
 * report settings, and write the report (Markdown and/or HTML with its SVG
 * figures) into a directory.
 */
#ifndef CASCADE_CAMPAIGN_REPORT_RUN_H
#define CASCADE_CAMPAIGN_REPORT_RUN_H

#include <sqlite3.h>

#include "rdata.h"
#include "report_doc.h"
#include "report_spec.h"
#include "study_analysis.h"

struct report_ctx {
    struct rdata d;
    struct report_spec own;        /* parsed from the database's copy of the study file */
    const struct report_spec *rs;  /* &own, or the caller's */
    struct study_analysis a;
    struct rdoc *doc;
    int loaded, analysed;
};

/* Read and analyse study `name`.  `rs` may be NULL: the settings are then
 * read from the study file text the database keeps. */
int report_load(struct report_ctx *c, sqlite3 *db, const char *name, const struct report_spec *rs,
                struct err *e);

/* Build the report's sections after whatever the caller already added to
 * c->doc (created here when NULL), draw the figures and write
 * dir/report.md and/or dir/report.html (dir is created). */
int report_emit(struct report_ctx *c, const char *dir, int md, int html, const char *db_path,
                struct err *e);

void report_ctx_free(struct report_ctx *c);

#endif
