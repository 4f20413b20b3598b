/*
 * run: the services every case type uses while it runs -- output directory,
 * result.json, the HDF5/XDMF file, thermo CSV, extended XYZ, timers,
 * progress and the log.  A case type owns its models; the run owns the
 * outputs.
 */
#ifndef CASCADE_RUN_H
#define CASCADE_RUN_H

#include <jansson.h>
#include <stdint.h>
#include <stdio.h>

#include "core/box.h"
#include "core/particles.h"
#include "core/timers.h"
#include "output/h5out.h"
#include "output/progress.h"
#include "output/result.h"
#include "util/cfg.h"
#include "util/err.h"
#include "util/wfile.h"

struct parallel;

/* What the command line asks of a run. */
struct run_options {
    const char *out_dir;
    int nthreads;
    int progress;       /* show progress (terminal or plain lines) */
    int quiet;          /* only errors on stderr */
    int rank;           /* MPI rank: only rank 0 writes files and logs */
    const char *restart;/* checkpoint file to continue from (NULL: none) */
    long kill_at_step;  /* testing: SIGKILL itself after this step (0: never)
                         * unless it continues from a checkpoint; from
                         * CASCADE_SOLVER_KILL_AT_STEP */
    const struct parallel *par; /* the MPI ranks of the run (NULL: serial): a
                                 * failed write on one rank fails them all */
};

/* The `output` section of a case. */
struct output_settings {
    long thermo_every;      /* steps between thermo rows (0: first and last only) */
    long snapshot_every;    /* steps between HDF5 snapshots (0: first and last only) */
    long xyz_every;         /* steps between extended XYZ frames (0: none) */
    int hdf5;               /* write fields.h5 + fields.xdmf */
    long checkpoint_every;  /* steps between checkpoints (0: none; engine/sim.h) */
    const char *final_state;/* file name for the final particle state (NULL: none):
                             * NAME.data = LAMMPS data, NAME.xyz = extended XYZ;
                             * system.read_data / read_xyz of a later case reads it */
};

int output_settings_read(struct cfg_obj *root, struct output_settings *o);

struct run {
    struct run_options opt;
    struct output_settings out;
    json_t *case_doc;          /* resolved case (borrowed) */
    char case_key[32];
    uint64_t seed;
    char title[256];
    struct result result;
    struct h5out h5;
    int h5_open;
    struct wfile thermo_w;     /* thermo.csv (written as thermo.csv.tmp until run_close) */
    struct wfile xyz_w;        /* snapshots.xyz (the same) */
    FILE *thermo_csv;          /* thermo_w.f, NULL when not written (or after a failure) */
    FILE *xyz;                 /* xyz_w.f, the same */
    struct err write_err;      /* the first failed write of a stream: run_close reports it */
    FILE *log;                 /* stderr unless quiet */
    struct timers timers;
    struct progress progress;
    long steps_run;            /* steps for the timing report, set by cases that
                                * do not run md.steps (0: md.steps) */
};

int run_open(struct run *r, const struct run_options *opt, const struct output_settings *out,
             json_t *case_doc, uint64_t seed, const char *title, struct err *e);
/* Write result.json with status and timing, close every file.  `status` is
 * "ok", "diverged" or "failed"; when a file cannot be completed (a write
 * failed), result.json says "failed" with that message, and so does e.
 * thermo.csv, snapshots.xyz and fields.h5/.xdmf (written as NAME.tmp until
 * here) are kept for "ok" and "diverged" and removed for "failed": a run
 * that failed leaves no output cut short under its final name.  A run that
 * never gets here (killed) leaves NAME.tmp. */
int run_close(struct run *r, const char *status, const char *message, long steps, long particles,
              struct err *e);

/* Close every file of a run that ends before run_close (an error while
 * opening): the files written so far are removed, nothing is written. */
void run_discard(struct run *r);

/* Write the final particle state when the case asks for it
 * (output.final_state) and list it under "artifacts" in result.json. */
int run_write_final_state(struct run *r, const struct particles *p, const struct box *b,
                          long step, double time, struct err *e);
/* The parts of it for a writer on bricks (output/final_state.c): the
 * data file's title; the record of the file in result.json (rank 0). */
void run_final_state_title(const struct run *r, long step, double time, char *out, size_t len);
void run_final_state_recorded(struct run *r);

/* Path of a file inside the output directory. */
void run_path(const struct run *r, const char *name, char *out, size_t len);

/* Thermo CSV: header once, then rows (same number of values).  A row is
 * flushed as it is written; a failure to write it is remembered (the
 * remaining rows go nowhere) and returned by run_close, and by
 * run_thermo_row (ERR_RUNTIME, with r->write_err) for callers that can stop
 * at once. */
int run_thermo_header(struct run *r, const char *const *columns, int n);
int run_thermo_row(struct run *r, const double *values, int n);

/* After a frame was written to r->xyz: flush it (the same rules). */
int run_xyz_frame_done(struct run *r, struct err *e);

/* The fields every particle snapshot starts with: the cell of box b
 * (run_snapshot_cell), position (Å), velocity (Å/ps), force (eV/Å), id and
 * type of the owned particles, into the open snapshot group g; ibuf is
 * scratch for n_owned integers. */
int run_snapshot_particles(struct run *r, hid_t g, const struct particles *p,
                           const struct box *b, int64_t *ibuf, struct err *e);
/* A collective particle snapshot of fields.h5 in a brick run (h5out.h,
 * h5out_par_begin): every rank calls begin with its count of owned
 * particles, then writes the snapshot with its own particles, then end
 * with its result (returned agreed over the ranks). */
int run_h5_par_begin(struct run *r, long n_local, struct err *e);
int run_h5_par_end(struct run *r, int rc, struct err *e);

/* The box as the cell of the open snapshot g (h5out_snapshot_cell): bounds,
 * tilt 0, periodicity and boundary kinds. */
int run_snapshot_cell(struct run *r, hid_t g, const struct box *b, struct err *e);

/* A thermo table kept in memory (nrows rows of ncols values) written as
 * one series per column under /series of the HDF5 file; nothing without
 * an HDF5 file. */
int run_write_series_table(struct run *r, const double *rows, long nrows, int ncols,
                           const char *const *names, const char *const *units, struct err *e);

/* Log line (printf style) unless quiet. */
void run_log(struct run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Whether step `s` of `total` is one to act on with interval `every` (0:
 * first and last only). */
int run_due(long s, long total, long every);

#endif
