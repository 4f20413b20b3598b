/*
 * checkpoint: the complete state of a run in one HDF5 file, so that a run
 * killed at any step continues bitwise from its last checkpoint.
 *
 * Layout:
 *   /   attributes format = "cascade-checkpoint", version, case_key, step,
 *       time_ps, case (canonical JSON); every dataset is chunked with a
 *       Fletcher-32 checksum, so a corrupt file is refused on read
 *   /engine/...        the loop's own state (step, phase, initial energies)
 *   /model/<name>/...  each model's state (particles, grid points, ...)
 *   /case/...          the case type's accumulators and partial series
 *
 * Files are written to a temporary name and renamed, so a reader never sees
 * half a checkpoint; the writer keeps the newest two (sim.c).
 *
 * Every function returns 0 or an error code with the message in the err
 * given at open/create: the message names the file and the dataset.
 */
#ifndef CASCADE_CHECKPOINT_H
#define CASCADE_CHECKPOINT_H

#include <hdf5.h>
#include <jansson.h>
#include <stdint.h>

#include "core/box.h"
#include "core/particles.h"
#include "util/err.h"

#define CKPT_FORMAT "cascade-checkpoint"
#define CKPT_VERSION 1

struct ckpt {
    hid_t file;
    hid_t group;          /* where put/get act: a subgroup, or the file */
    char path[4096];
    char where[128];      /* current group name, for messages */
    int writing;
    int par;              /* open through MPI-IO on every rank (ckpt_open_parallel) */
    struct err *e;
};

/* Create `path` (truncating) with the root attributes. */
int ckpt_create(struct ckpt *c, const char *path, const json_t *case_doc, const char *case_key,
                long step, double time, struct err *e);
/* Open `path` for reading: refuses another format or version, and a case
 * key other than `expect_key` (NULL: any).  *step gets the step it holds. */
int ckpt_open(struct ckpt *c, const char *path, const char *expect_key, long *step,
              struct err *e);
/* Close; 0 or the error of the final flush (a full disk shows here). */
int ckpt_close(struct ckpt *c);

/* Enter group `name` (a path like "model/md"); created when writing. */
int ckpt_enter(struct ckpt *c, const char *name);

int ckpt_put_doubles(struct ckpt *c, const char *name, const double *d, long n);
int ckpt_put_i64(struct ckpt *c, const char *name, const int64_t *d, long n);
int ckpt_put_ints(struct ckpt *c, const char *name, const int *d, long n);
int ckpt_put_u32(struct ckpt *c, const char *name, const uint32_t *d, long n);
int ckpt_put_double(struct ckpt *c, const char *name, double v);
/* Plain structs of numbers (statistics of an analysis) as bytes: a
 * checkpoint is read by the build that wrote it (format version). */
int ckpt_put_bytes(struct ckpt *c, const char *name, const void *d, long n);
int ckpt_get_bytes(struct ckpt *c, const char *name, void *d, long n);
int ckpt_put_long(struct ckpt *c, const char *name, long v);

/* Length of a 1-D dataset, or -1 (with the error set) when missing. */
long ckpt_len(struct ckpt *c, const char *name);
/* Reads check the stored length against n exactly. */
int ckpt_get_doubles(struct ckpt *c, const char *name, double *d, long n);
int ckpt_get_i64(struct ckpt *c, const char *name, int64_t *d, long n);
int ckpt_get_ints(struct ckpt *c, const char *name, int *d, long n);
int ckpt_get_u32(struct ckpt *c, const char *name, uint32_t *d, long n);
int ckpt_get_double(struct ckpt *c, const char *name, double *v);
int ckpt_get_long(struct ckpt *c, const char *name, long *v);

/* A table stored as rows of ncols values (thermo rows, series): a new
 * array into *rows (the old one freed) and the row count into *nrows. */
int ckpt_get_rows(struct ckpt *c, const char *name, int ncols, double **rows, long *nrows);

/* Whether the current group holds `name`. */
int ckpt_has(struct ckpt *c, const char *name);

/* Tables of rows (a particle set's datasets): column q holds ncomp values
 * of one type per row, in dataset `name`, from data (rows in memory). */
struct ckpt_col {
    char name[64];
    hid_t memtype, filetype;
    int ncomp;
    const void *data;
};
/* n rows of every column: with their data, or the datasets only (the
 * serial phase of a collective checkpoint, below). */
int ckpt_put_columns(struct ckpt *c, const struct ckpt_col *col, int ncol, long n, int with_data);
/* Rows [first, first + count) of every column from its data, into the
 * datasets ckpt_put_columns laid out, in collective transfers on a file of
 * ckpt_open_parallel.  Collective. */
int ckpt_put_columns_part(struct ckpt *c, const struct ckpt_col *col, int ncol, long first,
                          long count);
/* Every one of the n stored rows, in blocks (the memory is one block of
 * every column): take(ctx, buf, k) for row k of a block, buf[q] the
 * block's values of column q (its data field is not used); a non-zero
 * return stops the read and is returned.  Each column's length is checked
 * against n first.  On a file of ckpt_open_parallel every rank reads every
 * block (collective transfers; an error on one rank is an error on all). */
int ckpt_get_columns_blocks(struct ckpt *c, const struct ckpt_col *col, int ncol, long n,
                            int (*take)(void *ctx, const void *const *buf, long k), void *ctx);

/* A particle set's owned particles (positions, velocities, forces, types,
 * ids, masks, images, per-particle energies and virials, extra fields) and
 * its type table, under group `name`. */
int ckpt_put_particles(struct ckpt *c, const char *name, const struct particles *p);
/* Replace the owned particles of p (ghosts dropped) by the stored ones, in
 * the stored order; the type table and the field names must match. */
int ckpt_get_particles(struct ckpt *c, const char *name, struct particles *p);

/* The same, keeping only the stored particles for which keep(ctx, x) is
 * non-zero (keep NULL: all), read in blocks: the memory is the kept
 * particles and one block, not the whole set (a rank of a brick
 * decomposition reads its brick's atoms).  Every stored particle is
 * checked as above; ids are checked unique among the kept ones (across
 * ranks the caller checks). */
int ckpt_get_particles_where(struct ckpt *c, const char *name, struct particles *p,
                             int (*keep)(const void *ctx, const double x[3]), const void *ctx);
/* The same, keep() given the row's values of p's field `field` (3
 * components, stored with the particles) instead of its position. */
int ckpt_get_particles_where_field(struct ckpt *c, const char *name, struct particles *p,
                                   const char *field,
                                   int (*keep)(const void *ctx, const double x[3]),
                                   const void *ctx);

/* Collective checkpoints of a brick decomposition (docs/parallel.md,
 * "Output"): rank 0 writes the file serially, a particle set with
 * ckpt_put_particles_layout (its datasets sized for every rank's particles,
 * no data), and closes it; then every rank opens it with
 * ckpt_open_parallel and writes its own particles' rows with
 * ckpt_put_particles_part at the offset of an MPI_Exscan of the counts, in
 * collective transfers (H5FD_MPIO_COLLECTIVE).  The file is the one a
 * serial writer makes from the same particles in rank order. */
int ckpt_put_particles_layout(struct ckpt *c, const char *name, const struct particles *p,
                              long n_total);
/* Open `path` on every rank through MPI-IO (H5Pset_fapl_mpio), for
 * writing the parts (writing 1) or for reading (writing 0: the checks of
 * ckpt_open).  Collective over MPI_COMM_WORLD; a failure on any rank fails
 * every rank. */
int ckpt_open_parallel(struct ckpt *c, const char *path, int writing, const char *expect_key,
                       long *step, struct err *e);
/* This rank's owned particles as rows [offset, offset + n_owned) of the
 * group laid out by ckpt_put_particles_layout.  Collective. */
int ckpt_put_particles_part(struct ckpt *c, const char *name, const struct particles *p,
                            long offset);
/* The stored particles split evenly over the ranks in stored order: this
 * rank reads rows [n rank / nranks, n (rank + 1) / nranks) in blocks, with
 * collective transfers when the file was opened by ckpt_open_parallel
 * (every rank calls it), checking them as ckpt_get_particles does (ids
 * unique among this rank's rows; across ranks the caller checks).  The
 * particles are not in their bricks: the caller migrates them. */
int ckpt_get_particles_part(struct ckpt *c, const char *name, struct particles *p, int rank,
                            int nranks);
/* rc agreed over the ranks of a parallel checkpoint (rc itself otherwise). */
int ckpt_agree(const struct ckpt *c, int rc);

/* The box bounds and boundaries (free boundaries move with the particles). */
int ckpt_put_box(struct ckpt *c, const char *name, const struct box *b);
int ckpt_get_box(struct ckpt *c, const char *name, struct box *b);

#endif
