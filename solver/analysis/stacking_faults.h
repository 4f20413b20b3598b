/*
 * stacking_faults: when the stacking faults of an impact appear.  Guo &
 * Yang 2005 (section 3.3, Figs. 14-15) see stacking faults (hcp atoms in
 * the CNA) only late in an impact, and for the 1052-atom cluster a "burst"
 * of them; this puts a time on it from the hcp-atom count n(t) of the
 * analysis series.
 *
 * Criterion.  Let n_max be the largest count of the series, first reached
 * at t_peak.  When n_max >= min_atoms, the burst time is the first time
 * the count reaches n_max / 2, linearly interpolated between the two
 * analyses around the crossing; the rise time is the time from the first
 * crossing of 0.1 n_max to the first crossing of 0.9 n_max (how sudden the
 * jump is: a burst rises in a fraction of its burst time, a slow growth
 * takes about as long as the burst time itself).  A sigmoidal jump
 * n(t) = n_max / (1 + exp(-(t - t0)/w)) gives t0 and 4.39 w.  With
 * n_max < min_atoms (a handful of hcp atoms come and go as the shock
 * passes) there is no burst: times are NaN.
 */
#ifndef CASCADE_STACKING_FAULTS_H
#define CASCADE_STACKING_FAULTS_H

/* below this many hcp atoms at the peak there is no burst */
#define STACKING_FAULTS_MIN_ATOMS 50.0

struct sf_burst {
    double peak;        /* n_max (atoms) */
    double peak_time;   /* first time of n_max (ps) */
    double burst_time;  /* first crossing of n_max / 2 (ps); NaN: no burst */
    double rise_time;   /* first crossing of 0.9 n_max minus that of 0.1 n_max (ps); NaN: no burst */
};

/* t[k], n[k] for k < m analyses, t increasing; stride: the distance between
 * consecutive values in both arrays (1 for plain arrays, the column count
 * for rows of a table). */
void stacking_faults_burst(const double *t, const double *n, long m, long stride,
                           double min_atoms, struct sf_burst *out);

#endif
