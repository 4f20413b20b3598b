/*
 * import_parse: reference rows of an external source read from a file, for
 * `cascade import` -- no database here.
 *
 * CSV: a header line, then one row per line.  A column named `name [unit]`
 * is a metric (`[1]` for a dimensionless one), a column without brackets a
 * parameter (a swept case key such as grid.cell, or any name for a study
 * that has only references).  Lines starting with '#' are comments; one of
 * them may say `# source: NAME`.  Fields may be double-quoted ("" for a
 * quote).  Numbers become numbers (integers stay integers), other text a
 * string; an empty metric cell is a missing value, an empty parameter cell
 * an error.
 *
 *   # source: Celik et al. 2008, Table 1
 *   cells,phi [1]
 *   18000,6.063
 *
 * JSON (or YAML; --json): {"source": NAME, "rows": [{"params": {...},
 * "metrics": {NAME: {"value": x, "unit": "u"}, ...}}, ...]}.
 *
 * Every error names the file, line (and column for JSON) and the field.
 */
#ifndef CASCADE_CAMPAIGN_IMPORT_PARSE_H
#define CASCADE_CAMPAIGN_IMPORT_PARSE_H

#include <jansson.h>

#include "util/err.h"

struct import_row {
    int line;                 /* where it was written */
    int col;                  /* JSON: column of the row (0 for CSV) */
    json_t *params;           /* owned: {name: value} */
    json_t *metrics;          /* owned: {name: {"value": x | null, "unit": u}} */
};

struct import_set {
    char file[4096];
    char source[256];         /* from the file, or "" */
    struct import_row *rows;
    int nrows;
    /* for messages about a column: the line of the header (CSV) */
    int header_line;
};

/* Read a CSV (json = 0) or JSON/YAML (json = 1) file.  ERR_INPUT with
 * "file:line: field: ..." on any problem. */
int import_parse(const char *path, int json, struct import_set *out, struct err *e);
void import_set_free(struct import_set *s);

/* "file:line" (or "file:line:col") of row i, into out. */
void import_where(const struct import_set *s, int i, char *out, size_t len);

#endif
