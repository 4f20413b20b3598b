/*
 * report_build: a study's report as a document (report_doc.h) -- summary,
 * failed and missing jobs, convergence along the resolution axis (values,
 * observed order, Richardson extrapolation, GCI, flags, two figures per
 * metric), the metrics against the other swept axes with the requested
 * fits, and a short note on the method.  Figures are drawn with gnuplot
 * into the report directory as SVG files.
 */
#ifndef CASCADE_CAMPAIGN_REPORT_BUILD_H
#define CASCADE_CAMPAIGN_REPORT_BUILD_H

#include "report_doc.h"
#include "study_analysis.h"

struct report_info {
    const char *db_path;       /* shown in the header */
    const char *generated;     /* ISO time */
};

/* Add the study's sections to `doc` and draw the figures into `dir` (which
 * must exist). */
int report_build(struct rdoc *doc, const struct study_analysis *a, const struct report_info *ri,
                 const char *dir, struct err *e);

/* Write dir/report.md and/or dir/report.html. */
int report_write(const struct rdoc *doc, const char *dir, int md, int html, struct err *e);

/* Format a number for a table: shortest text that keeps `digits`
 * significant digits ("—" for NaN). */
void report_num(double x, int digits, char *out, size_t len);

#endif
