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
    char source[256];              /* "campaign", or the imported source analysed */
    json_t *refs;                  /* imported reference rows beside the campaign's (rdata_ref.h) */
    json_t *refine;                /* adaptive refinement state per series (refine_state.h) */
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
/* The same for the rows of one imported source instead of the campaign's
 * runs (`source` NULL or "campaign": the campaign's, unless the study has
 * no runs and exactly one imported source, which is then taken). */
int report_load_source(struct report_ctx *c, sqlite3 *db, const char *name, const char *source,
                       const struct report_spec *rs, struct err *e);

/* Build the report's sections after whatever the caller already added to
 * c->doc (created here when NULL), draw the figures and write
 * dir/report.md and/or dir/report.html (dir is created), and always
 * dir/report.json (report_json.h). */
int report_emit(struct report_ctx *c, const char *dir, int md, int html, const char *db_path,
                struct err *e);

void report_ctx_free(struct report_ctx *c);

#endif
