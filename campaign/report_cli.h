/*
 * report_cli: what `cascade report` does besides writing the report --
 * the format list (md, html, json), the convergence rows into the
 * database, and report.json on stdout.
 */
#ifndef CASCADE_CAMPAIGN_REPORT_CLI_H
#define CASCADE_CAMPAIGN_REPORT_CLI_H

#include "report_run.h"

/* "md", "html", "json" or a comma-separated list of them; -1 when bad. */
int report_parse_formats(const char *list, int *md, int *html, int *json);

/* Write the report's convergence rows (conv_store.h) to the database at
 * db_path; a failure is a warning on stderr (the report stands without). */
void report_store_convergence(const struct report_ctx *c, const char *db_path);

/* Copy dir/report.json to stdout. */
int report_print_json(const char *dir, struct err *e);

#endif
