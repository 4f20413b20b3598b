/*
 * baseline: the reviewed numbers a regression check compares against -- a
 * JSON file in the repository (studies/baselines/NAME.json) with every
 * metric value at every point of the sweep (repeats averaged) and every
 * observed order along the resolution axis, and the solver version that
 * produced them.  One entry per line, keys sorted and numbers in their
 * shortest exact form, so a change reads well in a diff:
 *
 *   {"format": "cascade-baseline 1", "study": "nightly", "created": "...",
 *    "solver": {"version": "0.1.0", "git": "abc"}, "cascade": "...",
 *    "resolution": "md.timestep",
 *    "values": [{"metric":"pe_per_atom","params":{...},"unit":"eV/atom","value":-3.49},
 *               ...],
 *    "orders": [{"extrapolated":-3.4967,"group":{...},"kind":"monotone",
 *                "metric":"pe_per_atom","p":1.998}, ...],
 *    "converged": [...]}   (a study with refine:, baseline_conv.h)
 *
 * Comparison: a value passes when |now - baseline| <= abs + rel |baseline|
 * with the metric's tolerances (report_spec.h), an order when |p_now -
 * p_baseline| <= the order tolerance and the convergence kind (monotone,
 * oscillatory, ...) is unchanged.  A baseline entry with no current value
 * (a job failed, a point or metric gone) and a job not done both count as
 * regressions; current values the baseline lacks are listed as new.
 */
#ifndef CASCADE_CAMPAIGN_BASELINE_H
#define CASCADE_CAMPAIGN_BASELINE_H

#include <jansson.h>
#include <stdio.h>

#include "report_doc.h"
#include "study_analysis.h"

#define BASELINE_FORMAT "cascade-baseline 1"

/* The baseline of an analysis (a new reference). */
json_t *baseline_build(const struct study_analysis *a, const char *created);
/* Write it (one entry per line). */
int baseline_write(const json_t *b, const char *path, struct err *e);
/* Read and check a baseline file of study `study`; *text receives the file's
 * bytes (malloc'ed). */
int baseline_read(const char *path, const char *study, json_t **b, char **text, struct err *e);

/* The solver ('version (git)') most of the analysed values come from, or "". */
void baseline_solver_of(const struct study_analysis *a, char *out, size_t len);
/* Split 'version (git)' into its parts. */
void baseline_split_solver(const char *s, char *version, size_t vlen, char *git, size_t glen);

enum cmp_verdict { CMP_OK, CMP_REGRESSED, CMP_MISSING, CMP_FAILED, CMP_NEW };
extern const char *const cmp_verdict_names[];   /* ok, REGRESSED, MISSING, FAILED, new */

struct cmp_item {
    enum cmp_verdict verdict;
    char metric[128];
    char what[16];               /* value | order | job */
    char where[SA_LABEL_MAX];    /* the point, the series, or the job */
    double base, now, tol;       /* NaN where not applicable */
    char note[256];
};

struct cmp_report {
    struct cmp_item *it;
    int n, cap;
    int compared;                /* baseline entries compared */
    int regressed;               /* REGRESSED + MISSING + FAILED */
    int added;                   /* NEW */
};

/* Add an item to a comparison (for the comparisons of baseline_conv.h);
 * NULL when out of memory. */
struct cmp_item *cmp_add_item(struct cmp_report *r, enum cmp_verdict v, const char *metric,
                              const char *what, const char *where);

int baseline_compare(const json_t *b, const struct study_analysis *a,
                     const struct report_spec *rs, struct cmp_report *r, struct err *e);
void cmp_free(struct cmp_report *r);

/* The diff table as text: every item, or only those that did not pass. */
void cmp_print(const struct cmp_report *r, FILE *out, int all);
/* The same as a report section. */
void cmp_to_doc(const struct cmp_report *r, struct rdoc *doc, const char *baseline_path,
                const char *baseline_solver);
/* The items that did not pass, as a JSON list (new reference). */
json_t *cmp_failures_json(const struct cmp_report *r);

#endif
