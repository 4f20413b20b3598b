/*
 * wave_front: a wave speed that does not depend on a chosen absolute
 * threshold.
 *
 * The signal is sampled at many probe positions x_k along the propagation
 * direction (typically the mean particle velocity along the axis in thin
 * Lagrangian slabs, flyer run minus a reference run, so that it is zero
 * ahead of the wave).  At each probe the front arrives when the signal
 * first reaches a fraction f of its own (local) peak -- a level that
 * scales with the wave where it is, so a pulse that weakens or spreads on
 * its way is measured at the same point of its shape everywhere, which a
 * fixed threshold is not.  The crossing is placed by linear interpolation
 * between the two samples that bracket it.
 *
 * The local peak is that of the leading pulse: the first sample that is
 * the largest within +-halfwidth of it and above WAVE_FRONT_PEAK_FLOOR (1 %)
 * of the largest value of the window (a monotone rise, with no such
 * sample, uses the largest value).  Why the first and not the largest: a
 * flyer impact sends a train of pulses, and the leading one weakens on its
 * way (in the quick DPD bar from 0.6 to 0.05 Å/ps over 36 Å) while a later
 * one does not, so the largest value belongs to different pulses at
 * different probes and the fit would mix them.  The floor only rejects
 * round-off: the impact signals are differences to a reference run, zero
 * to 1e-6 ahead of the wave.  The window is the samples before a
 * caller-given time per probe (before the first reflection from a far
 * surface can arrive).
 *
 * The speed is the least-squares slope of x_k against the arrival times
 * t_k over all probes that were reached (GSL gsl_fit_linear), with its
 * standard error from the residuals (needs at least 3 probes).
 *
 * The criterion set: f = 0.1, 0.2, 0.5, 0.8 and 0.9 (wave_front_fractions).
 * The reported speed is the fit at f = 0.5, the middle of the rise (the
 * point of a dispersing step front that travels at the long-wavelength
 * speed).  A rise that broadens on its way (a weak linear wave in a
 * discrete medium does: its short wavelengths lag) makes f = 0.1 run ahead
 * of f = 0.5 and f = 0.9 behind it by the same amount, so the spread over
 * f = 0.1/0.2/0.5 of earlier versions measured the broadening as much as
 * any dependence of the travel on the criterion.  Travel and broadening
 * are therefore separated: arrival(f, x) = x / c + t0(f) + b(f) x, and
 *
 *   - the spread is taken over the rise's centres: f = 0.5 and the
 *     midpoints of the symmetric pairs (0.2, 0.8) and (0.1, 0.9), whose b
 *     cancel for a symmetric broadening; (max - min) / speed of their three
 *     fits says how much the speed still depends on the criterion (the
 *     shape of the rise changing on its way, e.g. a precursor growing
 *     ahead of the main front), and a speed whose spread exceeds
 *     WAVE_FRONT_SPREAD_MAX (3 %) is flagged rather than reported;
 *   - the broadening b(0.9) - b(0.1), the growth of the 10-90 % rise time
 *     per unit distance (ps/Å, with its standard error), and the mean rise
 *     time are numbers of their own;
 *   - the rise centroid (the mean over all f in (0, 1) of the crossing
 *     times: no fraction chosen) is fitted beside them;
 *   - the pulse centroid (the signal-weighted mean time of the leading
 *     pulse, from the window's start until the signal returns to zero)
 *     gives a threshold-free speed of the pulse's energy: in a bar with
 *     free lateral surfaces its long wavelengths travel at the bar speed
 *     sqrt(E/rho), not at the longitudinal sqrt(C11/rho) of the front's
 *     first arrival (Pochhammer).
 *
 * Why 3 %: the standard error of a front fit over the probes of the quick
 * bars is 0.1-1 % of the speed (docs/dpd_mpm.md), so a spread of 3 % is
 * well beyond the fits' scatter; below it the criterion no longer moves
 * the result by more than the accuracy that the comparisons with the
 * papers need.
 */
#ifndef CASCADE_WAVE_FRONT_H
#define CASCADE_WAVE_FRONT_H

#define WAVE_FRONT_NFRAC 5
#define WAVE_FRONT_PRIMARY 2          /* index of f = 0.5 in wave_front_fractions */
#define WAVE_FRONT_NCENTRE 3          /* f = 0.5, mid(0.2, 0.8), mid(0.1, 0.9) */
#define WAVE_FRONT_SPREAD_MAX 0.03
#define WAVE_FRONT_PEAK_FLOOR 0.01

extern const double wave_front_fractions[WAVE_FRONT_NFRAC];

/* Flags of a wave-speed measurement (metric wave_speed_flag). */
enum wave_front_flag {
    WAVE_FRONT_OK = 0,          /* spread <= 3 %: wave_speed is a result */
    WAVE_FRONT_SPREAD = 1,      /* spread > 3 %: not a result (wave_speed null) */
    WAVE_FRONT_NO_FIT = 2       /* fewer than 3 probes reached at some fraction */
};

/* The first time the signal s (n samples at times t; sample j at
 * s[j * stride]) reaches f times the peak of its leading pulse (above;
 * halfwidth <= 0: the largest value) among the samples with t <= tmax;
 * NAN when there is no positive peak.  *peak (may be NULL) gets the peak. */
double wave_front_crossing(const double *t, const double *s, long n, long stride, double f,
                           double tmax, double halfwidth, double *peak);

struct wave_front_fit {
    double speed;      /* slope dx/dt (units of x over units of t) */
    double stderr_;    /* its standard error */
    double intercept;  /* x at t = 0 */
    int nprobes;       /* probes reached and fitted */
};

/* Fit over np probes at positions x[k]: sig[j * np + k] is probe k's
 * signal at t[j] (nt samples); tmax[k] the peak window of probe k (NULL:
 * every sample).  Returns 0, or -1 (fit->speed NAN) when fewer than 3
 * probes are reached or the times do not spread. */
int wave_front_fit(const double *t, long nt, const double *sig, int np, const double *x,
                   const double *tmax, double halfwidth, double f, struct wave_front_fit *fit);

/* The same fit from given per-probe times (NAN: probe not reached). */
int wave_front_fit_times(const double *times, int np, const double *x, struct wave_front_fit *fit);

/* Threshold-free times of the leading pulse of s (as wave_front_crossing):
 * pulse = 0: the rise centroid, the mean over f in (0, 1) of the first
 * crossing of f times the peak; pulse = 1: the signal-weighted mean time
 * from the window's start until the signal falls to zero after the peak.
 * NAN without a positive peak. */
double wave_front_centroid(const double *t, const double *s, long n, long stride, double tmax,
                           double halfwidth, int pulse);

/* The whole measurement: fits at every fraction and at the rise's
 * centres, the primary speed, the spread, the broadening and the flag. */
struct wave_front_result {
    struct wave_front_fit fit[WAVE_FRONT_NFRAC];
    struct wave_front_fit centre[WAVE_FRONT_NCENTRE];   /* f = 0.5, mid(0.2, 0.8),
                                                           mid(0.1, 0.9) */
    struct wave_front_fit rise_centroid, pulse_centroid;
    double speed;      /* fit at the primary fraction, NAN when flagged */
    double speed_fit;  /* the same whether flagged or not */
    double stderr_;
    double spread;     /* (max - min) / speed_fit over the centres; NAN without fits */
    double broadening, broadening_stderr;   /* ps/Å: d(t_0.9 - t_0.1)/dx */
    double rise_time;  /* ps: t_0.9 - t_0.1 at the probes' mean position */
    int flag;          /* enum wave_front_flag */
};

void wave_front_measure(const double *t, long nt, const double *sig, int np, const double *x,
                        const double *tmax, double halfwidth, struct wave_front_result *r);

/* Two-region arrival with relative thresholds: each region's signal (s1,
 * s2, n samples, peaks before tmax1 / tmax2) crosses f of its own peak;
 * distance / (t2 - t1), NAN if either is not reached.  *t1, *t2 may be
 * NULL. */
double wave_front_arrival_speed(const double *t, long n, const double *s1, double tmax1,
                                const double *s2, double tmax2, double halfwidth, double distance,
                                double f, double *t1, double *t2);

#endif
