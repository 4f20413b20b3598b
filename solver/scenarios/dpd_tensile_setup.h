/*
 * dpd_tensile_setup: the tensile rod of Chen et al. 2014, Sec. 4.1.2, as
 * the DPD-only (dpd_tensile) and DPD/MPM-grid (dpd_grid_tensile) case types
 * share it: the `tensile` section, the rod with its rigid grips, and the
 * run that turns the grips' forces into the stress-strain curve.
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
 * failure after building, d is freed. */
int dpd_tensile_read(struct cfg_obj *root, const struct case_common *common, struct dpd *d,
                     struct dpd_tensile *t);

/* Run t->steps steps of `step` (which advances d by one step), sampling
 * the grips' forces into the stress-strain curve; metrics and series into
 * run->result, thermo and snapshots on the output schedule, the final
 * state when asked. */
int dpd_tensile_run(struct dpd *d, const struct dpd_tensile *t,
                    int (*step)(void *ctx, struct err *e), void *ctx, struct run *run,
                    struct err *e);

#endif
