/*
 * db_fault: fault injection for the results database, in the spirit of
 * SQLite's own I/O-error and malloc-failure tests.  Off unless `cascade` is
 * started with one of (read once in campaign/main.c, handed over here before
 * SQLite is first used):
 *
 *   CASCADE_FAULT_IO=N       the Nth xWrite or xSync SQLite makes (any file:
 *                            database, WAL, journal) fails: a write with
 *                            SQLITE_FULL, a sync with SQLITE_IOERR_FSYNC
 *   CASCADE_FAULT_MALLOC=N   the Nth allocation SQLite makes (malloc or
 *                            realloc) fails
 *
 * N alone fails that one call (a transient fault: later calls succeed
 * again); "N+" fails it and every later one (a persistent fault: a disk
 * that stays full); 0 only counts.  When either is set, `cascade` ends by
 * printing on stderr one line per hook:
 *
 *   cascade: fault injection: io: N calls, failed M
 *
 * (M: how many calls were failed), so a test can first count a run's calls
 * and then fail each of them in turn.
 *
 * The I/O hook is a VFS ("cascade-fault") that wraps the default one and is
 * made the default; the malloc hook wraps SQLite's allocator
 * (SQLITE_CONFIG_MALLOC), so it must be installed before SQLite initialises.
 *
 * The counters are the one piece of mutable global state of the campaign
 * library: they live in db_fault.c alone, and nothing else reads or writes
 * them.
 */
#ifndef CASCADE_CAMPAIGN_DB_FAULT_H
#define CASCADE_CAMPAIGN_DB_FAULT_H

#include <stdio.h>

#include "util/err.h"

/* Install the hooks: io_spec / malloc_spec are the environment values (NULL
 * or "" leaves that hook off).  Call once, before any other SQLite use.
 * ERR_INPUT on a malformed value, ERR_RUNTIME when SQLite refuses. */
int db_fault_install(const char *io_spec, const char *malloc_spec, struct err *e);

/* Print the counts of the installed hooks to f (nothing when none is). */
void db_fault_report(FILE *f);

#endif
