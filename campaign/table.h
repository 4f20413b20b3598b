/*
 * table: printing result rows of SQL statements as an aligned text table,
 * CSV (RFC 4180) or JSON lines.  Reals print in the shortest form that
 * reads back to the same double.
 */
#ifndef CASCADE_CAMPAIGN_TABLE_H
#define CASCADE_CAMPAIGN_TABLE_H

#include <sqlite3.h>
#include <stdio.h>

#include "util/err.h"

enum table_format { TABLE_TEXT, TABLE_CSV, TABLE_JSON };

/* Step a prepared statement to the end, printing its rows (with a header
 * for text and CSV).  *nrows receives the row count. */
int table_print(sqlite3 *db, sqlite3_stmt *st, enum table_format f, FILE *out, long *nrows,
                struct err *e);

/* One column value as text (NULL -> ""), into buf. */
void table_cell(sqlite3_stmt *st, int col, char *buf, size_t len);

/* Write s as one CSV field. */
void table_csv_field(FILE *out, const char *s);

#endif
