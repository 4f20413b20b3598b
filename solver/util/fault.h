/*
 * fault: failing the Nth allocation or the Nth file write of a process on
 * request, so tests can walk every error path of the programs' own code the
 * way SQLite's malloc and I/O-error tests walk SQLite's (docs/fuzzing.md,
 * "Fault injection").  Off unless a program's main() installs it from
 *
 *   CASCADE_FAULT_ALLOC=N   the Nth allocation through util/mem.h fails
 *   CASCADE_FAULT_WRITE=N   the Nth write-side file operation fails: an open
 *                           for writing (a file, an HDF5 file, a directory),
 *                           a write (a flush of buffered data, an HDF5
 *                           dataset), an fsync or a rename (util/wfile.h,
 *                           solver/output/h5out.c, checkpoint.c, ...)
 *
 * N alone fails that one call (transient); "N+" fails it and every later
 * one (a disk that stays full); 0 only counts.  fault_report() then prints
 * "PROG: fault injection: alloc: C calls, failed M" (and "write: ..."), so
 * a test counts a command's calls first and then fails each in turn.
 *
 * The counters are process-wide mutable state, the one exception to the
 * project's rule against it: a fault point sits in functions as low as
 * malloc (hundreds of call sites, no context to thread through), and the
 * count must run across the whole process to name "the Nth call".  They
 * live in fault.c alone; when nothing is installed a fault point costs one
 * load and one branch.  Counting is atomic (OpenMP threads allocate).
 */
#ifndef CASCADE_FAULT_H
#define CASCADE_FAULT_H

#include <stdio.h>

#include "util/err.h"

/* Install from the two environment values (NULL or "": that hook off).
 * ERR_INPUT naming the variable on a malformed value. */
int fault_install(const char *alloc_spec, const char *write_spec, struct err *e);

/* Whether any hook is installed (the report is printed only then). */
int fault_installed(void);

/* A fault point for an allocation: 1 when this one is to fail. */
int fault_alloc_fails(void);

/* A fault point for a write-side file operation: when this one is to fail,
 * errno = err and -1; otherwise 0.  Call it just before the real operation:
 *     if (fault_write(ENOSPC) != 0 || fflush(f) != 0) -> error, strerror(errno) */
int fault_write(int err);

/* "PROG: fault injection: alloc|write: C calls, failed M" per installed hook. */
void fault_report(FILE *f, const char *prog);

#endif
