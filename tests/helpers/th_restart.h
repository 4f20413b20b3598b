/*
 * th_restart: helpers of the checkpoint/restart tests -- run the solver
 * (killed at an exact step through CASCADE_SOLVER_KILL_AT_STEP, or
 * restarted), and compare a restarted run with the uninterrupted one
 * bitwise: every metric of result.json, thermo.csv rows, and datasets of
 * the last HDF5 snapshot.  Outputs go to th_temp_dir()/<out_name>.
 */
#ifndef CASCADE_TEST_TH_RESTART_H
#define CASCADE_TEST_TH_RESTART_H

#include <stddef.h>
#include <stdint.h>

/* cascade-solver run case_path --out <tmp>/out_name --threads 1; kill_at:
 * step to SIGKILL at (NULL: none); restart: NULL none, "" --restart alone,
 * else --restart PATH.  Returns the exit status (128 + signal). */
int th_restart_solve(const char *out_name, const char *case_path, const char *kill_at,
                     const char *restart, char *msg, size_t len);

/* Overwrite the first element of `dataset` of a checkpoint file through
 * HDF5 (the checksum is recomputed: the file is valid, its value is not). */
void th_ckpt_poke(const char *file, const char *dataset, long memtype, const void *value);
/* The same at row `row` of a one-dimensional dataset. */
void th_ckpt_poke_at(const char *file, const char *dataset, long memtype, long row,
                     const void *value);

/* The positions (3 a row) and ids of a checkpoint's particle group
 * ("/model/dpd/particles"), malloc'ed; returns the row count. */
long th_ckpt_positions_ids(const char *file, const char *group, double **x, int64_t **ids);

/* Whole file into a new buffer (*len its size, may be NULL). */
char *th_restart_slurp(const char *path, long *len);

/* The listed datasets of the last snapshot of /collection in the runs'
 * fields.h5 files (th_temp_dir()/a and /b) are bitwise equal. */
void th_restart_assert_same_snapshot(const char *a, const char *b, const char *collection,
                                     const char *const *datasets);

/* Run `yaml` uninterrupted (out "full"); then for each step of kill_steps
 * (NULL-ended) run it killed at that step and restarted (out
 * "killed-STEP"), and assert: exit 137 then 0, restarted_from_step in
 * result.json, every metric bitwise equal, thermo.csv rows equal (when
 * thermo_csv), and the listed datasets of the last snapshot of
 * /`collection` in fields.h5 bitwise equal (collection NULL: no check). */
void th_kill_and_restart(const char *yaml, const char *const *kill_steps, int thermo_csv,
                         const char *collection, const char *const *datasets);

#endif
