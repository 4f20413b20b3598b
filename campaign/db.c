/* db: opening, migrating and small helpers for the results database. */
#include "db.h"

#include <jansson.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "util/canon.h"

#define DB_BUSY_MS 30000

const char *db_name(sqlite3 *db)
{
    const char *f = db ? sqlite3_db_filename(db, "main") : NULL;
    return f && f[0] ? f : ":memory:";
}

/* Every message of this layer names the file: a campaign may use several
 * databases (--db), and "attempt to write a readonly database" alone does
 * not say which. */
int db_err(sqlite3 *db, struct err *e, int code, const char *fmt, ...)
{
    char msg[ERR_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return err_set(e, code, "database %s: %s", db_name(db), msg);
}

int db_fail(sqlite3 *db, struct err *e, const char *what)
{
    return db_err(db, e, ERR_RUNTIME, "%s: %s", what, db ? sqlite3_errmsg(db) : "no handle");
}

int db_exec(sqlite3 *db, const char *sql, struct err *e)
{
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK) {
        int rc = db_err(db, e, ERR_RUNTIME, "%s (in: %.80s)", msg ? msg : sqlite3_errmsg(db),
                        sql);
        sqlite3_free(msg);
        return rc;
    }
    return 0;
}

int db_prepare(sqlite3 *db, const char *sql, sqlite3_stmt **st, struct err *e)
{
    if (sqlite3_prepare_v2(db, sql, -1, st, NULL) != SQLITE_OK)
        return db_err(db, e, ERR_RUNTIME, "%s (in: %.80s)", sqlite3_errmsg(db), sql);
    return 0;
}

int db_begin(sqlite3 *db, struct err *e)
{
    return db_exec(db, "BEGIN IMMEDIATE", e);
}

int db_commit(sqlite3 *db, struct err *e)
{
    return db_exec(db, "COMMIT", e);
}

void db_rollback(sqlite3 *db)
{
    if (!sqlite3_get_autocommit(db))
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
}

int db_user_version(sqlite3 *db, int *version, struct err *e)
{
    sqlite3_stmt *st;
    int rc = db_prepare(db, "PRAGMA user_version", &st, e);
    if (rc)
        return rc;
    if (sqlite3_step(st) != SQLITE_ROW) {
        sqlite3_finalize(st);
        return db_fail(db, e, "reading user_version");
    }
    *version = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    return 0;
}

int db_migrate(sqlite3 *db, const struct db_migration *list, int n, struct err *e)
{
    int rc = db_begin(db, e);
    if (rc)
        return rc;
    int v;
    if ((rc = db_user_version(db, &v, e))) {
        db_rollback(db);
        return rc;
    }
    if (v > n) {
        db_rollback(db);
        return db_err(db, e, ERR_INPUT,
                      "schema version %d, newer than this cascade knows (%d); use a newer cascade",
                      v, n);
    }
    for (; v < n; v++) {
        if ((rc = db_exec(db, list[v].sql, e))) {
            db_rollback(db);
            return err_prefix(e, "migration %s (schema version %d): ", list[v].name, v + 1);
        }
        char pragma[64];
        snprintf(pragma, sizeof pragma, "PRAGMA user_version = %d", v + 1);
        if ((rc = db_exec(db, pragma, e))) {
            db_rollback(db);
            return rc;
        }
    }
    return db_commit(db, e);
}

/* The journal mode of the file ("wal", "delete", ...) into mode, or "" when
 * the pragma could not run; returns the SQLite result (SQLITE_ROW when it
 * ran). */
static int journal_mode(sqlite3 *db, const char *sql, char *mode, size_t len)
{
    sqlite3_stmt *st = NULL;
    mode[0] = '\0';
    int r = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
    if (r == SQLITE_OK && (r = sqlite3_step(st)) == SQLITE_ROW) {
        const unsigned char *m = sqlite3_column_text(st, 0);
        snprintf(mode, len, "%s", m ? (const char *)m : "");
    }
    sqlite3_finalize(st);
    return r;
}

/* WAL is a property of the file: after the first runner converted it there
 * is nothing to do.  The conversion itself needs exclusive access and
 * SQLite does not call the busy handler for it, so two runners opening a
 * fresh database at once make one of them fail at once with "database is
 * locked": retry with a growing pause within the busy timeout. */
static int db_use_wal(sqlite3 *db, struct err *e)
{
    char mode[16];
    long waited_us = 0, pause_us = 1000;
    for (;;) {
        journal_mode(db, "PRAGMA journal_mode", mode, sizeof mode);
        if (strcmp(mode, "wal") == 0)
            return 0;
        int r = journal_mode(db, "PRAGMA journal_mode = WAL", mode, sizeof mode);
        if (strcmp(mode, "wal") == 0)
            return 0;
        /* only another connection in the way is worth waiting for; a file
         * that cannot be written (permissions, a read-only file system)
         * stays so */
        int busy = (r & 0xff) == SQLITE_BUSY || (r & 0xff) == SQLITE_LOCKED;
        if (!busy || waited_us >= (long)DB_BUSY_MS * 1000)
            return db_err(db, e, ERR_RUNTIME, "cannot switch to WAL journal mode: %s",
                          sqlite3_errmsg(db));
        usleep((useconds_t)pause_us);
        waited_us += pause_us;
        if (pause_us < 100000)
            pause_us *= 2;
    }
}

static int db_configure(sqlite3 *db, int readonly, struct err *e)
{
    sqlite3_busy_timeout(db, DB_BUSY_MS);
    int rc = db_exec(db, "PRAGMA foreign_keys = ON", e);
    if (!rc && !readonly)
        rc = db_use_wal(db, e);
    if (!rc && !readonly)
        rc = db_exec(db, "PRAGMA synchronous = NORMAL", e);
    if (!rc && readonly)
        rc = db_exec(db, "PRAGMA query_only = ON", e);
    return rc;
}

int db_open(const char *path, sqlite3 **out, struct err *e)
{
    sqlite3 *db = NULL;
    *out = NULL;
    if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL) != SQLITE_OK) {
        int rc = err_set(e, ERR_RUNTIME, "database %s: cannot open: %s", path,
                         db ? sqlite3_errmsg(db) : "out of memory");
        sqlite3_close(db);
        return rc;
    }
    /* SQLite opens a file it may not write read-only without a word; every
     * writing command would then fail on its first write, after the plan */
    if (sqlite3_db_readonly(db, "main") == 1) {
        int rc = db_err(db, e, ERR_RUNTIME,
                        "cannot open for writing (read-only: check the permissions of the file "
                        "and its directory)");
        sqlite3_close(db);
        return rc;
    }
    int n;
    const struct db_migration *list = db_migrations(&n);
    int rc = db_configure(db, 0, e);
    if (!rc)
        rc = db_migrate(db, list, n, e);
    if (rc) {
        sqlite3_close(db);
        return rc;
    }
    *out = db;
    return 0;
}

int db_open_readonly(const char *path, sqlite3 **out, struct err *e)
{
    sqlite3 *db = NULL;
    *out = NULL;
    if (access(path, F_OK) != 0)
        return err_set(e, ERR_INPUT, "%s: no such database (run 'cascade run STUDY.yaml' first, "
                                     "or give --db FILE)", path);
    if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL) != SQLITE_OK) {
        int rc = err_set(e, ERR_RUNTIME, "database %s: cannot open: %s", path,
                         db ? sqlite3_errmsg(db) : "out of memory");
        sqlite3_close(db);
        return rc;
    }
    int n, v = 0;
    db_migrations(&n);
    int rc = db_configure(db, 1, e);
    if (!rc)
        rc = db_user_version(db, &v, e);
    if (!rc && v > n)
        rc = db_err(db, e, ERR_INPUT, "schema version %d is newer than this cascade knows (%d)", v,
                    n);
    if (!rc && v == 0)
        rc = db_err(db, e, ERR_INPUT, "not a Cascade database (schema version 0)");
    if (rc) {
        sqlite3_close(db);
        return rc;
    }
    *out = db;
    return 0;
}

void db_close(sqlite3 **db)
{
    if (db && *db) {
        sqlite3_close(*db);
        *db = NULL;
    }
}

int db_bind_json_value(sqlite3_stmt *st, int idx, const void *value)
{
    const json_t *v = value;
    switch (json_typeof(v)) {
    case JSON_INTEGER: return sqlite3_bind_int64(st, idx, (sqlite3_int64)json_integer_value(v));
    case JSON_REAL: return sqlite3_bind_double(st, idx, json_real_value(v));
    case JSON_TRUE: return sqlite3_bind_int(st, idx, 1);
    case JSON_FALSE: return sqlite3_bind_int(st, idx, 0);
    case JSON_NULL: return sqlite3_bind_null(st, idx);
    case JSON_STRING: return sqlite3_bind_text(st, idx, json_string_value(v), -1, SQLITE_TRANSIENT);
    default: {
        char *text = canon_json(v);
        int rc = sqlite3_bind_text(st, idx, text ? text : "", -1, SQLITE_TRANSIENT);
        free(text);
        return rc;
    }
    }
}
