/*
 * dpd_output: thermo rows, HDF5 snapshots and XYZ frames of a DPD run, on
 * the schedule of the case's `output` section.
 *
 * Thermo columns (thermo.csv and /series in fields.h5):
 *   step, time_ps, pe_eV, ke_eV, uint_eV (DPDE internal energy), etotal_eV
 *   (pe + ke + uint), temp_K (free particles), press_GPa (virial pressure
 *   in the box volume; meaningful for periodic boxes)
 * Snapshots: position, velocity, force (conservative), id, type, pe when
 * per-particle energies are on, and every per-particle field (u_internal
 * in eV, x_ref in Å, ...).
 */
#ifndef CASCADE_DPD_OUTPUT_H
#define CASCADE_DPD_OUTPUT_H

#include "dpd/dpd.h"
#include "output/checkpoint.h"
#include "output/run.h"

#define DPD_THERMO_COLS 8

struct dpd_output {
    double *series;   /* DPD_THERMO_COLS per row */
    long nrows, cap;
    int64_t *ibuf;
    long cap_atoms;
};

int dpd_output_begin(struct dpd_output *o, struct run *run, struct err *e);
/* A restarted run: the thermo rows of the steps before the checkpoint
 * (nrows rows of DPD_THERMO_COLS, as o->series held them) back into the
 * series and thermo.csv.  Call after dpd_output_begin. */
int dpd_output_resume(struct dpd_output *o, struct run *run, const double *rows, long nrows,
                      struct err *e);
/* Checkpoint the thermo rows so far (group entered by the caller) / read
 * them back into a new buffer *rows (owned by the caller) of *nrows rows. */
int dpd_output_checkpoint_write(const struct dpd_output *o, struct ckpt *ck);
int dpd_output_checkpoint_read(struct ckpt *ck, double **rows, long *nrows, struct err *e);
/* Act on d->step if due (thermo, snapshot, xyz). */
int dpd_output_step(struct dpd_output *o, struct run *run, struct dpd *d, long total_steps);
int dpd_output_snapshot(struct dpd_output *o, struct run *run, struct dpd *d);
/* Write the thermo series to the HDF5 file and free. */
int dpd_output_end(struct dpd_output *o, struct run *run, struct err *e);

/* Total energy pe + ke + internal (eV). */
double dpd_total_energy(const struct dpd *d);

#endif
