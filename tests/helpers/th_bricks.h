/*
 * th_bricks: running a case serially or under `mpirun --oversubscribe -np
 * N` and comparing what the runs wrote (the thermo series in fields.h5,
 * result.json metrics, a snapshot's datasets matched by particle id), for
 * the brick-decomposition tests of the particle engines other than MD
 * (tests/test_bricks_dpd.c, tests/test_bricks_mpm.c).
 */
#ifndef CASCADE_TH_BRICKS_H
#define CASCADE_TH_BRICKS_H

#include <hdf5.h>
#include <jansson.h>
#include <stddef.h>
#include <stdint.h>

/* The environment of a run on np ranks (0: serial, leak checks on). */
void thb_mpi_env(int np);

/* Run path serially (np 0) or on np ranks into dir, extra arguments
 * NULL-ended (may be NULL); returns the exit status, output in out. */
int thb_run(const char *path, int np, const char *dir, const char *const *extra, char *out,
            size_t len);
/* The same, failing the test on a non-zero exit. */
void thb_must_run(const char *path, int np, const char *dir, const char *const *extra);

/* A dataset of a run's fields.h5 (new buffer; *n elements). */
void *thb_read_h5(const char *dir, const char *name, hid_t type, size_t elem, long *n);

/* /series/<col> of two runs agree to rel of the column's largest
 * magnitude, for each NULL-ended column. */
void thb_compare_series(const char *a, const char *b, const char *const *cols, double rel,
                        const char *tag);
/* The same with a least scale per column: floor[c] (NULL: none), for a
 * column whose values may stay near zero while their parts are large. */
void thb_compare_series_floor(const char *a, const char *b, const char *const *cols,
                              const double *floor, double rel, const char *tag);

json_t *thb_result(const char *dir);
double thb_metric(json_t *res, const char *name);
/* The values of result.json's series `name` (an object's "values" or the
 * array itself; NULL when absent). */
json_t *thb_series_values(json_t *res, const char *name);
/* Metrics of two runs agree to tol absolutely (metrics that are zero in
 * exact arithmetic, or changes on their own scale), each NULL-ended name. */
void thb_compare_metrics_abs(const char *a, const char *b, const char *const *names,
                             double tol, const char *tag);
/* Some particle changed its rank: the per-rank counts of run `dir` (np
 * ranks) differ from those of the same case at step 0 (`dir_step0`). */
void thb_assert_ranks_changed(const char *dir, const char *dir_step0, int np);
/* Every metric of an impact's result ra in rb (more than 40 of them): null
 * in both, or to rel relative; the energy changes (energy_drift,
 * energy_deviation_max over |E|, energy_deviation_max_abs in eV,
 * energy_error_impact_fraction over the impact energy: differences of
 * nearly equal total energies) to rel of the total energy, the
 * momentum_change (round-off of the total momentum) below rel of the
 * flyer's momentum flyer_p (amu Å/ps). */
void thb_compare_impact_metrics(json_t *ra, json_t *rb, double flyer_p, double rel,
                                const char *tag);
/* Every series of result ra in rb (at least min_series of them), each to
 * rel of its largest magnitude plus 1e-12 relative, nulls in the same
 * places. */
void thb_compare_result_series(json_t *ra, json_t *rb, size_t min_series, double rel,
                               const char *tag);
/* /grid/<step>/<set> of two runs' fields.h5 node by node (the same node
 * numbering), to rel of each set's largest magnitude, for each NULL-ended
 * set; no set may be all zero. */
void thb_compare_grid(const char *a, const char *b, long step, const char *const *sets,
                      double rel, const char *tag);

/* Metrics of two runs agree to rel relative (plus 1e-12 for the printed
 * digits), for each NULL-ended name. */
void thb_compare_metrics(const char *a, const char *b, const char *const *names, double rel,
                         const char *tag);

/* group/<set> of two runs (each NULL-ended set with ncomp components)
 * agree particle by particle, matched by group/id, to rel of the set's
 * largest magnitude. */
/* The set-up snapshot (/particles/00000000) of runs a and b: the same
 * ids, positions bitwise, velocities to vrel of their largest magnitude
 * (0: bitwise), which must exceed vmin (Å/ps: the velocities were set).
 * Returns the atom count. */
long thb_compare_setup(const char *a, const char *b, double vmin, double vrel, const char *tag);

void thb_compare_snapshot(const char *a, const char *b, const char *group,
                          const char *const *sets, const int *ncomp, double rel, const char *tag);

/* The final-state files (output.final_state, extended XYZ: %.10g) of two
 * runs hold the same atoms (matched by id) and header, text fields equal
 * and numbers equal to their printed precision plus rel of the column's
 * largest magnitude. */
void thb_compare_final_xyz(const char *a, const char *b, const char *name, double rel,
                           const char *tag);

/* A snapshot group's particles in id order: (id, index in the datasets). */
struct thb_by_id {
    int64_t id;
    long i;
};
struct thb_by_id *thb_order_by_id(const char *dir, const char *group, long *n);

/* mkdir dir, then copy the file from to the file to (0, or -1). */
int thb_mkdir_copy(const char *from, const char *dir, const char *to);
/* Restart the case at path on np ranks (0: without mpirun) from the
 * checkpoint of step `step` in from_dir, in a new directory
 * TEMP/ck-restart-K whose name goes to dir; asserts that it ran. */
void thb_restart_at(const char *path, const char *from_dir, long step, int np, int k, char *dir,
                    size_t len);
/* One impossible value in a copy of checkpoint ck of step `step` (in
 * TEMP/<stem>): `val`, of HDF5 memory type `type`, at flat row `row` of
 * `dataset` (th_ckpt_poke_at).  Restarted on np ranks the run must stop
 * with exit 2 and the failing rank's own message (not "another MPI
 * rank"), naming the checkpoint file and containing `want`.  The output
 * is left in out for the caller's further checks. */
void thb_restart_refuses(const char *path, const char *ck, long step, const char *stem, int np,
                         const char *dataset, long type, long row, const void *val,
                         const char *want, char *out, size_t len);
/* One restart of the checkpoint tests: from the run in `from`, on np ranks
 * (0: without mpirun); when bitwise_with is given, the restarted run's
 * thermo.csv must be that run's text after the header (the same rank
 * count: the same arithmetic). */
struct thb_restart {
    const char *from;
    int np;
    const char *tag;
    const char *bitwise_with;
};
/* What a suite checks of a restarted run in dir against the reference. */
typedef void (*thb_check_fn)(const char *ref, const char *dir, const char *tag);
/* Each of the n restarts of the case at path from the checkpoint of step
 * `step` (thb_restart_at, in TEMP/ck-restart-K), checked against ref. */
void thb_restarts_match(const char *path, long step, const struct thb_restart *r, int n,
                        const char *ref, thb_check_fn check);

/* Run path serially into TEMP/<stem>-serial, checked by `measured` (may be
 * NULL), then with the same case file on each of the nnp rank counts
 * nps[] into TEMP/<stem>-<np>: each checked against the serial run by
 * `compare` (tag "<what> on <np> ranks") and its parallel record over n
 * particles. */
void thb_matches_serial(const char *path, const char *stem, const int *nps, int nnp, long n,
                        void (*measured)(const char *dir), thb_check_fn compare,
                        const char *what);

/* Run path on np ranks into dir with no `parallel` section of its own:
 * it must run on bricks (result.json's parallel.decomposition) without the
 * note that the case type is not decomposed. */
void thb_must_run_auto_bricks(const char *path, int np, const char *dir);

/* The checkpoint test of a decomposed case at path (output.checkpoint_every
 * 50, no `parallel` section): run serially into TEMP/<stem>-ck-serial and
 * on 2 ranks (thb_must_run_auto_bricks) into TEMP/<stem>-ck-2, compare
 * them, then restart the 2-rank checkpoint of step 50 serially, on 4 and
 * on 2 ranks: each restarted from step 50 and checked against the serial
 * run by `compare`, the 2-rank restart's thermo bitwise the 2-rank run's. */
void thb_checkpoint_moves(const char *path, const char *stem, thb_check_fn compare,
                          const char *what);

/* dir/name as text into buf (at most len - 1 bytes; asserts it opens). */
void thb_read_text(const char *dir, const char *name, char *buf, size_t len);

/* A case too short for np bricks, run serially and on np ranks under
 * `auto`: the np-rank run says so (the planner's note) and runs replicated,
 * its thermo.csv the serial one below the header, bitwise. */
void thb_short_replicates(const char *path, int np, const char *stem);

/* result.json's parallel record: np ranks whose counts add up to n, the
 * imbalance their max over mean, a grid of np bricks. */
void thb_check_parallel_record(const char *dir, int np, long n);

/* A hierarchical grid whole on np ranks (run dir's parallel record): no
 * rank made the node tables of `most` times the grid's cells or more (a
 * rank makes those of its particles' cells, solver/mpm/mpm_hgrid.h; an
 * empty brick none), some rank made some; returns the largest fraction. */
double thb_check_cell_tables(const char *dir, int np, double most);

/* The dynamic balance's part of run dir's parallel record
 * (parallel.balance_every): checks, shifts and the worst max/mean a check
 * found (each may be NULL); returns the run's final max/mean.  The
 * record must be there. */
double thb_balance_record(const char *dir, long *checks, long *shifts, double *worst);

/* A run in dir went on bricks: result.json's parallel.decomposition is
 * "bricks" on np ranks, and, when grid is not NULL, its brick grid is
 * grid[0] x grid[1] x grid[2]. */
void thb_assert_bricks(const char *dir, int np, const int *grid);

#endif
