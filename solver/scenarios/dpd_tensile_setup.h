/*
 * dpd_tensile_setup: the tensile rod of Chen et al. 2014, Sec. 4.1.2, as
 * the DPD-only (dpd_tensile) and DPD/MPM-grid (dpd_grid_tensile) case types
 * share it: the `tensile` section, the rod with its rigid grips, and the
 * stress-strain curve sampled from the grips' forces (both case types run
 * on the engine and call the curve from their hooks).
 *
 *   tensile:
 *     axis: x                   the rod axis
 *     grip_length: 15.0         Å of material at each end held rigid
 *     velocity: 2.169           Å/ps of each end, outward
 *     lattice_constant: 0       Å for the plane spacing a/2 that sets the rod's length
 *                               and cross-section (0: the parameter file's)
 *     area: 0                   Å^2 cross-section (0: measured, (extent + a/2)^2 per axis)
 *     velocity_ramp: true       start the rod at the homogeneous strain rate: every
 *                               free particle gets v (2 x - x_lo - x_hi) / (x_hi - x_lo)
 *                               along the axis on top of its thermal velocity
 *     sample_every: 20          steps per stress-strain point (forces averaged over them)
 *
 * Strain: engineering, 2 v t / L0 with L0 the rod's length (faces + a/2).
 * Stress: (F_left - F_right) / (2 A) along the axis, F the total force of
 * the rest of the rod on each grip (conservative + dissipative + random),
 * tension positive.
 *
 * Metrics: peak_stress (GPa), strain_at_peak (1), strain_rate (1/ps),
 * strain_final (1), rod_length (Å), area (Å^2), particles, grip_particles,
 * temperature (K).  Series: strain, stress (GPa), time_ps.
 */
#ifndef CASCADE_DPD_TENSILE_SETUP_H
#define CASCADE_DPD_TENSILE_SETUP_H

#include "dpd/dpd.h"
#include "output/checkpoint.h"
#include "output/run.h"
#include "scenarios/case_type.h"
#include "scenarios/dpd_bar.h"

#define DPD_GRIP_LO_BIT (1u << 2)
#define DPD_GRIP_HI_BIT (1u << 3)

struct dpd_tensile {
    int axis, ramp;
    double grip, v, a, area_key;
    long sample_every, steps;
    double L0, area;        /* Å, Å^2 */
    long ngrip;
    struct dpd_bar bar;
};

/* Read system, dpd and tensile; unless shallow build the DPD model over d
 * with the grips as prescribed bodies 0 (low end) and 1 (high end).  On
 * failure after building, d is freed.  halo (NULL: never): under mpirun
 * the rod on bricks when the `parallel` section and the box give them
 * (*halo the new halo, owned by the caller, or NULL); each rank builds
 * (or receives) only its brick's part of the rod.  sweep: the DPD step
 * sweeps pairs (dpd_tensile; not the grid-carried rod), so the ghost
 * shell covers the cell sweep's reach and the bricks are planned on the
 * box; without the sweep they are planned on the rod's extent less the
 * skin (dpd_split_plan.grid_carried). */
int dpd_tensile_read(struct cfg_obj *root, const struct case_common *common, struct dpd *d,
                     struct dpd_tensile *t, struct halo **halo, int sweep);

/* The stress-strain curve as the run samples it: the pieces a case type
 * on the engine calls from its hooks (dpd_tensile_case.c), checkpointed. */
struct dpd_tensile_curve {
    double *strain, *stress, *times;   /* 1, GPa, ps per point */
    long n, cap;
    double fsum, tsum;                 /* grip force (eV/Å) and time (ps) summed over
                                        * the steps of the point being sampled */
    long nacc;                         /* steps summed */
};

int dpd_tensile_curve_init(struct dpd_tensile_curve *cv, const struct dpd_tensile *t,
                           struct err *e);
/* After a step: the grips' forces into the current point, which is closed
 * every sample_every steps and at the last step (`last`). */
void dpd_tensile_curve_add(struct dpd_tensile_curve *cv, const struct dpd_tensile *t,
                           const struct dpd *d, int last);
/* Metrics and series into run->result (and the peak into the log). */
void dpd_tensile_curve_report(const struct dpd_tensile_curve *cv, const struct dpd_tensile *t,
                              const struct dpd *d, struct run *run);
/* Into / from the group the caller entered. */
int dpd_tensile_curve_checkpoint_write(const struct dpd_tensile_curve *cv, struct ckpt *ck);
int dpd_tensile_curve_checkpoint_read(struct dpd_tensile_curve *cv, struct ckpt *ck,
                                      struct err *e);
void dpd_tensile_curve_free(struct dpd_tensile_curve *cv);


#endif
