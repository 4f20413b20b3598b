/*
 * report_json: the numbers of a study report as one JSON document
 * (report.json, `cascade report --format json`), every number at full
 * double precision (jansson prints doubles with 17 significant digits, so
 * they read back bit for bit); NaN and infinities are null.
 *
 *   {"format": "cascade-report 1", "study": ..., "source": "campaign",
 *    "generated": ..., "resolution": {"axis": ..., "h": "value", "why": ...},
 *    "safety": 1.25, "jobs": {"sweep": n, "done": n},
 *    "series": [{"metric", "unit", "series": {other swept values},
 *                "status": "ok" | "few" | "error", "note",
 *                "levels": [{"h", "params", "value", "sd", "n", "local_p",
 *                            "local_kind"}, ...]   (ascending h),
 *                "celik": {"h": [h1, h2, h3], "phi": [...], "r21", "r32",
 *                          "ratio", "kind", "p", "iterations", "phi_ext",
 *                          "e_a21", "e_ext21", "gci_fine", "gci_medium",
 *                          "band", "asymptotic"},
 *                "formal_order", "flags": [...], "flagged": bool}, ...],
 *    "references": [...], "refinement": [...]}
 *
 * GCIs and relative errors are fractions (0.01 = 1 %), as in the
 * `convergence` table.
 */
#ifndef CASCADE_CAMPAIGN_REPORT_JSON_H
#define CASCADE_CAMPAIGN_REPORT_JSON_H

#include <jansson.h>

#include "study_analysis.h"

/* A new document; `references` and `refinement` (may be NULL) are lists
 * added as they are (new references taken). */
json_t *report_json(const struct study_analysis *a, const char *source, const char *generated,
                    json_t *references, json_t *refinement);

/* Write the document to `path` (through a temporary file: no half-written
 * report.json is ever left). */
int report_json_write(const json_t *doc, const char *path, struct err *e);

/* A finite number, or null. */
json_t *report_json_num(double x);

#endif
