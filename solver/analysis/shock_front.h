/*
 * shock_front: where a plane shock is, from particle data.
 *
 * A profile is the mean of a per-particle quantity (usually the particle
 * velocity along the shock direction) in slabs of width w along the shock
 * direction.  The front is found by scanning the profile from the
 * undisturbed side -- from the far end in the direction the shock travels
 * -- for the first slab whose mean reaches `level`; the crossing is placed
 * by linear interpolation between that slab's centre and the previous
 * one.  With level = half the particle velocity behind the shock this is
 * the middle of the front, insensitive to the front's width, to thermal
 * noise well below the jump and to what happens further behind (release
 * waves, the piston).  An elastic precursor weaker than `level` is passed
 * over; a lower level finds the leading edge instead.
 *
 * The shock speed is the slope of a least-squares line through the front
 * positions over time (GSL gsl_fit_linear), with its standard error.
 */
#ifndef CASCADE_SHOCK_FRONT_H
#define CASCADE_SHOCK_FRONT_H

#include "util/err.h"

/* mean[k], count[k] over slabs [lo + k w, lo + (k+1) w), k < nbins, of the
 * coordinate s[i] (stride `stride`, e.g. 3 with s = x + axis) of n
 * particles; val likewise (stride vstride). */
void shock_profile(const double *s, int stride, const double *val, int vstride, int n, double lo,
                   double w, int nbins, double *mean, long *count);

/* The front position (Å) for a shock travelling towards +s (dir = +1) or
 * -s (dir = -1).  Slabs with fewer than min_count particles are skipped.
 * Returns 0, or -1 when no slab reaches the level. */
int shock_front_locate(const double *mean, const long *count, int nbins, double lo, double w,
                       double level, int dir, long min_count, double *pos);

/* Least-squares slope of x(t) and its standard error; n >= 3. */
int shock_speed_fit(const double *t, const double *x, int n, double *speed, double *speed_err,
                    double *intercept, struct err *e);

#endif
