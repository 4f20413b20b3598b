/*
 * md_output: thermo rows, HDF5 snapshots and XYZ frames of an MD run, on
 * the schedule of the case's `output` section.
 *
 * Thermo columns (thermo.csv and /series in fields.h5):
 *   step, time_ps, pe_eV, ke_eV, etotal_eV, temp_K, press_GPa,
 *   pxx_GPa, pyy_GPa, pzz_GPa, pxy_GPa, pxz_GPa, pyz_GPa
 */
#ifndef CASCADE_MD_OUTPUT_H
#define CASCADE_MD_OUTPUT_H

#include "md/md.h"
#include "output/run.h"

#define MD_THERMO_COLS 13

struct md_output {
    double *series;   /* MD_THERMO_COLS per row */
    long nrows, cap;
    double *stress;   /* scratch: 6 per atom */
    int64_t *ibuf;    /* scratch: ids / types */
    long cap_atoms;
    int xyz_field;    /* per-particle field written as an extra XYZ column (-1: none) */
    int *xyz_buf;
    struct err err;   /* why the last md_output_step / md_output_snapshot failed */
};

int md_output_begin(struct md_output *o, struct run *run, struct md *md, struct err *e);
/* A restarted run: the thermo rows written before its checkpoint (nrows x
 * MD_THERMO_COLS) go back into the series and thermo.csv. */
int md_output_resume(struct md_output *o, struct run *run, const double *rows, long nrows,
                     struct err *e);
/* Act on md->step if due (thermo, snapshot, xyz). */
int md_output_step(struct md_output *o, struct run *run, struct md *md, long total_steps);
/* Force a snapshot now (for example at the end of a diverged run). */
int md_output_snapshot(struct md_output *o, struct run *run, struct md *md);
/* Bricks (md->halo): the grid, the atoms of every rank, the load
 * imbalance (max / mean) and every rank's peak resident memory under
 * "parallel" in result.json; collective. */
void md_output_decomposition(struct run *run, const struct md *md);
/* Write the thermo series to the HDF5 file and free. */
int md_output_end(struct md_output *o, struct run *run, struct err *e);

#endif
