/* report_extra: reference rows and refinement state in a report (see report_extra.h). */
#include "report_extra.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "report_build.h"
#include "study_analysis.h"
#include "util/mem.h"

#define CELL 160

static void num(const json_t *v, int digits, char *out, size_t len)
{
    if (json_is_number(v))
        report_num(json_number_value(v), digits, out, len);
    else
        snprintf(out, len, "—");
}

static void pct(const json_t *v, char *out, size_t len)
{
    if (json_is_number(v))
        snprintf(out, len, "%#.4g %%", 100 * json_number_value(v));
    else
        snprintf(out, len, "—");
}

static void emit(struct rdoc *doc, int ncols, const char *const *hdr, char (*cells)[CELL], int nrows)
{
    const char **p = mem_alloc((size_t)(nrows ? nrows : 1) * (size_t)ncols * sizeof *p);
    if (!p)
        return;
    for (int i = 0; i < nrows * ncols; i++)
        p[i] = cells[i];
    rdoc_table(doc, ncols, hdr, nrows, p);
    free(p);
}

static void references(struct rdoc *doc, const json_t *refs)
{
    int n = (int)json_array_size(refs);
    if (!n)
        return;
    rdoc_heading(doc, 1, "Reference values");
    rdoc_para(doc, "Values imported with cascade import (source, file line), beside the "
                   "campaign's value at the same point of the sweep (repeats averaged); diff = "
                   "campaign - reference.");
    const char *hdr[] = {"source", "line", "parameters", "metric", "reference", "campaign", "diff",
                         "relative"};
    char(*cells)[CELL] = mem_calloc((size_t)n * 8, CELL);
    if (!cells)
        return;
    for (int i = 0; i < n; i++) {
        const json_t *r = json_array_get(refs, (size_t)i);
        char(*c)[CELL] = cells + 8 * i;
        char params[SA_LABEL_MAX], unit[64];
        sa_params_label(json_object_get(r, "params"), params, sizeof params);
        snprintf(c[0], CELL, "%s", json_string_value(json_object_get(r, "source")));
        snprintf(c[1], CELL, "%lld", (long long)json_integer_value(json_object_get(r, "line")));
        snprintf(c[2], CELL, "%s", params);
        snprintf(unit, sizeof unit, "%s", json_string_value(json_object_get(r, "unit")));
        snprintf(c[3], CELL, "%s [%s]", json_string_value(json_object_get(r, "metric")), unit);
        num(json_object_get(r, "value"), 10, c[4], CELL);
        num(json_object_get(r, "campaign"), 10, c[5], CELL);
        num(json_object_get(r, "diff"), 4, c[6], CELL);
        pct(json_object_get(r, "rel"), c[7], CELL);
    }
    emit(doc, 8, hdr, cells, n);
    free(cells);
}

static void refinement(struct rdoc *doc, const json_t *refine)
{
    int n = (int)json_array_size(refine);
    if (!n)
        return;
    rdoc_heading(doc, 1, "Adaptive refinement");
    rdoc_para(doc, "The runner added finer levels along %s to each series until the study's "
                   "refine: criteria were met, the level cap or the budget was reached, or the "
                   "sequence diverged or oscillated (docs/reports.md).",
              json_string_value(json_object_get(json_array_get(refine, 0), "axis")));
    const char *hdr[] = {"metric", "series", "levels", "finest", "value", "extrapolated",
                         "GCI fine", "band ±", "state", "why", "core-s spent", "next level (predicted core-s)"};
    char(*cells)[CELL] = mem_calloc((size_t)n * 12, CELL);
    if (!cells)
        return;
    for (int i = 0; i < n; i++) {
        const json_t *r = json_array_get(refine, (size_t)i);
        char(*c)[CELL] = cells + 12 * i;
        char series[SA_LABEL_MAX];
        sa_params_label(json_object_get(r, "series"), series, sizeof series);
        snprintf(c[0], CELL, "%s", json_string_value(json_object_get(r, "metric")));
        snprintf(c[1], CELL, "%s", series);
        snprintf(c[2], CELL, "%lld", (long long)json_integer_value(json_object_get(r, "levels")));
        const json_t *fv = json_object_get(r, "finest");
        if (json_is_number(fv)) {
            report_num(json_number_value(fv), 6, c[3], CELL);
        } else {
            char *f = json_dumps(fv, JSON_COMPACT | JSON_ENCODE_ANY);
            snprintf(c[3], CELL, "%s", f ? f : "?");
            free(f);
        }
        num(json_object_get(r, "value"), 10, c[4], CELL);
        num(json_object_get(r, "phi_ext"), 10, c[5], CELL);
        pct(json_object_get(r, "gci_fine"), c[6], CELL);
        num(json_object_get(r, "band"), 4, c[7], CELL);
        snprintf(c[8], CELL, "%s", json_string_value(json_object_get(r, "state")));
        snprintf(c[9], CELL, "%s", json_string_value(json_object_get(r, "reason")));
        num(json_object_get(r, "spent_core_s"), 4, c[10], CELL);
        num(json_object_get(r, "next_core_s"), 4, c[11], CELL);
    }
    emit(doc, 12, hdr, cells, n);
    free(cells);
}

void report_extra_sections(struct rdoc *doc, const json_t *refs, const json_t *refine)
{
    refinement(doc, refine);
    references(doc, refs);
}
