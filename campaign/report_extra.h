/*
 * report_extra: the report's sections about imported reference rows (beside
 * the campaign's values at the same point) and about adaptive refinement
 * (per series: levels, GCI, state and why), from the lists rdata_ref.h and
 * refine_state.h give.
 */
#ifndef CASCADE_CAMPAIGN_REPORT_EXTRA_H
#define CASCADE_CAMPAIGN_REPORT_EXTRA_H

#include <jansson.h>

#include "report_doc.h"

/* Either list may be NULL or empty (no section then). */
void report_extra_sections(struct rdoc *doc, const json_t *refs, const json_t *refine);

#endif
