/*
 * baseline_conv: the converged results of a study with `refine:` in its
 * regression baseline -- per metric and series, the state the refinement
 * ended in (converged / stopped), the level it ended at (the number of
 * levels and the finest value of the axis) and the metric's value there:
 *
 *   "converged": [{"finest":0.0125,"group":{"fake.y":1.0},"levels":7,
 *                  "metric":"sum","state":"converged","value":1.0125}, ...]
 *
 * `cascade regress` flags a change of the level or the state (exactly) and
 * of the value (the metric's value tolerance).
 */
#ifndef CASCADE_CAMPAIGN_BASELINE_CONV_H
#define CASCADE_CAMPAIGN_BASELINE_CONV_H

#include <jansson.h>

#include "baseline.h"

/* Add "converged" to a baseline when the analysis carries a refinement state. */
void baseline_conv_add(json_t *b, const struct study_analysis *a);
/* NULL when the baseline's "converged" (optional) is well formed, else why not. */
const char *baseline_conv_check(const json_t *b);
/* Compare the baseline's "converged" entries with the refinement state now. */
void baseline_conv_compare(const json_t *b, const struct study_analysis *a,
                           const struct report_spec *rs, struct cmp_report *r);

#endif
