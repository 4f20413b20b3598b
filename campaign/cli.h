/*
 * cli: the subcommands of `cascade` (one function each, in cmd_*.c) and the
 * option parsing they share.  Each returns the process exit code: 0 ok,
 * 1 a job failed / runtime error, 2 bad input or usage, 130 interrupted.
 */
#ifndef CASCADE_CAMPAIGN_CLI_H
#define CASCADE_CAMPAIGN_CLI_H

#include <stdio.h>

#define CASCADE_DB_DEFAULT "cascade.db"

int cmd_plan(int argc, char **argv);
int cmd_run(int argc, char **argv);
int cmd_status(int argc, char **argv);
int cmd_query(int argc, char **argv);
int cmd_show(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_retry(int argc, char **argv);
int cmd_report(int argc, char **argv);
int cmd_regress(int argc, char **argv);
int cmd_import(int argc, char **argv);
int cmd_cancel(int argc, char **argv);
/* cascade report --nightly (cmd_report_nightly.c) */
int cmd_report_nightly(int argc, char **argv);

/* Whether argv holds --help or -h. */
int cli_wants_help(int argc, char **argv);
/* Exit code for an err class. */
int cli_exit_code(int rc);
/* Option `name` with a value at argv[*i]: sets *val and advances; returns
 * 1 when matched, 0 when not, -1 when the value is missing (message printed). */
int cli_opt(int argc, char **argv, int *i, const char *name, const char **val);
/* Parse an integer option value; prints the error. */
int cli_int(const char *opt, const char *s, long lo, long hi, long *out);
int cli_real(const char *opt, const char *s, double lo, double *out);
/* "md", "html" or "md,html" into two flags; -1 when the list is bad. */
int cli_parse_formats(const char *list, int *md, int *html);
/* The arguments of a command that takes only [STUDY] [--db FILE]: sets
 * *study (left as it is when absent) and *db_path; returns 0, or 2 with
 * the error and usage printed. */
int cli_study_db_args(int argc, char **argv, const char *usage, const char **study,
                      const char **db_path);
/* Print "error: ..." and the usage; returns 2. */
int cli_usage_error(const char *usage, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
