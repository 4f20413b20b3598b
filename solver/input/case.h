/*
 * case: a case file from disk to a validated, resolved document and the
 * case type's models.
 *
 * Resolving fills every default into the document and normalises types, so
 * the canonical JSON of the resolved document (util/canon.h) names the run
 * exactly; its hash is the job key.
 */
#ifndef CASCADE_CASE_H
#define CASCADE_CASE_H

#include <jansson.h>

#include "scenarios/case_type.h"
#include "output/run.h"
#include "util/cfg.h"
#include "util/locmap.h"

struct case_doc {
    json_t *doc;              /* owned */
    struct locmap *locs;      /* owned, NULL for JSON input */
    char name[4096];          /* file name for messages */
    char dir[4096];           /* directory of the case file */
};

int case_load_file(struct case_doc *cd, const char *path, struct err *e);
/* A case given as JSON text (batch resolve): `name` is used in messages. */
int case_load_json(struct case_doc *cd, const char *text, const char *name, struct err *e);
void case_doc_free(struct case_doc *cd);

struct case_resolved {
    const struct case_type *type;
    struct case_common common;
    struct output_settings output;
    void *state;              /* the type's models (deep reads only) */
};

/* Validate and resolve.  shallow: keys and values only (no files opened);
 * otherwise build the models too.  The cfg used stays valid for errors the
 * run reports later against the document. */
int case_resolve(struct case_doc *cd, int shallow, int nthreads, const struct parallel *par,
                 struct case_resolved *out, struct err *e);
void case_resolved_free(struct case_resolved *r);

#endif
