/*
 * mpm_case: the material point method case type (`type: mpm`), shared by
 * its reader (mpm_case_read.c), its run (mpm_case.c) and its output
 * (mpm_output.c).  The case file schema is in docs/mpm.md and at the top of
 * mpm_case_read.c.
 */
#ifndef CASCADE_MPM_CASE_H
#define CASCADE_MPM_CASE_H

#include "core/region.h"
#include "engine/models.h"
#include "mpm/mpm.h"
#include "mpm/mpm_units.h"
#include "scenarios/case_type.h"

#define MPM_CASE_MAX_REPORT 32
#define MPM_CASE_MAX_PROBES 16

/* Mean fields of the points that started inside a region. */
struct mpm_probe {
    char name[32];
    struct region region;   /* Å */
};

/* Output: thermo rows and HDF5 snapshots (points and grid). */
#define MPM_OUTPUT_MAX_COLS (11 + 3 * MPM_MAX_BODIES + 4 * MPM_CASE_MAX_PROBES)
struct mpm_output {
    char col_name[MPM_OUTPUT_MAX_COLS][48];    /* series name          */
    char col_unit[MPM_OUTPUT_MAX_COLS][16];    /* its unit             */
    char col_head[MPM_OUTPUT_MAX_COLS][64];    /* thermo.csv: name_unit */
    double *buf;           /* scratch for unit conversion */
    long cap;
    int64_t *ibuf;
    long icap;
    double *series;        /* thermo rows kept for /series */
    long nrows, rcap;
    int ncols;
};

struct mpm_case {
    struct mpm m;
    struct mpm_units u;
    long steps;
    double dt_fixed;        /* ps; 0: from the CFL condition */
    double cfl;             /* safety factor on the explicit limit */
    int adaptive;           /* recompute the CFL step every step */
    double load_ramp;       /* ps: tractions reach full value after this (0: step) */
    int nreport;
    long report_steps[MPM_CASE_MAX_REPORT];
    int nprobes;
    struct mpm_probe probe[MPM_CASE_MAX_PROBES];
    int output_grid;        /* grid fields in the snapshots */
    double energy_tolerance;   /* relative total-energy change counted as divergence */

    /* bricks (mpm/mpm_bricks.h; owned), or NULL: serial or replicated */
    struct mpm_bricks *bricks;
    long npoints_total;     /* material points of all ranks */

    /* the run on the engine (mpm_case.c) */
    struct mpm_model model;
    struct mpm_output out;
    /* accumulators of the run (checkpointed) */
    struct mpm_totals t0;   /* the state at step 0 */
    double dt_first, dt_min, dt_max;
    double de_max, dec_max; /* largest relative change of the total and centred energy */
    double ke_report[MPM_CASE_MAX_REPORT];
    long acc_step;          /* the last step accumulated */
    double *restored_rows;  /* thermo rows read from a checkpoint */
    long nrestored, restored_cols;
};

/* Read the `mpm` section; when not shallow, build the model into *out. */
int mpm_case_read(struct cfg_obj *root, const struct case_common *common, struct mpm_case **out);
void mpm_case_free(struct mpm_case *c);

int mpm_output_begin(struct mpm_output *o, struct run *run, struct mpm_case *c, struct err *e);
int mpm_output_thermo(struct mpm_output *o, struct run *run, struct mpm_case *c, double dt,
                      const struct mpm_totals *t, struct err *e);
int mpm_output_snapshot(struct mpm_output *o, struct run *run, struct mpm_case *c, struct err *e);
/* A restarted run: the thermo rows written before its checkpoint (nrows x
 * ncols, ncols as mpm_output_begin set them) go back into the series and
 * thermo.csv. */
int mpm_output_resume(struct mpm_output *o, struct run *run, const double *rows, long nrows,
                      long ncols, struct err *e);
int mpm_output_end(struct mpm_output *o, struct run *run, struct err *e);

/* Mean stress (6, eV/Å^3) and displacement (3, Å) of the points of probe k. */
long mpm_probe_means(const struct mpm_case *c, int k, double stress[6], double disp[3]);

#endif
