/*
 * ct: helpers for the campaign tests -- a scratch directory per test,
 * study files, running bin/cascade there (found through CASCADE_BIN, the
 * stand-in solver through CASCADE_STANDIN), and looking into the results
 * database with plain SQL.
 */
#ifndef CASCADE_TEST_CT_H
#define CASCADE_TEST_CT_H

#include <sqlite3.h>
#include <stddef.h>
#include <sys/types.h>

const char *ct_cascade_bin(void);
const char *ct_standin(void);

/* A fresh directory under /tmp (out: at least 64 bytes); ct_rmrf removes it. */
void ct_mkdir(char *out, size_t len);
void ct_rmrf(const char *dir);

/* Write text to dir/name; returns the path in a static slot 0..7. */
const char *ct_write(int slot, const char *dir, const char *name, const char *text);

/* dir/flaky.yaml (slot 0): two stand-in jobs that fail their first
 * attempt (each creates its flag file in dir) and pass the retry. */
void ct_write_flaky_study(const char *dir);

/* Run bin/cascade with the NULL-ended arguments in `dir`; output (stdout and
 * stderr) into out; returns the exit status (128 + signal when killed).
 * `env` (may be NULL) is a NULL-ended list of extra NAME=VALUE entries. */
int ct_cascade(const char *dir, const char *const *env, char *out, size_t len, ...);
/* ct_cascade as an unprivileged user: as root (where file permissions do
 * not stop a write), the child drops to uid/gid 65534 (nobody) first;
 * otherwise the same as ct_cascade.  dir must be readable by that user. */
int ct_cascade_unprivileged(const char *dir, char *out, size_t len, ...);
/* The same for any argv (argv[0] a path). */
int ct_exec(const char *dir, const char *const *env, const char *const *argv, char *out, size_t len);
/* Start argv in dir in the background (stdout/stderr to dir/name.log). */
pid_t ct_spawn(const char *dir, const char *const *env, const char *const *argv, const char *log);
/* Wait for a spawned process; returns its exit status or 128 + signal. */
int ct_wait(pid_t pid);

/* Open dir/cascade.db read-only (asserts). */
sqlite3 *ct_db(const char *dir);
/* First column of the first row of an SQL query as an integer (asserts a row). */
long long ct_int(sqlite3 *db, const char *sql);
/* ... as a double. */
double ct_real(sqlite3 *db, const char *sql);
/* ... as text into out ("" when NULL). */
void ct_text(sqlite3 *db, const char *sql, char *out, size_t len);

#endif
