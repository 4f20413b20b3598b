/*
 * wave_arrival: when a wave reaches a point, and its speed between two.
 *
 * Arrival criterion (Chen 2014 Sec. 4.1.1, "the time at which particles ...
 * first undergo significant displacements"): the first time the sampled
 * signal s(t) -- the mean displacement of a reference region along the
 * propagation direction -- reaches `threshold` (s >= threshold for a
 * positive threshold, s <= threshold for a negative one), with linear
 * interpolation between the two samples that bracket the crossing.  The
 * speed is the regions' separation over the difference of their arrival
 * times, which cancels the (equal) rise time of the front at both.
 */
#ifndef CASCADE_WAVE_ARRIVAL_H
#define CASCADE_WAVE_ARRIVAL_H

/* Arrival time (units of t), or NAN when the signal never reaches it. */
double wave_arrival_time(const double *t, const double *s, long n, double threshold);

/* distance / (t2 - t1); NAN unless both are finite and t2 > t1. */
double wave_speed(double distance, double t1, double t2);

#endif
