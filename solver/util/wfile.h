/*
 * wfile: writing a file so no reader ever sees it half-written.  The data
 * goes to PATH.tmp; wfile_commit flushes, fsyncs, closes and renames it
 * over PATH.  A failure at any step removes PATH.tmp and leaves whatever
 * PATH was before (the previous complete file, or none).
 *
 * A file written during a whole run (thermo.csv, snapshots.xyz) is the same
 * with wfile_flush after each record: PATH.tmp grows while the run goes on
 * (a run killed on the way leaves it, named as what it is) and becomes PATH
 * when the run ends well.
 *
 * Every step is a fault point of CASCADE_FAULT_WRITE (util/fault.h): the
 * open (ENOSPC), each flush and the last one (ENOSPC), the fsync (EIO), the
 * rename (ENOSPC).  Messages read "cannot write PATH: <why>".
 */
#ifndef CASCADE_WFILE_H
#define CASCADE_WFILE_H

#include <stdio.h>

#include "util/err.h"

struct wfile {
    FILE *f;             /* write here (NULL when not open) */
    int no_sync;         /* commit without fsync (set after wfile_open) */
    char path[4096];     /* the file's name */
    char tmp[4096 + 8];  /* PATH.tmp, renamed over path by wfile_commit */
};

/* Open PATH.tmp for writing (truncating it); on failure errno says why. */
int wfile_open(struct wfile *w, const char *path, struct err *e);
/* Hand the buffered data to the kernel (after each record of a stream);
 * on failure the file is discarded. */
int wfile_flush(struct wfile *w, struct err *e);
/* Flush, fsync, close, rename over PATH.  The file is closed either way;
 * on failure PATH.tmp is removed.  Nothing when w is not open. */
int wfile_commit(struct wfile *w, struct err *e);
/* Close and remove PATH.tmp (an error elsewhere: nothing half-written
 * stays); nothing when w is not open. */
void wfile_discard(struct wfile *w);

/* The whole of `text` as the file PATH (wfile_open + fputs + commit);
 * durable 0 skips the fsync, for a file that is read at once and rewritten
 * whenever it is needed again (a job's case.yaml: a machine that goes down
 * takes the job with it). */
int wfile_write_text(const char *path, const char *text, int durable, struct err *e);

/* mkdir and rename behind a write fault point (0, or -1 with errno); the
 * mkdir of a path that exists is not a fault point. */
int wfile_mkdir(const char *path, unsigned mode);
int wfile_rename(const char *from, const char *to);

#endif
