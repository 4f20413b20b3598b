/*
 * db: the SQLite results database -- opening it the one way Cascade does
 * (WAL, foreign keys, busy timeout), bringing its schema up to date through
 * PRAGMA user_version, and small statement helpers.
 *
 * The schema lives in db/schema.sql (version 1) and db/migrations/ (versions
 * 2, 3, ...); the build embeds those files, so bin/cascade needs no data
 * files at run time.
 */
#ifndef CASCADE_CAMPAIGN_DB_H
#define CASCADE_CAMPAIGN_DB_H

#include <sqlite3.h>

#include "util/err.h"

struct db_migration {
    const char *name;   /* file name, e.g. "schema.sql" or "0002_x.sql" */
    const char *sql;
};

/* The migrations built into this program; version = index + 1. */
const struct db_migration *db_migrations(int *n);

/* Open (creating when absent) for writing and migrate to the newest schema. */
int db_open(const char *path, sqlite3 **db, struct err *e);
/* Open an existing database read-only (PRAGMA query_only); refuses a
 * database newer than this program. */
int db_open_readonly(const char *path, sqlite3 **db, struct err *e);
void db_close(sqlite3 **db);

/* Apply list[v..n-1] to a database at user_version v, all in one
 * transaction: either every step applies or none.  Refuses v > n. */
int db_migrate(sqlite3 *db, const struct db_migration *list, int n, struct err *e);
int db_user_version(sqlite3 *db, int *version, struct err *e);

/* Run SQL without results (several statements allowed). */
int db_exec(sqlite3 *db, const char *sql, struct err *e);
/* Prepare one statement; on error the message names the SQL. */
int db_prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st, struct err *e);
/* Every error of this layer reads "database PATH: ...". */
/* Record the database's current error for `what`; returns ERR_RUNTIME. */
int db_fail(sqlite3 *db, struct err *e, const char *what);
/* Record an error about the database (printf-style); returns code. */
int db_err(sqlite3 *db, struct err *e, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* The database's file name (absolute), ":memory:" for none. */
const char *db_name(sqlite3 *db);

/* BEGIN IMMEDIATE / COMMIT / ROLLBACK (rollback never fails loudly). */
int db_begin(sqlite3 *db, struct err *e);
int db_commit(sqlite3 *db, struct err *e);
void db_rollback(sqlite3 *db);

/* Bind a JSON scalar the way job_params stores it: integers and reals as
 * numbers, booleans as 0/1, strings as text, lists/mappings as JSON text. */
int db_bind_json_value(sqlite3_stmt *st, int idx, const void *json_value);

#endif
