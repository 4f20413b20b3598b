/*
 * report_doc: one report as a list of blocks (headings, paragraphs, tables,
 * figures) written twice -- a Markdown page whose figures are SVG files next
 * to it, and a self-contained HTML page with the SVG inline.
 */
#ifndef CASCADE_REPORT_DOC_H
#define CASCADE_REPORT_DOC_H

#include "util/err.h"

struct rdoc;

struct rdoc *rdoc_create(const char *title);
void rdoc_destroy(struct rdoc **d);

void rdoc_heading(struct rdoc *d, int level, const char *text);
void rdoc_para(struct rdoc *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A table; cells are copied.  rows x ncols cells in row-major order. */
void rdoc_table(struct rdoc *d, int ncols, const char *const *header, int nrows,
                const char *const *cells);
/* A figure: an SVG file (path relative to the report directory for the
 * Markdown page; read and inlined into the HTML page). */
void rdoc_figure(struct rdoc *d, const char *dir, const char *svg_name, const char *caption);

/* Memory ran out while building a block outside: writing the document fails
 * (rdoc_write_* say so) rather than leave the block out. */
void rdoc_mark_incomplete(struct rdoc *d);

int rdoc_write_markdown(const struct rdoc *d, const char *path, struct err *e);
int rdoc_write_html(const struct rdoc *d, const char *path, struct err *e);

#endif
