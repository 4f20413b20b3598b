/*
 * impact_front: the samples and the report of the threshold-free wave
 * speed of the flyer/target impacts (DPD-only, DPD/MPM grid, concurrent
 * DPD/MPM; analysis/wave_front.h).
 *
 * Probes: Lagrangian slabs one (100) plane spacing thick from the first
 * reference region's centre to the second's (every slab whose material
 * started there).  Each sample holds, per probe, the mean particle velocity
 * along the impact axis in the flyer run minus that in the reference run
 * (zero ahead of the wave: the same random numbers), over two sets of
 * material:
 *
 *   core     the particles whose start position lies in the central half of
 *            the bar's cross-section (at least a quarter of the width from
 *            each free lateral surface): the longitudinal front, before the
 *            release from the free surfaces reaches the axis;
 *   section  the whole cross-section: what a bar-mean measurement sees.
 *
 * and per reference region the section-mean velocity difference (for the
 * two-region arrival at a fraction of each region's peak).
 *
 * Report (metrics, all m/s unless said):
 *   wave_speed            core front fit at f = 0.5 of the leading pulse's peak
 *                         (analysis/wave_front.h, peak half-width 0.1 ps); null
 *                         when the spread over the rise's centres (f = 0.5,
 *                         mid(0.2, 0.8), mid(0.1, 0.9)) exceeds 3 %
 *   wave_speed_fit        the same value whether flagged or not
 *   wave_speed_stderr     its standard error
 *   wave_speed_spread     (max - min) / wave_speed_fit over those centres (1)
 *   wave_speed_flag       0 ok, 1 spread > 3 % (not a result), 2 no fit (1)
 *   wave_speed_probes     probes fitted at f = 0.5 (1)
 *   wave_speed_section    the section-mean front fit at f = 0.5
 *   wave_speed_section_spread  its spread (1)
 *   wave_speed_rise_centroid   core fit of the rise centroids (the mean over all f)
 *   wave_front_broadening(_stderr)  growth of the core's 10-90 % rise time (ps/Å)
 *   wave_front_rise_time  that rise time at the probes' mean position (ps)
 *   wave_speed_pulse_centroid(_stderr)  section-mean fit of the leading pulse's
 *                         centroid: the pulse's long wavelengths, which travel at
 *                         the bar speed where the lateral surfaces are free
 *   wave_speed_pulse_centroid_core  the same for the core
 *   wave_speed_peak       fit of the times of the leading peaks (core)
 *   wave_speed_arrival    two regions, each at f = 0.5 of its own peak
 *   arrival_front_1/2     those arrival times (ps)
 *   longitudinal_speed    sqrt(C11 / rho) of the material
 *   bar_speed             sqrt(E100 / rho), E100 = (C11 - C12)(C11 + 2 C12) / (C11 + C12)
 * and series front_fractions, wave_speed_fractions (core fits per f),
 * wave_speed_fractions_stderr, wave_speed_section_fractions, front_probe_x
 * (Å from the face) with f = 0.1/0.2/0.5/0.8/0.9.  Each probe's peak is taken before the first
 * reflection from the far end can reach it: t <= (2 L - x) / (1.15 c_L)
 * (15 % above sqrt(C11/rho) for the nonlinear speed-up of a strong front).
 */
#ifndef CASCADE_IMPACT_FRONT_H
#define CASCADE_IMPACT_FRONT_H

#include <stdint.h>

#include "output/checkpoint.h"
#include "output/result.h"
#include "util/err.h"

struct impact_front {
    int axis, np;
    double face;              /* Å: absolute coordinate of the impact face */
    double x_first, w;        /* Å from the face: first probe's lower edge, width */
    double core_lo[3], core_hi[3];   /* absolute, lateral axes only */
    double reg_lo[2], reg_hi[2];     /* Å from the face */
    double length;            /* Å: the bar's length along the axis */
    long cap, n;
    double *t;                /* cap */
    double *core, *sect;      /* cap x np: velocity signals */
    double *reg;              /* cap x 2 */
    /* per-sample accumulators: [run][slot], slots: core np, section np, regions 2 */
    double *sum;
    long *cnt;
};

/* Probes between region centres r1 < r2 (Å from the face, slabs of
 * thickness w); regions r +- half; the bar's lateral extent from lo[] to
 * lo[] + extent[] (absolute); cap samples. */
int impact_front_init(struct impact_front *f, int axis, double face, double length,
                      const double regions[2], double half, double w, const double lo[3],
                      const double extent[3], long cap, struct err *e);
void impact_front_free(struct impact_front *f);

/* A sample: clear, add the material of run 0 (flyer) and run 1 (reference),
 * then end.  x0: start positions, v: velocities (3 per item); items with a
 * bit of `exclude` in mask (mask may be NULL) are skipped. */
void impact_front_clear(struct impact_front *f);
void impact_front_add(struct impact_front *f, int run, const double *x0, const double *v,
                      const uint32_t *mask, uint32_t exclude, long n);
void impact_front_end(struct impact_front *f, double t, int has_ref);
/* On bricks, between the adds and the end: each rank added its own
 * particles; the probes' sums and counts become sums over the ranks. */
struct halo;
void impact_front_sum_ranks(struct impact_front *f, const struct halo *h);

/* Metrics and series into res; c11, c12 (eV/Å^3) and rho (amu/Å^3) of the
 * material for the reference speeds and the peak window.  *speed (may be
 * NULL) gets wave_speed in Å/ps (NAN when flagged). */
void impact_front_report(const struct impact_front *f, struct result *res, double c11, double c12,
                         double rho, double *speed);

int impact_front_checkpoint_write(const struct impact_front *f, struct ckpt *ck);
int impact_front_checkpoint_read(struct impact_front *f, struct ckpt *ck, struct err *e);

#endif
